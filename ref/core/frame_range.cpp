#include "core/frame_range.h"

#include <cctype>
#include <limits>

#include "core/error.h"

namespace dynref {
namespace {

// Non-empty run of decimal digits -> value; false on empty text or overflow.
bool ParseIndex(const std::string& digits, int64_t* value) {
  if (digits.empty()) return false;
  int64_t v = 0;
  for (char c : digits) {
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
    const int d = c - '0';
    if (v > (std::numeric_limits<int64_t>::max() - d) / 10) return false;
    v = v * 10 + d;
  }
  *value = v;
  return true;
}

}  // namespace

FrameRange ParseFrameRange(const std::string& text, const std::string& option) {
  const auto bad = [&](const std::string& why) {
    return InputError(option, "expected A, A-B or A- (0-based inclusive frame indices), got '" + text +
                                  "'" + (why.empty() ? "" : ": " + why));
  };
  FrameRange r;
  const size_t dash = text.find('-');
  if (!ParseIndex(text.substr(0, dash), &r.first)) throw bad("");
  if (dash == std::string::npos) {
    r.last = r.first;
  } else if (dash + 1 < text.size()) {
    if (!ParseIndex(text.substr(dash + 1), &r.last)) throw bad("");
    if (r.last < r.first) throw bad("B < A");
  }
  return r;
}

int64_t FrameRange::LastIn(int64_t count, const std::string& option) const {
  const int64_t l = open_ended() ? count - 1 : last;
  if (first >= count || l >= count) {
    throw InputError(option, "frames " + std::to_string(first) + "-" +
                                 (open_ended() ? std::string() : std::to_string(last)) +
                                 " beyond the sequence's " + std::to_string(count) + " frames (0-based)");
  }
  return l;
}

}  // namespace dynref
