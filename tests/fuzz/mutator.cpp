#include "mutator.h"

#include <algorithm>
#include <array>

namespace dynref::fuzz {
namespace {

constexpr std::array<const char*, 22> kTokens = {
    "0", "-1", "nan", "inf", "-inf", "1e309", "-1e309", "4294967296", "9223372036854775808",
    "1e-320", "0x10", " ", "\n", "\t", ",", "#", ":", "\"", "\xEF\xBB\xBF", "~", "{", "["};
constexpr std::array<unsigned char, 12> kBytes = {0x00, 0xFF, 0x7F, 0x80, '\n', ' ', '-',
                                                  '9',  '.',  'e',  ':',  0x01};

size_t Pick(Rng& rng, size_t n) { return static_cast<size_t>(rng.UniformInt(0, static_cast<int64_t>(n) - 1)); }

// Span [begin, end) of the number-like token around a random position, or empty.
std::pair<size_t, size_t> NumberAt(const std::string& s, size_t at) {
  auto numeric = [](char c) {
    return (c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+' || c == 'e' || c == 'E';
  };
  size_t b = at, e = at;
  while (b > 0 && numeric(s[b - 1])) --b;
  while (e < s.size() && numeric(s[e])) ++e;
  return {b, e};
}

void MutateOnce(std::string& s, Rng& rng) {
  const int kind = static_cast<int>(rng.UniformInt(0, 8));
  if (s.empty()) {
    s = kTokens[Pick(rng, kTokens.size())];
    return;
  }
  const size_t at = Pick(rng, s.size());
  switch (kind) {
    case 0:  // flip one bit
      s[at] = static_cast<char>(s[at] ^ (1 << rng.UniformInt(0, 7)));
      break;
    case 1:  // boundary byte
      s[at] = static_cast<char>(kBytes[Pick(rng, kBytes.size())]);
      break;
    case 2:  // insert a token
      s.insert(at, kTokens[Pick(rng, kTokens.size())]);
      break;
    case 3: {  // replace the number around `at` by a token
      const auto [b, e] = NumberAt(s, at);
      if (e > b) s.replace(b, e - b, kTokens[Pick(rng, 11)]);
      else s[at] = static_cast<char>(kBytes[Pick(rng, kBytes.size())]);
      break;
    }
    case 4: {  // delete a span
      const size_t n = 1 + Pick(rng, std::min<size_t>(64, s.size() - at));
      s.erase(at, n);
      break;
    }
    case 5: {  // duplicate a span
      const size_t n = 1 + Pick(rng, std::min<size_t>(64, s.size() - at));
      s.insert(at, s.substr(at, n));
      break;
    }
    case 6:  // truncate
      s.resize(at);
      break;
    case 7: {  // swap two lines (or two 8-byte words in binary data)
      const size_t other = Pick(rng, s.size());
      const size_t a = s.rfind('\n', at), b = s.rfind('\n', other);
      if (a == std::string::npos || b == std::string::npos || a == b) {
        for (size_t i = 0; i < 8 && at + i < s.size() && other + i < s.size(); ++i)
          std::swap(s[at + i], s[other + i]);
        break;
      }
      const size_t ae = std::min(s.find('\n', a + 1), s.size()), be = std::min(s.find('\n', b + 1), s.size());
      const std::string la = s.substr(a, ae - a), lb = s.substr(b, be - b);
      if (a < b) s = s.substr(0, a) + lb + s.substr(ae, b - ae) + la + s.substr(be);
      else s = s.substr(0, b) + la + s.substr(be, a - be) + lb + s.substr(ae);
      break;
    }
    default: {  // overwrite 1..8 bytes with random values
      const size_t n = 1 + Pick(rng, 8);
      for (size_t i = 0; i < n && at + i < s.size(); ++i)
        s[at + i] = static_cast<char>(rng.UniformInt(0, 255));
      break;
    }
  }
}

}  // namespace

std::string Mutate(const std::string& seed, Rng& rng) {
  std::string s = seed;
  const int edits = 1 + static_cast<int>(rng.UniformInt(0, 3));
  for (int i = 0; i < edits; ++i) MutateOnce(s, rng);
  return s;
}

}  // namespace dynref::fuzz
