// place: vocabulary files (ORBvoc.txt text format and dynref's), Transform, scores.
#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "core/error.h"
#include "features/orb_extractor.h"
#include "place/vocabulary.h"
#include "test_support.h"
#include "io/image_file.h"

using namespace dynref;
using namespace dynref::place;

namespace {

std::string Bytes(int v) {
  std::string s;
  for (int i = 0; i < kDescriptorBytes; ++i) s += std::to_string(v) + " ";
  return s;
}

// k = 2, L = 2, TF-IDF, L1, in ORB-SLAM2's text format (saveToTextFile's spacing). Words:
// node 3 (0x00, w 0.5) -> word 0, node 4 (0x0f, 1.25) -> 1, node 5 (0xf0, 2) -> 2, node 6 (0xff, 0, stopped) -> 3.
std::string TinyOrbVoc() {
  return "2 2  0 0\n"
         "0 0 " + Bytes(0x00) + " 0\n"
         "0 0 " + Bytes(0xff) + " 0\n"
         "1 1 " + Bytes(0x00) + " 0.5\n"
         "1 1 " + Bytes(0x0f) + " 1.25\n"
         "2 1 " + Bytes(0xf0) + " 2\n"
         "2 1 " + Bytes(0xff) + " 0\n";
}

cv::Mat Rows(const std::vector<int>& fill) {
  cv::Mat m(static_cast<int>(fill.size()), kDescriptorBytes, CV_8U);
  for (int r = 0; r < m.rows; ++r) m.row(r).setTo(fill[r]);
  return m;
}

// d_a 0x01 -> word 0, d_b 0x0e -> word 1, d_c 0xf1 -> word 2, d_d 0xfe -> word 3 (stopped), d_e 0x00 -> word 0.
cv::Mat TinyDescriptors() { return Rows({0x01, 0x0e, 0xf1, 0xfe, 0x00}); }

void ExpectInputError(const std::string& text, bool orb_format, const std::string& fragment) {
  try {
    if (orb_format)
      Vocabulary::ParseOrbSlamText(text, "voc.txt");
    else
      Vocabulary::ParseDynref(text, "voc.txt");
    FAIL("no InputError, expected " << fragment);
  } catch (const InputError& e) {
    CHECK_THAT(e.what(), Catch::Contains(fragment));
  }
}

}  // namespace

TEST_CASE("ORBvoc.txt text format gives the same BoW vectors as dynref's format") {
  const std::string dir = test::ScratchDir("place_orbvoc");
  const std::string orb_path = test::WriteText(dir + "/ORBvoc.txt", TinyOrbVoc());
  const Vocabulary orb = Vocabulary::Load(orb_path);  // sniffed: no dynref header
  REQUIRE(orb.k() == 2);
  REQUIRE(orb.levels() == 2);
  REQUIRE(orb.weighting() == Weighting::kTfIdf);
  REQUIRE(orb.scoring() == Scoring::kL1);
  REQUIRE(orb.size() == 4);
  REQUIRE(orb.nodes().size() == 7);

  orb.Save(dir + "/voc.dynref");
  const Vocabulary own = Vocabulary::Load(dir + "/voc.dynref");
  CHECK(own.Serialize() == orb.Serialize());
  // Back to ORB-SLAM2's text: byte-identical to the file the test wrote.
  CHECK(orb.SerializeOrbSlamText() == TinyOrbVoc());

  for (int up = 0; up <= 3; ++up) {
    BowVector b1, b2;
    FeatureVector f1, f2;
    orb.Transform(TinyDescriptors(), &b1, &f1, up);
    own.Transform(TinyDescriptors(), &b2, &f2, up);
    CHECK(b1 == b2);
    CHECK(f1 == f2);
  }

  // Hand-computed TF-IDF, L1-normalised: word 0 twice (0.5 each), word 1 (1.25), word 2 (2); word 3 is stopped.
  BowVector bow;
  FeatureVector fv;
  orb.Transform(TinyDescriptors(), &bow, &fv, 1);
  REQUIRE(bow.size() == 3);
  CHECK(bow.at(0) == Approx(1.0 / 4.25).epsilon(1e-15));
  CHECK(bow.at(1) == Approx(1.25 / 4.25).epsilon(1e-15));
  CHECK(bow.at(2) == Approx(2.0 / 4.25).epsilon(1e-15));
  // levels_up 1 -> level-1 nodes 1 (0x00 side) and 2 (0xff side); the stopped feature 3 is absent.
  CHECK(fv == FeatureVector{{1, {0, 1, 4}}, {2, {2}}});
  orb.Transform(TinyDescriptors(), &bow, &fv, 0);
  CHECK(fv == FeatureVector{{3, {0, 4}}, {4, {1}}, {5, {2}}});
  orb.Transform(TinyDescriptors(), &bow, &fv, 2);  // level 0 = root
  CHECK(fv == FeatureVector{{0, {0, 1, 2, 4}}});

  CHECK(orb.ParentNode(2, 1) == 2);
  CHECK(orb.ParentNode(2, 5) == 0);
  CHECK(orb.WordsFromNode(1) == std::vector<WordId>{0, 1});
  CHECK(orb.WordsFromNode(6) == std::vector<WordId>{3});
}

TEST_CASE("L1 score is 1 - 0.5 |v - w|_1 (DBoW2 L1Scoring)") {
  const BowVector v{{1, 0.5}, {2, 0.5}};
  const BowVector w{{2, 0.25}, {3, 0.75}};
  // |v - w|_1 = 0.5 + 0.25 + 0.75 = 1.5 -> 1 - 0.75 = 0.25
  CHECK(Score(Scoring::kL1, v, w) == Approx(0.25).epsilon(1e-15));
  CHECK(Score(Scoring::kL1, v, v) == Approx(1.0).epsilon(1e-15));
  CHECK(Score(Scoring::kL1, v, BowVector{{7, 1.0}}) == 0.0);
  CHECK(Score(Scoring::kL1, v, w) == Score(Scoring::kL1, w, v));
  // Dot product and L2 on the same vectors: sum v_i w_i = 0.125.
  CHECK(Score(Scoring::kDotProduct, v, w) == Approx(0.125));
  CHECK(Score(Scoring::kL2, v, w) == Approx(1.0 - std::sqrt(0.875)));
  BowVector n{{4, 2.0}, {9, 6.0}};
  Normalize(&n, Norm::kL1);
  CHECK(n.at(4) == 0.25);
  CHECK(n.at(9) == 0.75);
}

TEST_CASE("bad vocabulary files are InputErrors naming file and line") {
  std::string t = TinyOrbVoc();
  ExpectInputError("2 2 0\n", true, "voc.txt:1:");
  ExpectInputError("1 2 0 0\n0 1 " + Bytes(1) + " 1\n", true, "voc.txt:1:");    // k = 1
  ExpectInputError("2 2 7 0\n", true, "voc.txt:1: scoring type 7");
  ExpectInputError("2 2 0 0\n0 1 " + Bytes(300) + " 1\n", true, "voc.txt:2: descriptor byte 0 = 300");
  ExpectInputError("2 2 0 0\n0 1 " + Bytes(1) + "\n", true, "voc.txt:2:");      // weight missing
  ExpectInputError("2 2 0 0\n0 2 " + Bytes(1) + " 1\n", true, "voc.txt:2: leaf flag");
  ExpectInputError("2 2 0 0\n1 1 " + Bytes(1) + " 1\n", true, "voc.txt:2: node 1 names parent 1");
  ExpectInputError("2 2 0 0\n0 1 " + Bytes(1) + " x\n", true, "voc.txt:2: weight 'x'");
  ExpectInputError("2 2 0 0\n0 0 " + Bytes(1) + " 0\n", true, "voc.txt:2: node 1 is marked inner");
  ExpectInputError("2 2 0 0\n0 1 " + Bytes(1) + " 1\n1 1 " + Bytes(1) + " 1\n", true, "voc.txt:3:");  // child of a leaf
  ExpectInputError("\xEF\xBB\xBF" + t, true, "voc.txt:1:");

  const Vocabulary v = Vocabulary::ParseOrbSlamText(t, "voc.txt");
  const std::string good = v.Serialize();
  CHECK_NOTHROW(Vocabulary::ParseDynref(good, "voc.txt"));
  std::string changed = good;
  changed[good.find("0.5")] = '1';  // a weight changed: the checksum no longer matches
  ExpectInputError(changed, false, "voc.txt:9: checksum");
  ExpectInputError(good.substr(0, good.find("end")), false, "missing the final 'end crc32c'");
  ExpectInputError("dynref-vocabulary 2\n", false, "voc.txt:1: format version 2");
  std::string hdr = good;
  hdr.replace(hdr.find("tf-idf"), 6, "tfidf!");
  ExpectInputError(hdr, false, "voc.txt:2: unknown weighting");
  ExpectInputError(good + "0 1 00 1\n", false, "voc.txt:10: text after");

  try {
    Vocabulary::Load(test::ScratchDir("place_missing") + "/nope.txt");
    FAIL("loaded a missing file");
  } catch (const InputError& e) {
    CHECK_THAT(e.what(), Catch::Contains("nope.txt"));
  }
}

TEST_CASE("float descriptors are refused (no float vocabulary)") {
  const Vocabulary v = Vocabulary::ParseOrbSlamText(TinyOrbVoc(), "voc.txt");
  BowVector b;
  CHECK_THROWS_AS(v.Transform(cv::Mat(3, 128, CV_32F, cv::Scalar(0.1)), &b), std::invalid_argument);
  CHECK_THROWS_AS(v.Transform(cv::Mat(3, 16, CV_8U, cv::Scalar(1)), &b), std::invalid_argument);
}

TEST_CASE("the embedded default vocabulary loads and scores a real frame") {
  const Vocabulary& v = Vocabulary::Default();
  CHECK(v.k() == 10);
  CHECK(v.levels() == 4);
  CHECK(v.weighting() == Weighting::kTfIdf);
  CHECK(v.scoring() == Scoring::kL1);
  CHECK(v.size() > 1000);
  // Same bytes as the shipped file.
  CHECK(v.Serialize() == test::ReadFileBytes(test::SourcePath("models/vocab/dynref_orb_k10_l4.txt")));

  const cv::Mat bgr = dynref::ImageRead(test::SourcePath("datasets/real/tum_fr1_desk_9frames/rgb/1305031453.359684.png"));
  REQUIRE(!bgr.empty());
  cv::Mat grey;
  cv::cvtColor(bgr, grey, cv::COLOR_RGB2GRAY);
  features::OrbExtractor ex(features::OrbOptions{});
  std::vector<cv::KeyPoint> keys;
  cv::Mat desc;
  ex.Extract(grey, &keys, &desc);
  BowVector bow;
  FeatureVector fv;
  v.Transform(desc, &bow, &fv, v.levels() - 2);
  REQUIRE(bow.size() > 100);
  double sum = 0;
  for (const auto& [w, x] : bow) sum += x;
  CHECK(sum == Approx(1.0).epsilon(1e-12));
  CHECK(v.Score(bow, bow) == Approx(1.0).epsilon(1e-12));
  size_t features = 0;
  for (const auto& [n, idx] : fv) features += idx.size();
  CHECK(features <= static_cast<size_t>(desc.rows));
  CHECK(features > static_cast<size_t>(desc.rows) / 2);
}
