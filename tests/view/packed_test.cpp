// The data format of `dynref view` (ref/view/packed.h): the one-character-per-byte literal of a
// zlib stream round-trips any bytes and is a valid JavaScript string body, and packed columns
// (references, templates of integers) give back exactly the plain columns.
#include "view/packed.h"

#include <catch2/catch.hpp>
#include <string>

#include "core/error.h"

using dynref::view::DeflateLatin1;
using dynref::view::InflateLatin1;
using dynref::view::LzmaLatin1;
using dynref::view::UnlzmaLatin1;
using dynref::view::PackColumns;
using dynref::view::UnpackColumns;
using nlohmann::json;

namespace {

// True when `text` is a JavaScript "..." literal body: no line end or NUL, every quote and
// backslash escaped, and only the escapes DeflateLatin1 writes.
bool ValidLiteral(const std::string& text) {
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '"' || c == '\n' || c == '\r' || c == '\0') return false;
    if (c != '\\') continue;
    if (text.compare(i + 1, 3, "x00") == 0) i += 3;
    else if (i + 1 < text.size() && std::string("\"\\nr").find(text[i + 1]) != std::string::npos) ++i;
    else return false;
  }
  return true;
}

}  // namespace

TEST_CASE("view data: the zlib literal round-trips every length and byte, and is a valid JavaScript string", "[view]") {
  for (size_t n : {0, 1, 2, 3, 13, 14, 100, 4097}) {
    std::string bytes;
    for (size_t i = 0; i < n; ++i) bytes += static_cast<char>((i * 131 + n * 7) % 256);
    const std::string text = DeflateLatin1(bytes);
    CHECK(ValidLiteral(text));
    CHECK(InflateLatin1(text) == bytes);
  }
  // Every byte value, the escaped ones included, in the compressed stream of random-looking text.
  std::string noise;
  for (uint32_t i = 0, x = 1; i < 20000; ++i) x = x * 1103515245u + 12345u, noise += static_cast<char>(x >> 23);
  const std::string text = DeflateLatin1(noise);
  for (const char* e : {"\\\"", "\\\\", "\\n", "\\r", "\\x00"}) CHECK(text.find(e) != std::string::npos);
  CHECK(ValidLiteral(text));
  CHECK(InflateLatin1(text) == noise);
  CHECK_THROWS_AS(InflateLatin1("ab\"c"), dynref::InputError);   // an unescaped quote
  CHECK_THROWS_AS(InflateLatin1("ab\\qc"), dynref::InputError);  // an escape it never writes
  CHECK_THROWS_AS(InflateLatin1("abcd"), dynref::InputError);     // not a zlib stream
}

TEST_CASE("view data: the LZMA literal round-trips, is a valid JavaScript string, and beats zlib on repeated frames", "[view]") {
  for (size_t n : {0, 1, 14, 4097}) {
    std::string bytes;
    for (size_t i = 0; i < n; ++i) bytes += static_cast<char>((i * 131 + n * 7) % 256);
    const std::string text = LzmaLatin1(bytes);
    CHECK(ValidLiteral(text));
    CHECK(UnlzmaLatin1(text) == bytes);
    CHECK(LzmaLatin1(bytes) == text);  // deterministic
  }
  // Two "frames" of pseudo-random numbers 40 KB apart, the second repeating most of the first:
  // zlib's 32 KB window cannot reach back, LZMA's can (README.md "Size": why chunks of frames).
  std::string frame;
  for (uint32_t i = 0, x = 7; frame.size() < 40000; ++i) x = x * 1103515245u + 12345u, frame += std::to_string(x >> 9) + ",";
  const std::string two = frame + frame.substr(0, 39000) + "1,2,3";
  const std::string text = LzmaLatin1(two);
  CHECK(UnlzmaLatin1(text) == two);
  CHECK(text.size() < DeflateLatin1(two).size() * 6 / 10);
  CHECK_THROWS_AS(UnlzmaLatin1("abcd"), dynref::InputError);  // not an LZMA stream
}

TEST_CASE("view data: packed columns restore the plain ones, repeated columns stored once", "[view]") {
  const json cols = {
      {"0", {{"f12.0", "f12.1", "f12.7"}, {0, 0, 1}, {0.5, 0.25, "nan"}, {"1", "-1", "12"}}},
      {"1", {{"f12.0", "f12.1", "f12.7"}, {0, 0, 1}, {"mp1@kf0", "mp1@kf3", "mp40@kf2"}, {0.5, 0.25, "nan"}}},
      // json::array: a braced pair of texts would be a JSON object
      {"2", {json::array({"007", "7"}), json::array({"-0", "1"}), json::array({"2c62", "7b82"}), json::array({"", ""}),
             json::array()}},
      {"10", json::array({json::array({"a-1.5", "a-3.5"}), json::array({"9999999999999999", "1"})})}};
  const json packed = PackColumns(cols);
  CHECK(packed["1"][0] == json({{"=", {0, 0}}}));    // same entities as schema 0
  CHECK(packed["1"][3] == json({{"=", {0, 2}}}));    // same numbers as schema 0's field
  CHECK(packed["0"][0].at("t") == json({"f", ".", ""}));
  CHECK(packed["0"][0].at("n") == json({{12, 0, 0}, {0, 1, 6}}));
  CHECK(packed["1"][2].at("t") == json({"mp", "@kf", ""}));
  CHECK(packed["2"][0].is_array());  // "007" would not print back
  CHECK(packed["2"][1].is_array());  // "-0" neither
  CHECK(packed["10"][1].is_array());  // 16 digits: beyond a double's exact integers
  CHECK(UnpackColumns(packed) == cols);
}
