// DBoW2 BowVector / FeatureVector / ScoringObject equivalents (see bow.h).
#include "place/bow.h"

#include <cfloat>
#include <cmath>

namespace dynref::place {
namespace {

const char* const kWeightingNames[] = {"tf-idf", "tf", "idf", "binary"};
const char* const kScoringNames[] = {"l1", "l2", "chi-square", "kl", "bhattacharyya", "dot-product"};

// Calls f(v_i, w_i) for every word the two vectors share, in ascending word id.
template <typename F>
void ForShared(const BowVector& a, const BowVector& b, F f) {
  auto ia = a.begin(), ib = b.begin();
  while (ia != a.end() && ib != b.end()) {
    if (ia->first == ib->first) {
      f(ia->second, ib->second);
      ++ia;
      ++ib;
    } else if (ia->first < ib->first) {
      ia = a.lower_bound(ib->first);
    } else {
      ib = b.lower_bound(ia->first);
    }
  }
}

}  // namespace

std::string WeightingName(Weighting w) { return kWeightingNames[static_cast<int>(w)]; }
std::string ScoringName(Scoring s) { return kScoringNames[static_cast<int>(s)]; }

bool ParseWeighting(const std::string& name, Weighting* out) {
  for (int i = 0; i < 4; ++i)
    if (name == kWeightingNames[i]) {
      *out = static_cast<Weighting>(i);
      return true;
    }
  return false;
}

bool ParseScoring(const std::string& name, Scoring* out) {
  for (int i = 0; i < 6; ++i)
    if (name == kScoringNames[i]) {
      *out = static_cast<Scoring>(i);
      return true;
    }
  return false;
}

bool MustNormalize(Scoring s, Norm* norm) {
  switch (s) {
    case Scoring::kL2:
      *norm = Norm::kL2;
      return true;
    case Scoring::kDotProduct:
      *norm = Norm::kL1;
      return false;
    default:  // L1, chi-square, KL, Bhattacharyya
      *norm = Norm::kL1;
      return true;
  }
}

void AddWeight(BowVector* v, WordId id, double w) {
  auto it = v->lower_bound(id);
  if (it != v->end() && it->first == id)
    it->second += w;
  else
    v->emplace_hint(it, id, w);
}

void AddIfNotExist(BowVector* v, WordId id, double w) {
  auto it = v->lower_bound(id);
  if (it == v->end() || it->first != id) v->emplace_hint(it, id, w);
}

void Normalize(BowVector* v, Norm norm) {
  double n = 0.0;
  if (norm == Norm::kL1) {
    for (const auto& [id, w] : *v) n += std::fabs(w);
  } else {
    for (const auto& [id, w] : *v) n += w * w;
    n = std::sqrt(n);
  }
  if (n > 0.0)
    for (auto& [id, w] : *v) w /= n;
}

void AddFeature(FeatureVector* fv, NodeId node, uint32_t feature_index) {
  (*fv)[node].push_back(feature_index);
}

double Score(Scoring s, const BowVector& a, const BowVector& b) {
  double score = 0.0;
  switch (s) {
    case Scoring::kL1:
      ForShared(a, b, [&](double vi, double wi) { score += std::fabs(vi - wi) - std::fabs(vi) - std::fabs(wi); });
      return -score / 2.0;
    case Scoring::kL2:
      ForShared(a, b, [&](double vi, double wi) { score += vi * wi; });
      return score >= 1 ? 1.0 : 1.0 - std::sqrt(1.0 - score);
    case Scoring::kChiSquare:
      ForShared(a, b, [&](double vi, double wi) {
        if (vi + wi != 0.0) score += vi * wi / (vi + wi);
      });
      return 2.0 * score;
    case Scoring::kKl: {
      // Every word of a counts; a word missing from b stands for log(DBL_EPSILON) (DBoW2 LOG_EPS).
      const double log_eps = std::log(DBL_EPSILON);
      auto ia = a.begin(), ib = b.begin();
      while (ia != a.end() && ib != b.end()) {
        const double vi = ia->second, wi = ib->second;
        if (ia->first == ib->first) {
          if (vi != 0 && wi != 0) score += vi * std::log(vi / wi);
          ++ia;
          ++ib;
        } else if (ia->first < ib->first) {
          score += vi * (std::log(vi) - log_eps);
          ++ia;
        } else {
          ib = b.lower_bound(ia->first);
        }
      }
      for (; ia != a.end(); ++ia)
        if (ia->second != 0) score += ia->second * (std::log(ia->second) - log_eps);
      return score;
    }
    case Scoring::kBhattacharyya:
      ForShared(a, b, [&](double vi, double wi) { score += std::sqrt(vi * wi); });
      return score;
    case Scoring::kDotProduct:
      ForShared(a, b, [&](double vi, double wi) { score += vi * wi; });
      return score;
  }
  return score;
}

}  // namespace dynref::place
