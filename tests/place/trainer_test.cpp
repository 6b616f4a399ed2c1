// place: the deterministic vocabulary trainer (hierarchical k-medians, IDF) and `dynref vocab train`.
#include <catch2/catch.hpp>
#include <cmath>
#include <set>

#include "core/error.h"
#include "core/rng.h"
#include "place/trainer.h"
#include "place/training_set.h"
#include "test_support.h"

using namespace dynref;
using namespace dynref::place;

namespace {

// `images` images of `per_image` descriptors: noisy copies (8 flipped bits) of 12 prototypes.
std::vector<std::vector<Descriptor>> SyntheticImages(int images, int per_image, uint64_t seed) {
  Rng rng(seed, "test.place.descriptors");
  std::vector<Descriptor> protos(12);
  for (Descriptor& p : protos)
    for (uint8_t& b : p) b = static_cast<uint8_t>(rng.UniformInt(0, 255));
  std::vector<std::vector<Descriptor>> out(images);
  for (auto& img : out)
    for (int i = 0; i < per_image; ++i) {
      Descriptor d = protos[rng.UniformInt(0, 11)];
      for (int f = 0; f < 8; ++f) {
        const int bit = static_cast<int>(rng.UniformInt(0, 255));
        d[bit / 8] ^= static_cast<uint8_t>(1 << (bit % 8));
      }
      img.push_back(d);
    }
  return out;
}

const char* const kFixture = "tests/place/data/fr1_desk_k6_l3.txt";

TrainingSetOptions Fr1DeskSet() {
  TrainingSetOptions o;
  o.sequences = {test::SourcePath("datasets/real/tum_fr1_desk_9frames")};
  o.n_features = 300;
  return o;
}

}  // namespace

TEST_CASE("training is deterministic and the seed matters") {
  const auto images = SyntheticImages(20, 60, 7);
  TrainOptions o;
  o.k = 4;
  o.levels = 3;
  const std::string a = TrainVocabulary(images, o).Serialize();
  const std::string b = TrainVocabulary(images, o).Serialize();
  CHECK(a == b);
  o.seed = 2;
  CHECK(TrainVocabulary(images, o).Serialize() != a);
}

TEST_CASE("trained weights are ln(N / N_i) and the tree obeys k and L") {
  const auto images = SyntheticImages(15, 40, 3);
  TrainOptions o;
  o.k = 3;
  o.levels = 3;
  const Vocabulary v = TrainVocabulary(images, o);
  REQUIRE(!v.empty());
  CHECK(v.MaxDepth() <= 3);
  for (const VocabularyNode& n : v.nodes()) CHECK(n.children.size() <= 3u);
  std::vector<std::set<size_t>> docs(v.size());
  for (size_t i = 0; i < images.size(); ++i)
    for (const Descriptor& d : images[i]) docs[v.Transform(d.data())].insert(i);
  for (WordId w = 0; w < v.size(); ++w) {
    const double expected = docs[w].empty() ? 0.0 : std::log(15.0 / static_cast<double>(docs[w].size()));
    CHECK(v.nodes()[v.word_node(w)].weight == expected);
  }
}

TEST_CASE("few descriptors give one leaf each, groups get majority-bit centroids", "[cli]") {
  // <= k descriptors: one child per descriptor (DBoW2 HKmeansStep's trivial case).
  Descriptor x{}, y{};
  y.fill(0xff);
  TrainOptions o;
  o.k = 3;
  o.levels = 2;
  const Vocabulary v = TrainVocabulary({{x}, {y}}, o);
  REQUIRE(v.size() == 2);
  CHECK(v.nodes()[1].descriptor == x);
  CHECK(v.nodes()[2].descriptor == y);
  CHECK(v.nodes()[1].weight == Approx(std::log(2.0)));

  // Two tight groups, k = 2, L = 1: each centroid is the majority of its group.
  Descriptor a1{}, a2{}, a3{}, b1, b2, b3;
  a2[0] = 0x01;
  a3[0] = 0x03;  // majority of {00, 01, 03}: bit 0 set twice -> 0x01
  b1.fill(0xff);
  b2 = b1;
  b3 = b1;
  b2[5] = 0x7f;
  o.k = 2;
  o.levels = 1;
  const Vocabulary g = TrainVocabulary({{a1, a2, a3}, {b1, b2, b3}}, o);
  REQUIRE(g.size() == 2);
  std::set<std::vector<uint8_t>> centroids;
  for (NodeId n : g.nodes()[0].children)
    centroids.insert(std::vector<uint8_t>(g.nodes()[n].descriptor.begin(), g.nodes()[n].descriptor.end()));
  Descriptor ca{};
  ca[0] = 0x01;
  CHECK(centroids.count(std::vector<uint8_t>(ca.begin(), ca.end())) == 1);
  CHECK(centroids.count(std::vector<uint8_t>(b1.begin(), b1.end())) == 1);
}

TEST_CASE("bad training options are InputErrors naming the option") {
  TrainOptions o;
  o.k = 1;
  CHECK_THROWS_WITH(o.Check(), Catch::Contains("--k"));
  o = TrainOptions{};
  o.levels = 11;
  CHECK_THROWS_WITH(o.Check(), Catch::Contains("--levels"));
  CHECK_THROWS_AS(TrainVocabulary({}, TrainOptions{}), InputError);
  TrainingSetOptions s;
  CHECK_THROWS_WITH(s.Check(), Catch::Contains("--sequence"));
}

TEST_CASE("retraining on the bundled real frames reproduces the committed fixture") {
  const TrainingSet set = ExtractTrainingSet(Fr1DeskSet());
  REQUIRE(set.images.size() == 9);
  TrainOptions o;
  o.k = 6;
  o.levels = 3;
  const std::string bytes = TrainVocabulary(set.images, o).Serialize();
  CHECK(bytes == TrainVocabulary(set.images, o).Serialize());
  CHECK(bytes == test::ReadFileBytes(test::SourcePath(kFixture)));
}

TEST_CASE("dynref vocab train end to end is byte-identical and matches the fixture", "[cli]") {
  const std::string dir = test::ScratchDir("place_vocab_train");
  const std::string args = "vocab train --sequence " + test::Quote(test::SourcePath("datasets/real/tum_fr1_desk_9frames")) +
                           " --k 6 --levels 3 --features 300 --out ";
  const auto r1 = test::RunDynref(args + test::Quote(dir + "/a.txt"));
  REQUIRE(r1.exit_code == 0);
  const auto r2 = test::RunDynref(args + test::Quote(dir + "/b.txt"));
  REQUIRE(r2.exit_code == 0);
  const std::string a = test::ReadFileBytes(dir + "/a.txt");
  CHECK(!a.empty());
  CHECK(a == test::ReadFileBytes(dir + "/b.txt"));
  CHECK(a == test::ReadFileBytes(test::SourcePath(kFixture)));
  const auto info = test::RunDynref("vocab info " + test::Quote(dir + "/a.txt"));
  CHECK(info.exit_code == 0);
  CHECK_THAT(info.output, Catch::Contains("k 6") && Catch::Contains("levels 3"));
  // ORB-SLAM2 text export loads back with the same words.
  REQUIRE(test::RunDynref("vocab convert " + test::Quote(dir + "/a.txt") + " --format orbslam --out " +
                          test::Quote(dir + "/orb.txt")).exit_code == 0);
  const auto info2 = test::RunDynref("vocab info " + test::Quote(dir + "/orb.txt"));
  CHECK_THAT(info2.output, Catch::Contains("words " + std::to_string(Vocabulary::Load(dir + "/a.txt").size())));
  test::ExpectBadInput("vocab train --sequence " + test::Quote(dir + "/none") + " --out " + test::Quote(dir + "/c.txt"),
                       "none");
  test::ExpectBadInput("vocab info " + test::Quote(dir + "/none.txt"), "none.txt");
}

TEST_CASE("the default vocabulary's recipe at small size retrains byte-identically end to end", "[cli]") {
  // models/vocab/make_default.sh in miniature: synthetic presets of two seeds plus the real frames.
  const std::string dir = test::ScratchDir("place_vocab_recipe");
  std::string seqs;
  for (const char* p : {"walking_xyz"})
    for (int seed : {1, 2}) {
      const std::string out = dir + "/" + p + "_s" + std::to_string(seed);
      REQUIRE(test::RunDynref(std::string("synth --preset ") + p + " --seed " + std::to_string(seed) +
                              " --frames 3 --out " + test::Quote(out)).exit_code == 0);
      seqs += " --sequence " + test::Quote(out);
    }
  seqs += " --sequence " + test::Quote(test::SourcePath("datasets/real/tum_fr1_desk_9frames"));
  const std::string args = "vocab train" + seqs + " --k 5 --levels 2 --seed 1 --every 1 --features 200 --out ";
  REQUIRE(test::RunDynref(args + test::Quote(dir + "/a.txt")).exit_code == 0);
  REQUIRE(test::RunDynref(args + test::Quote(dir + "/b.txt")).exit_code == 0);
  const std::string a = test::ReadFileBytes(dir + "/a.txt");
  CHECK(a == test::ReadFileBytes(dir + "/b.txt"));
  const Vocabulary v = Vocabulary::ParseDynref(a, "a.txt");
  CHECK(v.size() > 10);
  CHECK(v.MaxDepth() == 2);
}
