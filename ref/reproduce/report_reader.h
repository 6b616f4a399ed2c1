// A strict reader of the Markdown reports `dynref reproduce <table>` writes (report_format.h): one
// pipe table under a heading, a cell addressed by its row (the leading cells, " | "-joined) and its
// column name, read as "mean ± S.D.", a plain number, or a per-seed list ("0.0094 (300) 0.0126
// (294)"). Anything named that is not there is an InputError naming the report file and line
// (exit 2): a report regenerated without a row the claims ledger reads fails loudly.
#pragma once
#include <string>
#include <vector>

namespace dynref::reproduce {

// One Markdown pipe table of a report: its heading, header cells and body rows with their lines.
struct ReportTable {
  std::string file;     // the report path as given
  std::string heading;  // the full heading text (without the '#'s)
  int heading_line = 0;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::vector<int> row_lines;  // 1-based line of each row
};

// A report cell read as a number: mean and S.D. (has_sd false for a plain number), or per-seed
// values (seeds non-empty, mean/sd computed from them). text is the cell as written.
struct ReportValue {
  std::string text;
  double mean = 0.0;
  double sd = 0.0;
  bool has_sd = false;
  std::vector<double> seeds;
  bool numeric = true;  // false for "-", "n/a", "never initialised" ...: not measured
  std::string file;
  int line = 0;
};

// The report's lines (InputError when it cannot be opened).
std::vector<std::string> ReadReportLines(const std::string& path);
// The first table after the one heading that starts with `heading` (InputError: no such heading,
// several match, or no table below it before the next heading).
ReportTable FindReportTable(const std::string& path, const std::vector<std::string>& lines, const std::string& heading);
ReportTable ReadReportTable(const std::string& path, const std::string& heading);
// The index of the row whose leading cells equal `row` split at " | " (exactly one such row).
size_t FindReportRow(const ReportTable& t, const std::string& row);
// The index of the column named `column`; "name#2" picks its second occurrence.
size_t FindReportColumn(const ReportTable& t, const std::string& column);
// The cell at (row, column), parsed (InputError naming file:line when the text is neither a
// number, "mean ± S.D." nor a per-seed list, and not a "not measured" marker).
ReportValue ReadReportValue(const ReportTable& t, const std::string& row, const std::string& column);
// Parses one cell's text; `where` names it in errors.
ReportValue ParseReportCell(const std::string& text, const std::string& file, int line);

// What a report says of its runs, from its "Written by `dynref reproduce ...`" line: --seeds and
// --frames ("" when the command names none); commit = the "commit <hash>" after it.
struct ReportProvenance {
  std::string seeds;
  std::string frames;
  std::string commit;
};
ReportProvenance ReadReportProvenance(const std::string& path, const std::vector<std::string>& lines);

}  // namespace dynref::reproduce
