// Sorting helpers that never depend on the input order of equal elements
// (std::stable_sort plus an explicit tie-break on the original index).
#pragma once
#include <algorithm>
#include <cstddef>
#include <numeric>
#include <vector>

namespace dynref {

// Indices 0..n-1 ordered by key(i) ascending; equal keys keep ascending index order.
template <typename KeyFn>
std::vector<size_t> StableOrder(size_t n, KeyFn key) {
  std::vector<size_t> idx(n);
  std::iota(idx.begin(), idx.end(), size_t{0});
  std::stable_sort(idx.begin(), idx.end(), [&](size_t a, size_t b) {
    const auto ka = key(a);
    const auto kb = key(b);
    if (ka < kb) return true;
    if (kb < ka) return false;
    return a < b;
  });
  return idx;
}

// Sorts v by key(element), ties broken by original position.
template <typename T, typename KeyFn>
void StableSortBy(std::vector<T>& v, KeyFn key) {
  const std::vector<size_t> order = StableOrder(v.size(), [&](size_t i) { return key(v[i]); });
  std::vector<T> out;
  out.reserve(v.size());
  for (size_t i : order) out.push_back(std::move(v[i]));
  v = std::move(out);
}

}  // namespace dynref
