#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "core/stable_sort.h"

TEST_CASE("stable_sort: equal keys keep original order") {
  std::vector<std::pair<int, std::string>> v = {{2, "a"}, {1, "b"}, {2, "c"}, {1, "d"}, {0, "e"}};
  dynref::StableSortBy(v, [](const auto& p) { return p.first; });
  std::string order;
  for (auto& p : v) order += p.second;
  CHECK(order == "ebdac");
}

TEST_CASE("stable_sort: StableOrder returns index permutation") {
  std::vector<double> keys = {0.5, 0.1, 0.5, 0.1};
  auto idx = dynref::StableOrder(keys.size(), [&](size_t i) { return keys[i]; });
  CHECK(idx == std::vector<size_t>{1, 3, 0, 2});
}
