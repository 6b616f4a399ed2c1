// Errors that carry a location, and the exit codes every dynref command uses.
#pragma once
#include <stdexcept>
#include <string>

namespace dynref {

// Throws InputError(path, 1, ...) when `first_line` starts with a UTF-8 byte-order mark
// (EF BB BF): editors on Windows add it, and every text reader here would otherwise report a
// confusing error about the first field (issue 20 item 10).
void RejectUtf8Bom(const std::string& path, const std::string& first_line);

// Process exit codes (contract, see README): 0 ok, 1 a check/comparison failed, 2 bad input/usage.
enum ExitCode : int { kExitOk = 0, kExitCheckFailed = 1, kExitBadInput = 2 };

// Bad input: names the file and (when known, > 0) the 1-based line. The CLI maps it to exit 2.
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& file, int line, const std::string& what);
  InputError(const std::string& file, const std::string& what) : InputError(file, 0, what) {}
  const std::string& file() const { return file_; }
  int line() const { return line_; }

 private:
  std::string file_;
  int line_;
};

// Formats "file:line: what" (or "file: what" when line <= 0).
std::string FormatLocation(const std::string& file, int line, const std::string& what);

}  // namespace dynref
