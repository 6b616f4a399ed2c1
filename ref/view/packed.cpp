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

// basE91's alphabet with '-' for '"' (README.md "Size"); the page's decoder (site/view.js) has the same.
constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789!#$%&()*+,./:;<=>?@[]^_`{|}~-";

std::string Base91(const std::string& bytes) {
  std::string out;
  out.reserve(bytes.size() * 5 / 4 + 2);
  uint32_t b = 0;
  int n = 0;
  for (char c : bytes) {
    b |= static_cast<uint32_t>(static_cast<unsigned char>(c)) << n;
    n += 8;
    if (n > 13) {
      uint32_t v = b & 8191;
      if (v > 88) {
        b >>= 13, n -= 13;
      } else {
        v = b & 16383, b >>= 14, n -= 14;
      }
      out += kAlphabet[v % 91], out += kAlphabet[v / 91];
    }
  }
  if (n > 0) {
    out += kAlphabet[b % 91];
    if (n > 7 || b > 90) out += kAlphabet[b / 91];
  }
  return out;
}

std::string Unbase91(const std::string& text) {
  std::string out;
  uint32_t b = 0;
  int n = 0, v = -1;
  for (char c : text) {
    const char* p = c == '\0' ? nullptr : std::strchr(kAlphabet, c);
    if (p == nullptr) throw InputError("base91", "invalid character");
    const int d = static_cast<int>(p - kAlphabet);
    if (v < 0) {
      v = d;
      continue;
    }
    v += d * 91;
    b |= static_cast<uint32_t>(v) << n;
    n += (v & 8191) > 88 ? 13 : 14;
    do out += static_cast<char>(b & 0xff), b >>= 8, n -= 8;
    while (n > 7);
    v = -1;
  }
  if (v >= 0) out += static_cast<char>((b | static_cast<uint32_t>(v) << n) & 0xff);
  return out;
}

}  // namespace

std::string DeflateBase91(const std::string& text) {
  uLongf size = compressBound(static_cast<uLong>(text.size()));
  std::string out(size, '\0');
  if (compress2(reinterpret_cast<Bytef*>(out.data()), &size, reinterpret_cast<const Bytef*>(text.data()),
                static_cast<uLong>(text.size()), 9) != Z_OK)
    throw std::runtime_error("zlib compress2 failed");
  out.resize(size);
  return Base91(out);
}

std::string InflateBase91(const std::string& b91) {
  const std::string in = Unbase91(b91);
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
  if (rc != Z_STREAM_END) throw InputError("base91", "not a complete zlib stream");
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
