// Errors that carry a location, and the exit codes every dynref command uses.
#pragma once
#include <stdexcept>
#include <string>

namespace dynref {

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
