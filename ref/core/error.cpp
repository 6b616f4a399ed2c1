#include "core/error.h"

namespace dynref {

std::string FormatLocation(const std::string& file, int line, const std::string& what) {
  if (line > 0) return file + ":" + std::to_string(line) + ": " + what;
  return file + ": " + what;
}

InputError::InputError(const std::string& file, int line, const std::string& what)
    : std::runtime_error(FormatLocation(file, line, what)), file_(file), line_(line) {}

}  // namespace dynref
