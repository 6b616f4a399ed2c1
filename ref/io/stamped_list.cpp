#include "io/stamped_list.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sys/stat.h>

#include "core/error.h"
#include "core/format.h"

namespace dynref {
namespace {

std::vector<std::string> SplitFields(const std::string& s) {
  std::vector<std::string> out;
  std::string cur;
  for (char ch : s) {
    if (ch == ' ' || ch == '\t' || ch == ',' || ch == '\r') {
      if (!cur.empty()) out.push_back(cur);
      cur.clear();
    } else {
      cur += ch;
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

}  // namespace

double ParseNumberField(const std::string& text, const std::string& file, int line,
                        const std::string& what) {
  const char* begin = text.data();
  const char* end = text.data() + text.size();
  if (begin != end && *begin == '+') ++begin;
  double v = 0;
  const auto res = std::from_chars(begin, end, v);
  if (begin == end || res.ec != std::errc() || res.ptr != end)
    throw InputError(file, line, what + " '" + text + "' is not a number");
  return v;
}

std::vector<StampedLine> ReadStampedList(const std::string& path, int min_fields, int max_fields,
                                         bool allow_equal_stamps) {
  struct stat st;
  if (::stat(path.c_str(), &st) != 0) throw InputError(path, "file not found");
  if (S_ISDIR(st.st_mode)) throw InputError(path, "is a directory, expected a text file");
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open file");
  std::vector<StampedLine> out;
  std::string text;
  int line_no = 0;
  while (std::getline(in, text)) {
    ++line_no;
    if (line_no == 1) RejectUtf8Bom(path, text);
    std::vector<std::string> f = SplitFields(text);
    if (f.empty() || f[0][0] == '#') continue;
    const int n = static_cast<int>(f.size()) - 1;
    if (n < min_fields || (max_fields >= 0 && n > max_fields)) {
      const std::string expected =
          min_fields == max_fields ? std::to_string(1 + min_fields)
                                   : "at least " + std::to_string(1 + min_fields);
      throw InputError(path, line_no,
                       "malformed line: " + std::to_string(f.size()) + " fields, expected " +
                           expected + " (timestamp first)");
    }
    StampedLine sl;
    sl.line = line_no;
    sl.stamp_text = f[0];
    sl.stamp = ParseNumberField(f[0], path, line_no, "timestamp");
    if (!std::isfinite(sl.stamp))
      throw InputError(path, line_no, "timestamp '" + f[0] + "' is not finite");
    if (!out.empty() && (sl.stamp < out.back().stamp ||
                         (sl.stamp == out.back().stamp && !allow_equal_stamps)))
      throw InputError(path, line_no,
                       std::string(sl.stamp < out.back().stamp ? "timestamps not increasing"
                                                               : "duplicate timestamp") +
                           ": " + f[0] + " after " +
                           out.back().stamp_text + " (line " + std::to_string(out.back().line) +
                           ")");
    sl.fields.assign(f.begin() + 1, f.end());
    out.push_back(std::move(sl));
  }
  if (in.bad()) throw InputError(path, line_no, "read error");
  return out;
}

}  // namespace dynref
