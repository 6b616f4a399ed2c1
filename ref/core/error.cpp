#include "core/error.h"

namespace dynref {

std::string FormatLocation(const std::string& file, int line, const std::string& what) {
  if (line > 0) return file + ":" + std::to_string(line) + ": " + what;
  return file + ": " + what;
}

InputError::InputError(const std::string& file, int line, const std::string& what)
    : std::runtime_error(FormatLocation(file, line, what)), file_(file), line_(line) {}

void RejectUtf8Bom(const std::string& path, const std::string& first_line) {
  if (first_line.size() >= 3 && static_cast<unsigned char>(first_line[0]) == 0xEF &&
      static_cast<unsigned char>(first_line[1]) == 0xBB && static_cast<unsigned char>(first_line[2]) == 0xBF)
    throw InputError(path, 1, "starts with a UTF-8 byte-order mark (bytes EF BB BF); save the file without it");
}

}  // namespace dynref
