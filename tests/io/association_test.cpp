// Association on hand-made stamp lists (binary-exact values, so ties are real ties).
#include <catch2/catch.hpp>

#include "core/error.h"
#include "io/association.h"

using dynref::AssociateEvo;
using dynref::AssociateTum;
using dynref::StampMatch;

namespace {
std::vector<std::pair<size_t, size_t>> Pairs(const std::vector<StampMatch>& m) {
  std::vector<std::pair<size_t, size_t>> out;
  for (const auto& x : m) out.emplace_back(x.first, x.second);
  return out;
}
using P = std::vector<std::pair<size_t, size_t>>;
}  // namespace

TEST_CASE("association: tum greedy one-to-one with gaps") {
  // 2.0 has no partner (gap), 4.0's partner is beyond max_difference.
  const std::vector<double> a = {1.0, 2.0, 3.0, 4.0};
  const std::vector<double> b = {1.0078125, 2.5, 2.9921875, 4.03125};
  CHECK(Pairs(AssociateTum(a, b, 0.02)) == P{{0, 0}, {2, 2}});
  CHECK(AssociateTum({}, b, 0.02).empty());
  CHECK(AssociateTum(a, {}, 0.02).empty());
}

TEST_CASE("association: tum ties broken as python sorts (diff, a, b)") {
  // Both a=0 and a=0.25 are 0.125 from b=0.125: the smaller a wins; a=0.25 then takes b=0.5.
  CHECK(Pairs(AssociateTum({0.0, 0.25}, {0.125, 0.5}, 1.0)) == P{{0, 0}, {1, 1}});
  // a=1 is 0.125 from both b=0.875 and b=1.125: the smaller b wins, b=1.125 stays unmatched.
  CHECK(Pairs(AssociateTum({0.0, 1.0}, {0.875, 1.125}, 0.5)) == P{{1, 0}});
  // Greedy, not per-row nearest: the globally smallest difference is taken first.
  // a=1.0 prefers b=1.25 (0.25) but b=1.25 is closer (0.125) to a=1.375, so a=1.0 gets b=0.625.
  CHECK(Pairs(AssociateTum({1.0, 1.375}, {0.625, 1.25}, 0.5)) == P{{0, 0}, {1, 1}});
  CHECK(Pairs(AssociateTum({1.0, 1.375}, {1.25}, 0.5)) == P{{1, 0}});
}

TEST_CASE("association: bounds are strict for tum, inclusive for evo") {
  CHECK(AssociateTum({0.0}, {0.5}, 0.5).empty());
  CHECK(Pairs(AssociateEvo({0.0}, {0.5}, 0.5)) == P{{0, 0}});
  CHECK(Pairs(AssociateTum({0.0}, {0.5}, 0.5000001)) == P{{0, 0}});
}

TEST_CASE("association: evo nearest neighbour from the shorter list, not one-to-one") {
  // Equal sizes: evo's first_longer is true, so the second list is walked; both of its stamps
  // pick a=1 (the first index on the tie at 1.125 would be a=1 too).
  CHECK(Pairs(AssociateEvo({0.0, 1.0}, {0.875, 1.125}, 0.5)) == P{{1, 0}, {1, 1}});
  // First shorter: the first list is walked; b ties (0.5 from 0.0 and 1.0) go to the first index.
  CHECK(Pairs(AssociateEvo({0.5}, {0.0, 1.0, 2.0}, 0.5)) == P{{0, 0}});
  // Gaps: stamps without a neighbour within max_diff are skipped.
  CHECK(Pairs(AssociateEvo({0.0, 5.0, 10.0}, {0.0, 0.25, 9.75, 10.0, 20.0}, 0.25)) ==
        P{{0, 0}, {2, 3}});
  // Duplicate stamps in the longer list: argmin picks the first of them.
  CHECK(Pairs(AssociateEvo({1.0}, {0.0, 1.0, 1.0}, 0.1)) == P{{0, 1}});
}

TEST_CASE("association: a max difference giving too many candidates is refused") {
  std::vector<double> a(5000), b(5000);
  for (int i = 0; i < 5000; ++i) a[i] = b[i] = i;
  CHECK(AssociateTum(a, b, 0.5).size() == 5000);
  CHECK_THROWS_AS(AssociateTum(a, b, 1e6), dynref::InputError);
}

TEST_CASE("association: dispatcher and names") {
  using dynref::AssociationKind;
  CHECK(std::string(dynref::AssociationKindName(AssociationKind::kTum)) == "tum");
  CHECK(std::string(dynref::AssociationKindName(AssociationKind::kEvo)) == "evo");
  CHECK(Pairs(dynref::Associate(AssociationKind::kEvo, {0.0, 1.0}, {0.875, 1.125}, 0.5)).size() == 2);
  CHECK(Pairs(dynref::Associate(AssociationKind::kTum, {0.0, 1.0}, {0.875, 1.125}, 0.5)).size() == 1);
}
