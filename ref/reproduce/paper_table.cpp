#include "reproduce/paper_table.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "pipeline/method_config.h"

namespace dynref::reproduce {
namespace {

// RFC 4180 cells: a quoted cell may hold commas ("AMD Ryzen 7 4800H CPU, NVIDIA RTX 2060 GPU"),
// "" inside quotes is one quote.
std::vector<std::string> SplitCsv(const std::string& line) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char ch = line[i];
    if (quoted && ch == '"' && i + 1 < line.size() && line[i + 1] == '"') {
      out.back() += '"';
      ++i;
    } else if (ch == '"') {
      quoted = !quoted;
    } else if (ch == ',' && !quoted) {
      out.emplace_back();
    } else if (ch != '\r') {
      out.back() += ch;
    }
  }
  return out;
}

}  // namespace

double PaperTable::Cell(const std::string& row, const std::string& column) const {
  auto r = rows.find(row);
  if (r == rows.end()) return std::nan("");
  for (size_t c = 0; c < header.size() && c < r->second.size(); ++c)
    if (header[c] == column) {
      char* end = nullptr;
      const double v = std::strtod(r->second[c].c_str(), &end);
      return end != r->second[c].c_str() ? v : std::nan("");  // empty (printed '-') or text: NaN
    }
  return std::nan("");
}

PaperTable ReadPaperTable(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open paper table");
  PaperTable t;
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] == '#') {
      // Before the header: provenance lines, then the caption (the last one); after it: notes.
      const std::string text = line.substr(line.size() > 1 && line[1] == ' ' ? 2 : 1);
      (t.header.empty() ? t.caption : t.notes.emplace_back()) = text;
      continue;
    }
    if (line.empty()) continue;
    if (t.header.empty()) {
      t.header = SplitCsv(line);
      continue;
    }
    const auto cells = SplitCsv(line);
    if (cells.empty()) continue;
    t.rows[cells[0]] = cells;
    t.ordered.push_back(cells);
  }
  return t;
}

std::string PaperTableDir() {
  // configs/<m>.yaml lives in the source tree, reports/ beside it.
  return (std::filesystem::path(MethodConfigPath("orb")).parent_path().parent_path() / "reports" / "paper-tables")
      .string();
}

}  // namespace dynref::reproduce
