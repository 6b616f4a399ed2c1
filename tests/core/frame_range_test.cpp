// The one `--frames` grammar shared by run, detect and overlay.
#include <catch2/catch.hpp>
#include <string>

#include "core/error.h"
#include "core/frame_range.h"

using dynref::FrameRange;
using dynref::ParseFrameRange;

TEST_CASE("frame_range: A, A-B and A- parse, LastIn resolves the open end") {
  const FrameRange one = ParseFrameRange("3");
  CHECK(one.first == 3);
  CHECK(one.last == 3);
  const FrameRange two = ParseFrameRange("2-7");
  CHECK(two.first == 2);
  CHECK(two.last == 7);
  CHECK(two.LastIn(8) == 7);
  const FrameRange open = ParseFrameRange("5-");
  CHECK(open.open_ended());
  CHECK(open.LastIn(9) == 8);
  CHECK(FrameRange{}.LastIn(4) == 3);  // default: the whole sequence
}

TEST_CASE("frame_range: bad text and ranges outside the sequence are InputErrors naming the option") {
  for (const std::string text : {"", "-", "-3", "a", "1-b", "1-2-3", "+1", " 1", "1 ", "3-1", "1.5",
                                 "99999999999999999999"}) {
    INFO("text '" << text << "'");
    CHECK_THROWS_AS(ParseFrameRange(text), dynref::InputError);
  }
  try {
    ParseFrameRange("3-1", "--frames");
    FAIL("no throw");
  } catch (const dynref::InputError& e) {
    CHECK(std::string(e.what()).find("--frames") != std::string::npos);
    CHECK(std::string(e.what()).find("3-1") != std::string::npos);
  }
  CHECK_THROWS_AS(ParseFrameRange("2-9").LastIn(9), dynref::InputError);
  CHECK_THROWS_AS(ParseFrameRange("9-").LastIn(9), dynref::InputError);
  CHECK_THROWS_AS(ParseFrameRange("9").LastIn(9), dynref::InputError);
  CHECK(ParseFrameRange("8").LastIn(9) == 8);
}
