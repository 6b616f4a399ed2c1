#include "reproduce/paper_table.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "pipeline/method_config.h"

namespace dynref::reproduce {
namespace {

std::vector<std::string> SplitCsv(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) out.push_back(cell);
  return out;
}

}  // namespace

double PaperTable::Cell(const std::string& row, const std::string& column) const {
  auto r = rows.find(row);
  if (r == rows.end()) return std::nan("");
  for (size_t c = 0; c < header.size() && c < r->second.size(); ++c)
    if (header[c] == column) return std::stod(r->second[c]);
  return std::nan("");
}

PaperTable ReadPaperTable(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open paper table");
  PaperTable t;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
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
