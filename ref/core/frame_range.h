// The one grammar of every `--frames` option (run, detect, overlay): 0-based inclusive indices,
//   "A"    one frame,
//   "A-B"  frames A..B (B >= A),
//   "A-"   frame A to the end of the sequence (last = kToEnd).
// Anything else (signs, spaces, trailing text, B < A, numbers beyond int64) is an InputError
// naming the option and the text.
#pragma once
#include <cstdint>
#include <string>

namespace dynref {

struct FrameRange {
  static constexpr int64_t kToEnd = -1;
  int64_t first = 0;
  int64_t last = kToEnd;
  bool open_ended() const { return last == kToEnd; }
  // Last index for a sequence of `count` frames; InputError when the range does not fit.
  int64_t LastIn(int64_t count, const std::string& option = "--frames") const;
};

FrameRange ParseFrameRange(const std::string& text, const std::string& option = "--frames");

}  // namespace dynref
