#include "reproduce/report_reader.h"

#include <charconv>
#include <cmath>
#include <fstream>

#include "core/error.h"

namespace dynref::reproduce {
namespace {

std::string TrimReport(const std::string& s) {
  size_t b = 0, e = s.size();
  while (b < e && (s[b] == ' ' || s[b] == '\t' || s[b] == '\r')) ++b;
  while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\t' || s[e - 1] == '\r')) --e;
  return s.substr(b, e - b);
}

bool IsTableLine(const std::string& line) { return !line.empty() && line[0] == '|'; }
bool IsHeadingLine(const std::string& line) { return !line.empty() && line[0] == '#'; }

std::string HeadingText(const std::string& line) {
  size_t i = 0;
  while (i < line.size() && line[i] == '#') ++i;
  return TrimReport(line.substr(i));
}

std::vector<std::string> SplitPipeRow(const std::string& line) {
  std::vector<std::string> cells;
  std::string t = TrimReport(line);
  if (!t.empty() && t.front() == '|') t.erase(0, 1);
  if (!t.empty() && t.back() == '|') t.pop_back();
  size_t start = 0;
  for (size_t i = 0; i <= t.size(); ++i)
    if (i == t.size() || t[i] == '|') {
      cells.push_back(TrimReport(t.substr(start, i - start)));
      start = i + 1;
    }
  return cells;
}

std::vector<std::string> SplitKey(const std::string& key) {
  std::vector<std::string> parts;
  size_t start = 0;
  for (;;) {
    const size_t at = key.find(" | ", start);
    parts.push_back(key.substr(start, at == std::string::npos ? std::string::npos : at - start));
    if (at == std::string::npos) return parts;
    start = at + 3;
  }
}

// A number at s[i..]: advances i past it.
bool ReadNumber(const std::string& s, size_t& i, double& v) {
  const char* b = s.data() + i;
  const auto r = std::from_chars(b, s.data() + s.size(), v);
  if (r.ec != std::errc() || r.ptr == b) return false;
  i += static_cast<size_t>(r.ptr - b);
  return true;
}

void SkipSpaces(const std::string& s, size_t& i) {
  while (i < s.size() && s[i] == ' ') ++i;
}

// " (...)" with no nested parentheses: advances past it.
bool ReadParenthesised(const std::string& s, size_t& i) {
  if (i >= s.size() || s[i] != '(') return false;
  const size_t close = s.find(')', i);
  if (close == std::string::npos) return false;
  i = close + 1;
  return true;
}

// "m", "m ± sd", each optionally followed by " %", "x" or " (...)".
bool ParseMeanSd(const std::string& s, ReportValue& v) {
  size_t i = 0;
  if (!ReadNumber(s, i, v.mean)) return false;
  size_t j = i;
  SkipSpaces(s, j);
  const std::string pm = "±";
  if (s.compare(j, pm.size(), pm) == 0) {
    j += pm.size();
    SkipSpaces(s, j);
    if (!ReadNumber(s, j, v.sd)) return false;
    v.has_sd = true;
    i = j;
  }
  if (i < s.size() && s[i] == 'x') ++i;
  SkipSpaces(s, i);
  if (i < s.size() && s[i] == '%') ++i;
  SkipSpaces(s, i);
  ReadParenthesised(s, i);
  return i == s.size();
}

// "a (n) b (n) c (n)" or "a b c": two or more per-seed values.
bool ParseSeedList(const std::string& s, ReportValue& v) {
  size_t i = 0;
  std::vector<double> values;
  while (i < s.size()) {
    double x = 0;
    if (!ReadNumber(s, i, x)) return false;
    values.push_back(x);
    SkipSpaces(s, i);
    if (ReadParenthesised(s, i)) SkipSpaces(s, i);
  }
  if (values.size() < 2) return false;
  double sum = 0, sq = 0;
  for (double x : values) sum += x;
  const double mean = sum / static_cast<double>(values.size());
  for (double x : values) sq += (x - mean) * (x - mean);
  v.seeds = values;
  v.mean = mean;
  v.sd = std::sqrt(sq / static_cast<double>(values.size()));  // population S.D., as the reports
  v.has_sd = true;
  return true;
}

bool IsNotMeasuredMarker(const std::string& s) {
  return s == "-" || s == "n/a" || s == "never initialised" || s == "- / -";
}

std::string AfterToken(const std::string& line, const std::string& token) {
  const size_t at = line.find(token);
  if (at == std::string::npos) return "";
  size_t b = at + token.size(), e = b;
  while (e < line.size() && line[e] != ' ' && line[e] != '`' && line[e] != ')' && line[e] != '.') ++e;
  return line.substr(b, e - b);
}

}  // namespace

std::vector<std::string> ReadReportLines(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open the report");
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

ReportTable FindReportTable(const std::string& path, const std::vector<std::string>& lines, const std::string& heading) {
  int found = -1;
  for (size_t i = 0; i < lines.size(); ++i)
    if (IsHeadingLine(lines[i]) && HeadingText(lines[i]).rfind(heading, 0) == 0) {
      if (found >= 0)
        throw InputError(path, static_cast<int>(i) + 1,
                         "heading '" + heading + "' is ambiguous (also line " + std::to_string(found + 1) + ")");
      found = static_cast<int>(i);
    }
  if (found < 0) throw InputError(path, "no heading starting with '" + heading + "'");
  ReportTable t;
  t.file = path;
  t.heading = HeadingText(lines[found]);
  t.heading_line = found + 1;
  size_t i = static_cast<size_t>(found) + 1;
  while (i < lines.size() && !IsTableLine(lines[i]) && !IsHeadingLine(lines[i])) ++i;
  if (i + 1 >= lines.size() || !IsTableLine(lines[i]) || !IsTableLine(lines[i + 1]))
    throw InputError(path, found + 1, "no table under heading '" + t.heading + "'");
  t.header = SplitPipeRow(lines[i]);
  for (i += 2; i < lines.size() && IsTableLine(lines[i]); ++i) {
    t.rows.push_back(SplitPipeRow(lines[i]));
    t.row_lines.push_back(static_cast<int>(i) + 1);
  }
  return t;
}

ReportTable ReadReportTable(const std::string& path, const std::string& heading) {
  return FindReportTable(path, ReadReportLines(path), heading);
}

size_t FindReportRow(const ReportTable& t, const std::string& row) {
  const std::vector<std::string> key = SplitKey(row);
  size_t found = t.rows.size();
  for (size_t r = 0; r < t.rows.size(); ++r) {
    if (t.rows[r].size() < key.size()) continue;
    bool same = true;
    for (size_t k = 0; k < key.size() && same; ++k) same = t.rows[r][k] == key[k];
    if (!same) continue;
    if (found != t.rows.size())
      throw InputError(t.file, t.row_lines[r], "row '" + row + "' is ambiguous under '" + t.heading + "'");
    found = r;
  }
  if (found == t.rows.size())
    throw InputError(t.file, t.heading_line, "no row '" + row + "' in the table under '" + t.heading + "'");
  return found;
}

size_t FindReportColumn(const ReportTable& t, const std::string& column) {
  std::string name = column;
  int occurrence = 1;
  const size_t hash = column.rfind('#');
  const bool numbered = hash != std::string::npos && hash + 1 < column.size() &&
                        column.find_first_not_of("0123456789", hash + 1) == std::string::npos;
  if (numbered) {
    name = column.substr(0, hash);
    occurrence = std::stoi(column.substr(hash + 1));
  }
  int seen = 0;
  size_t found = t.header.size();
  for (size_t c = 0; c < t.header.size(); ++c)
    if (t.header[c] == name && ++seen == occurrence) found = c;
  if (seen > 1 && !numbered)
    throw InputError(t.file, t.heading_line,
                     "column '" + column + "' is ambiguous under '" + t.heading + "' (name its occurrence: '" + column + "#2')");
  if (found < t.header.size()) return found;
  throw InputError(t.file, t.heading_line, "no column '" + column + "' in the table under '" + t.heading + "'");
}

ReportValue ParseReportCell(const std::string& text, const std::string& file, int line) {
  ReportValue v;
  v.text = TrimReport(text);
  v.file = file;
  v.line = line;
  if (IsNotMeasuredMarker(v.text)) {
    v.numeric = false;
    return v;
  }
  ReportValue m = v;
  if (ParseMeanSd(v.text, m)) return m;
  ReportValue s = v;
  if (ParseSeedList(v.text, s)) return s;
  throw InputError(file, line, "cell '" + v.text + "' is not a number, 'mean ± S.D.' or a per-seed list");
}

ReportValue ReadReportValue(const ReportTable& t, const std::string& row, const std::string& column) {
  const size_t r = FindReportRow(t, row);
  const size_t c = FindReportColumn(t, column);
  if (c >= t.rows[r].size())
    throw InputError(t.file, t.row_lines[r], "row '" + row + "' has no cell in column '" + column + "'");
  return ParseReportCell(t.rows[r][c], t.file, t.row_lines[r]);
}

ReportProvenance ReadReportProvenance(const std::string& path, const std::vector<std::string>& lines) {
  for (const std::string& line : lines)
    if (line.rfind("Written by `", 0) == 0) {
      const size_t begin = std::string("Written by `").size();
      const size_t end = line.find('`', begin);
      const std::string cmd = line.substr(begin, end == std::string::npos ? std::string::npos : end - begin);
      ReportProvenance p;
      p.seeds = AfterToken(cmd, "--seeds ");
      p.frames = AfterToken(cmd, "--frames ");
      p.commit = end == std::string::npos ? "" : AfterToken(line.substr(end), "commit ");
      return p;
    }
  throw InputError(path, "no 'Written by `dynref ...`' line");
}

}  // namespace dynref::reproduce
