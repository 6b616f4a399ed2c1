#include "view/packed.h"

#include <zlib.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "core/error.h"

namespace dynref::view {
namespace {

// The JavaScript escape of byte c inside a "..." literal, or nullptr when it stands for itself.
// NUL is written \x00 (a \0 before a digit would read as an octal escape).
const char* Escape(unsigned char c) {
  switch (c) {
    case '"': return "\\\"";
    case '\\': return "\\\\";
    case '\n': return "\\n";
    case '\r': return "\\r";
    case '\0': return "\\x00";
    default: return nullptr;
  }
}

}  // namespace

std::string Latin1Literal(const std::string& bytes) {
  std::string out;
  out.reserve(bytes.size() + bytes.size() / 32 + 8);
  for (char c : bytes) {
    const char* e = Escape(static_cast<unsigned char>(c));
    if (e != nullptr) out += e;
    else out += c;
  }
  return out;
}

std::string Latin1Bytes(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '"' || c == '\n' || c == '\r' || c == '\0') throw InputError("view data", "unescaped quote or line end");
    if (c != '\\') {
      out += c;
      continue;
    }
    const std::string rest = text.substr(i + 1, 3);
    if (rest.rfind("x00", 0) == 0) out += '\0', i += 3;
    else if (!rest.empty() && (rest[0] == '"' || rest[0] == '\\')) out += rest[0], ++i;
    else if (!rest.empty() && (rest[0] == 'n' || rest[0] == 'r')) out += rest[0] == 'n' ? '\n' : '\r', ++i;
    else throw InputError("view data", "unknown escape");
  }
  return out;
}

std::string DeflateLatin1(const std::string& text) {
  uLongf size = compressBound(static_cast<uLong>(text.size()));
  std::string out(size, '\0');
  if (compress2(reinterpret_cast<Bytef*>(out.data()), &size, reinterpret_cast<const Bytef*>(text.data()),
                static_cast<uLong>(text.size()), 9) != Z_OK)
    throw std::runtime_error("zlib compress2 failed");
  out.resize(size);
  return Latin1Literal(out);
}

std::string InflateLatin1(const std::string& literal) {
  const std::string in = Latin1Bytes(literal);
  z_stream z{};
  if (inflateInit(&z) != Z_OK) throw std::runtime_error("zlib inflateInit failed");
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data()));
  z.avail_in = static_cast<uInt>(in.size());
  std::string out;
  char buf[65536];
  int rc = Z_OK;
  while (rc == Z_OK) {
    z.next_out = reinterpret_cast<Bytef*>(buf);
    z.avail_out = sizeof(buf);
    rc = inflate(&z, Z_NO_FLUSH);
    out.append(buf, sizeof(buf) - z.avail_out);
  }
  inflateEnd(&z);
  if (rc != Z_STREAM_END) throw InputError("view data", "not a complete zlib stream");
  return out;
}

nlohmann::json RoundedNumber(double v, int digits) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  double r = v;
  if (digits < 17) {
    char text[40];
    std::snprintf(text, sizeof(text), "%.*g", digits, v);
    r = std::strtod(text, nullptr);
  }
  if (r == std::floor(r) && std::fabs(r) < 9007199254740992.0) return static_cast<int64_t>(r);
  return r;
}

}  // namespace dynref::view
