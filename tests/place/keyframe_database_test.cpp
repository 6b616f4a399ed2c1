// place: ORB-SLAM2's KeyFrameDatabase candidate searches on a hand-made set.
#include <catch2/catch.hpp>
#include <map>

#include "place/keyframe_database.h"
#include "place/vocabulary.h"

using namespace dynref::place;

namespace {

// Only the scoring type (L1) of the vocabulary matters to the database.
Vocabulary L1Vocabulary() {
  std::vector<NodeRecord> nodes(2);
  nodes[0].leaf = nodes[1].leaf = true;
  nodes[1].descriptor.fill(0xff);
  return Vocabulary::FromNodes(2, 1, Weighting::kTfIdf, Scoring::kL1, nodes);
}

BowVector Uniform(std::initializer_list<WordId> words, double w) {
  BowVector v;
  for (WordId id : words) v[id] = w;
  return v;
}

// Query q: words 1..5 at 0.2.  L1 scores with q (shared words only):
//   A (1): words 1..5 at 0.2                  shares 5, score 1
//   B (2): words 1..5 at 0.16, word 6 at 0.2  shares 5, score 1 - 0.5 * (5 * 0.04 + 0.2) = 0.8
//   C (3): words 1..5 at 0.05, word 7 at 0.75 shares 5, score 1 - 0.5 * (5 * 0.15 + 0.75) = 0.25
//   D (4): words 1..4 at 0.25                 shares 4 <= int(0.8 * 5): not scored
//   E (5): word 8                             shares nothing
struct Fixture {
  Vocabulary voc = L1Vocabulary();
  KeyFrameDatabase db{voc};
  BowVector q = Uniform({1, 2, 3, 4, 5}, 0.2);
  std::map<KeyFrameId, std::vector<KeyFrameId>> covis{{1, {4}}, {2, {3, 1}}, {3, {2}}, {4, {1}}};
  CovisibleFn covisible = [this](KeyFrameId kf, int n) {
    std::vector<KeyFrameId> out = covis.count(kf) ? covis.at(kf) : std::vector<KeyFrameId>{};
    if (static_cast<int>(out.size()) > n) out.resize(n);
    return out;
  };
  Fixture() {
    BowVector b = Uniform({1, 2, 3, 4, 5}, 0.16);
    b[6] = 0.2;
    BowVector c = Uniform({1, 2, 3, 4, 5}, 0.05);
    c[7] = 0.75;
    // Added out of id order on purpose: results must not depend on it.
    db.Add(5, Uniform({8}, 1.0));
    db.Add(3, c);
    db.Add(1, Uniform({1, 2, 3, 4, 5}, 0.2));
    db.Add(4, Uniform({1, 2, 3, 4}, 0.25));
    db.Add(2, b);
  }
};

}  // namespace

TEST_CASE("relocalisation candidates as ORB-SLAM2 (0.8 shared words, 0.75 group score)") {
  Fixture f;
  CHECK(f.db.size() == 5);
  CHECK(f.db.KeyFramesWithWord(1) == std::vector<KeyFrameId>{1, 2, 3, 4});
  PlaceQueryReport rep;
  const auto cands = f.db.DetectRelocalizationCandidates(f.q, f.covisible, &rep);
  CHECK(rep.sharing == std::vector<KeyFrameId>{1, 2, 3, 4});
  CHECK(rep.max_shared_words == 5);
  CHECK(rep.min_shared_words == 4);
  REQUIRE(rep.scored.size() == 3);
  CHECK(rep.scored[0].score == Approx(1.0f));
  CHECK(rep.scored[1].score == Approx(0.8f));
  CHECK(rep.scored[2].score == Approx(0.25f));
  // Groups: A = 1 (neighbour D is not scored); B = 0.8 + C 0.25 + A 1 = 2.05, best A; C = 0.25 + B 0.8 = 1.05, best B.
  CHECK(rep.scored[0].group_score == Approx(1.0f));
  CHECK(rep.scored[1].group_score == Approx(2.05f));
  CHECK(rep.scored[1].group_best == 1);
  CHECK(rep.scored[2].group_score == Approx(1.05f));
  CHECK(rep.scored[2].group_best == 2);
  CHECK(rep.best_group_score == Approx(2.05f));
  // Only B's group passes 0.75 * 2.05; its best member is A.
  CHECK(cands == std::vector<KeyFrameId>{1});
  CHECK(rep.candidates == cands);

  // Without covisibility every scored keyframe is its own group: 1 and 0.8 pass 0.75, 0.25 does not.
  const CovisibleFn none = [](KeyFrameId, int) { return std::vector<KeyFrameId>{}; };
  CHECK(f.db.DetectRelocalizationCandidates(f.q, none) == std::vector<KeyFrameId>{1, 2});
  CHECK(f.db.DetectRelocalizationCandidates(Uniform({9}, 1.0), none).empty());
}

TEST_CASE("loop candidates skip connected keyframes and need min_score") {
  Fixture f;
  PlaceQueryReport rep;
  // Query keyframe 100 connected to A: B and C are scored (C below min_score 0.3 but its score still
  // counts in B's group), D shares too few words.
  const auto cands = f.db.DetectLoopCandidates(100, f.q, {1}, 0.3f, f.covisible, &rep);
  CHECK(rep.sharing == std::vector<KeyFrameId>{2, 3, 4});
  CHECK(rep.min_shared_words == 4);
  REQUIRE(rep.scored.size() == 1);
  CHECK(rep.scored[0].id == 2);
  CHECK(rep.scored[0].group_score == Approx(1.05f));  // 0.8 + C 0.25 (A is connected: never counted)
  CHECK(cands == std::vector<KeyFrameId>{2});

  // The query itself in the database is not its own candidate.
  f.db.Add(100, f.q);
  CHECK(f.db.DetectLoopCandidates(100, f.q, {1}, 0.3f, f.covisible) == std::vector<KeyFrameId>{2});
  f.db.Erase(100);

  // Erasing B leaves C, below min_score: no candidate.
  f.db.Erase(2);
  CHECK(f.db.KeyFramesWithWord(6).empty());
  CHECK(f.db.DetectLoopCandidates(100, f.q, {1}, 0.3f, f.covisible).empty());
  f.db.Clear();
  CHECK(f.db.size() == 0);
  CHECK(f.db.DetectRelocalizationCandidates(f.q, f.covisible).empty());
}
