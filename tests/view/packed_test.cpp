// The data format of `dynref view` (ref/view/packed.h): basE91 of zlib round-trips any bytes, and
// packed columns (references, templates of integers) give back exactly the plain columns.
#include "view/packed.h"

#include <catch2/catch.hpp>
#include <string>

#include "core/error.h"

using dynref::view::DeflateBase91;
using dynref::view::InflateBase91;
using dynref::view::PackColumns;
using dynref::view::UnpackColumns;
using nlohmann::json;

TEST_CASE("view data: basE91 of zlib round-trips every length and byte, and needs no JavaScript escape", "[view]") {
  for (size_t n : {0, 1, 2, 3, 13, 14, 100, 4097}) {
    std::string bytes;
    for (size_t i = 0; i < n; ++i) bytes += static_cast<char>((i * 131 + n * 7) % 256);
    const std::string text = DeflateBase91(bytes);
    CHECK(text.find('"') == std::string::npos);
    CHECK(text.find('\\') == std::string::npos);
    CHECK(InflateBase91(text) == bytes);
  }
  CHECK_THROWS_AS(InflateBase91("ab\"c"), dynref::InputError);
  CHECK_THROWS_AS(InflateBase91("abcd"), dynref::InputError);  // not a zlib stream
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
