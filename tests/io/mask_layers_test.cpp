// io/mask_layers.h: per-frame label images of a method (RUN/masks/) round-trip, and a bad legend
// or a wrong-size PNG is an error naming the file (and line).
#include <catch2/catch.hpp>

#include "core/error.h"
#include "io/mask_layers.h"
#include "test_support.h"

using namespace dynref;

TEST_CASE("mask layers: labels and legend round-trip, empty frames are not written") {
  const std::string dir = test::ScratchDir("mask_layers") + "/masks";
  MaskLayersWriter w({{1, "segmenter", 255, 0, 0}, {4, "dilation", 10, 20, 30}});
  cv::Mat a = cv::Mat::zeros(48, 64, CV_8U);
  a(cv::Rect(3, 4, 10, 5)).setTo(1);
  a(cv::Rect(30, 20, 4, 4)).setTo(4);
  w.Add("100.5", a);
  w.Add("100.6", cv::Mat::zeros(48, 64, CV_8U));
  CHECK(w.Write(dir) == 1);
  REQUIRE(MaskLayersReader::Exists(dir));
  const MaskLayersReader r(dir);
  REQUIRE(r.legend().size() == 2);
  CHECK(r.legend()[1].name == "dilation");
  CHECK(r.legend()[1].b == 30);
  const cv::Mat b = r.Read("100.5", a.size());
  REQUIRE(!b.empty());
  CHECK(cv::countNonZero(a != b) == 0);
  CHECK(r.Read("100.6", a.size()).empty());
  CHECK_THROWS_AS(r.Read("100.5", cv::Size(640, 480)), InputError);
}

TEST_CASE("mask layers: a malformed legend names file and line") {
  const std::string dir = test::ScratchDir("mask_layers_bad");
  struct Case {
    std::string text, fragment;
    int line;
  };
  for (const Case& c : {Case{"dynref-mask-layers 2\n", "expected 'dynref-mask-layers 1'", 1},
                        Case{"dynref-mask-layers 1\n1 a 1 2\n", "expected '<value> <name> <r> <g> <b>'", 2},
                        Case{"dynref-mask-layers 1\n0 a 1 2 3\n", "value must be in 1..255", 2},
                        Case{"dynref-mask-layers 1\n1 a 1 2 300\n", "colour components", 2},
                        Case{"dynref-mask-layers 1\n1 a 1 2 3\n\n1 b 1 2 3\n", "value 1 given twice", 4}}) {
    INFO(c.text);
    test::WriteText(dir + "/legend.txt", c.text);
    try {
      MaskLayersReader r(dir);
      FAIL("no error");
    } catch (const InputError& e) {
      CHECK(e.line() == c.line);
      CHECK(std::string(e.what()).find(c.fragment) != std::string::npos);
      CHECK(std::string(e.what()).find(dir + "/legend.txt") != std::string::npos);
    }
  }
}
