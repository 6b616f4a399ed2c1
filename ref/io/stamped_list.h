// Line-oriented stamped text files of the TUM RGB-D benchmark (rgb.txt, depth.txt,
// groundtruth.txt, associate.py output, trajectories): '#' comments and blank lines skipped,
// fields separated by spaces, tabs or commas (as TUM's associate.py read_file_list).
#pragma once
#include <string>
#include <vector>

namespace dynref {

struct StampedLine {
  int line = 0;                     // 1-based line number in the file
  double stamp = 0;                 // first field
  std::string stamp_text;           // first field exactly as written
  std::vector<std::string> fields;  // remaining fields
};

// Reads every data line. InputError (file, line) when the file is missing, a line has fewer
// than 1 + min_fields fields (or more than 1 + max_fields when max_fields >= 0), the stamp
// is not a finite number, or stamps decrease. Equal consecutive stamps are an error too unless
// allow_equal_stamps (official TUM ground truth has a few; the caller decides which to keep).
std::vector<StampedLine> ReadStampedList(const std::string& path, int min_fields, int max_fields,
                                         bool allow_equal_stamps = false);

// Parses a whole field as a double (locale independent, leading '+' allowed).
// InputError naming file, line and what the field is when it is not a number.
double ParseNumberField(const std::string& text, const std::string& file, int line,
                        const std::string& what);

}  // namespace dynref
