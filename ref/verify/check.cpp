#include "verify/check.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/format.h"
#include "verify/trace_model.h"

namespace dynref::verify {

bool Agrees(double expected, double recorded, double tol) {
  if (std::isnan(expected) || std::isnan(recorded)) return std::isnan(expected) && std::isnan(recorded);
  if (std::isinf(expected) || std::isinf(recorded)) return expected == recorded;
  const double scale = std::max({1.0, std::fabs(expected), std::fabs(recorded)});
  return std::fabs(expected - recorded) <= tol * scale;
}

void Check::Near(const std::string& field, double expected, double recorded, double tol) {
  if (!ok() || Agrees(expected, recorded, tol)) return;
  verdict_ = {Status::kMismatch, field, expected, recorded,
              "expected " + FormatDouble17(expected) + ", recorded " + FormatDouble17(recorded)};
}

void Check::Same(const std::string& field, const std::string& expected, const std::string& recorded) {
  if (!ok() || expected == recorded) return;
  verdict_ = {Status::kMismatch, field, 0, 0, "expected '" + expected + "', recorded '" + recorded + "'"};
}

void Check::Same(const std::string& field, bool expected, bool recorded) {
  Same(field, std::string(expected ? "1" : "0"), std::string(recorded ? "1" : "0"));
}

void Check::Missing(const std::string& what) {
  if (verdict_.status == Status::kUnverifiable) return;
  // Unverifiable outranks a mismatch found before: the recomputation was not complete.
  verdict_ = {Status::kUnverifiable, what, 0, 0, "not in the trace: " + what};
}

void Check::NoVerifier(const std::string& why) { verdict_ = {Status::kUnverifiable, "", 0, 0, why}; }

double Check::Need(const trace::Record& r, const std::string& name) {
  return Need(Input(r, name), "input " + name);
}

double Check::Need(const std::optional<double>& value, const std::string& what) {
  if (value) return *value;
  Missing(what);
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace dynref::verify
