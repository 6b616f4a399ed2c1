// Small builders the per-paper claim files (claims_000.cpp .. claims_004.cpp) share: ids are
// numbered in the order the claims are added ("<paper>-C<n>").
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "reproduce/claims.h"

namespace dynref::reproduce {

inline ReportRef Cell(std::string report, std::string heading, std::string row, std::string column) {
  return {std::move(report), std::move(heading), std::move(row), std::move(column)};
}
inline PaperRef PaperCell(std::string csv, std::string row, std::string column) {
  return {std::move(csv), std::move(row), std::move(column)};
}
inline ClaimOperand Op(std::string label, ReportRef ours, PaperRef paper = {}) {
  return {std::move(label), std::move(ours), std::move(paper)};
}

class ClaimList {
 public:
  explicit ClaimList(std::string paper) : paper_(std::move(paper)) {}
  // Adds a claim and returns it for the kind-specific fields.
  Claim& Add(const std::string& source, const std::string& statement, ClaimKind kind,
             std::vector<ClaimOperand> operands, const std::string& explanation = "") {
    Claim c;
    c.id = paper_ + "-C" + std::to_string(claims_.size() + 1);
    c.paper = paper_;
    c.source = source;
    c.statement = statement;
    c.kind = kind;
    c.operands = std::move(operands);
    c.explanation = explanation;
    claims_.push_back(std::move(c));
    return claims_.back();
  }
  // A claim ours does not measure (the reason goes where an explanation would).
  void NotMeasured(const std::string& source, const std::string& statement, const std::string& why) {
    Add(source, statement, ClaimKind::kNotMeasured, {}, why);
  }
  std::vector<Claim> Take() { return std::move(claims_); }

 private:
  std::string paper_;
  std::vector<Claim> claims_;
};

// A threshold from the text (kAtLeast / kAtMost / kImprovement).
inline void SetThreshold(Claim& c, double value, const std::string& where) {
  c.threshold = value;
  c.threshold_text = where;
}

}  // namespace dynref::reproduce
