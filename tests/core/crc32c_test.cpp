#include <catch2/catch.hpp>

#include <string>

#include "core/crc32c.h"

TEST_CASE("crc32c: RFC 3720 B.4 and the common check value") {
  CHECK(dynref::Crc32c(std::string("123456789")) == 0xE3069283u);
  CHECK(dynref::Crc32c(std::string()) == 0u);
  std::string zeros(32, '\0'), ones(32, '\xFF'), up(32, '\0'), down(32, '\0');
  for (int i = 0; i < 32; ++i) {
    up[i] = static_cast<char>(i);
    down[i] = static_cast<char>(31 - i);
  }
  CHECK(dynref::Crc32c(zeros) == 0x8A9136AAu);
  CHECK(dynref::Crc32c(ones) == 0x62A8AB43u);
  CHECK(dynref::Crc32c(up) == 0x46DD794Eu);
  CHECK(dynref::Crc32c(down) == 0x113FDB5Cu);
}

TEST_CASE("crc32c: extending in pieces equals one pass, and one flipped bit changes it") {
  std::string text;
  for (int i = 0; i < 1000; ++i) text.push_back(static_cast<char>((i * 37 + 11) & 0xFF));
  const uint32_t whole = dynref::Crc32c(text);
  for (size_t cut : {0u, 1u, 7u, 8u, 9u, 500u, 999u, 1000u}) {
    uint32_t c = dynref::Crc32cExtend(0, text.data(), cut);
    c = dynref::Crc32cExtend(c, text.data() + cut, text.size() - cut);
    CHECK(c == whole);
  }
  for (size_t byte : {0u, 13u, 512u, 999u})
    for (int bit = 0; bit < 8; bit += 3) {
      std::string flipped = text;
      flipped[byte] = static_cast<char>(flipped[byte] ^ (1 << bit));
      CHECK(dynref::Crc32c(flipped) != whole);
    }
}
