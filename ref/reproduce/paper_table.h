// A paper's table as CSV (reports/paper-tables/*.csv, copied from ../shared/paper-tables):
// '#' comments, a header line, then one row per line; cells addressed by row name and column.
#pragma once
#include <map>
#include <string>
#include <vector>

namespace dynref::reproduce {

struct PaperTable {
  std::string caption;             // the last '#' line before the header: "Table 1. ... (unit)"
  std::vector<std::string> notes;  // later '#' lines: inconsistencies found in the paper's table
  std::vector<std::string> header;
  std::map<std::string, std::vector<std::string>> rows;  // first cell -> cells (a repeated first cell: the last row)
  std::vector<std::vector<std::string>> ordered;          // every row in file order (tables whose first column repeats)
  // The cell as a number; NaN when the row or column is missing or the cell is empty or text.
  double Cell(const std::string& row, const std::string& column) const;
};

// InputError naming the file when it cannot be opened.
PaperTable ReadPaperTable(const std::string& path);
// reports/paper-tables in the source tree.
std::string PaperTableDir();

}  // namespace dynref::reproduce
