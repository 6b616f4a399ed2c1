// Bag-of-words vectors and their scores, as DBoW2 (Galvez-Lopez & Tardos, "Bags of Binary Words
// for Fast Place Recognition in Image Sequences", T-RO 2012; the library ORB-SLAM2 ships in
// Thirdparty/DBoW2): BowVector.cpp (addWeight, addIfNotExist, normalize), FeatureVector.cpp
// (addFeature) and ScoringObject.cpp (the six scores). Both vectors are ordered maps keyed by id,
// so every iteration over them is in ascending id order (deterministic).
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace dynref::place {

using WordId = uint32_t;  // index of a leaf among the vocabulary's words (DBoW2 WordId)
using NodeId = uint32_t;  // index of a tree node, 0 = root (DBoW2 NodeId)

// Word id -> weight (DBoW2 BowVector; WordValue is double there too).
using BowVector = std::map<WordId, double>;
// Node id -> indices of the features under that node, ascending (DBoW2 FeatureVector).
using FeatureVector = std::map<NodeId, std::vector<uint32_t>>;

// The numbers are the ones written in ORBvoc.txt's header (DBoW2 WeightingType, ScoringType).
enum class Weighting : int { kTfIdf = 0, kTf = 1, kIdf = 2, kBinary = 3 };
enum class Scoring : int { kL1 = 0, kL2 = 1, kChiSquare = 2, kKl = 3, kBhattacharyya = 4, kDotProduct = 5 };
enum class Norm : int { kL1, kL2 };

std::string WeightingName(Weighting w);  // "tf-idf", "tf", "idf", "binary"
std::string ScoringName(Scoring s);      // "l1", "l2", "chi-square", "kl", "bhattacharyya", "dot-product"
// Inverse of the names above; false when `name` is none of them.
bool ParseWeighting(const std::string& name, Weighting* out);
bool ParseScoring(const std::string& name, Scoring* out);

// DBoW2 GeneralScoring::mustNormalize: whether Transform normalises the vector and with which norm
// (L1 for L1 / chi-square / KL / Bhattacharyya, L2 for L2, none for the dot product).
bool MustNormalize(Scoring s, Norm* norm);

// BowVector::addWeight (sum) and addIfNotExist (first value kept).
void AddWeight(BowVector* v, WordId id, double w);
void AddIfNotExist(BowVector* v, WordId id, double w);
// BowVector::normalize: divides by the L1 norm (sum |w|) or the L2 norm; nothing when it is 0.
void Normalize(BowVector* v, Norm norm);
// FeatureVector::addFeature.
void AddFeature(FeatureVector* fv, NodeId node, uint32_t feature_index);

// The score of two (already normalised) vectors, ScoringObject.cpp. L1 (ORB-SLAM2's choice):
// 1 - 0.5 * |v - w|_1 computed over the shared words only as
// -0.5 * sum_{i shared} (|v_i - w_i| - |v_i| - |w_i|), Nister & Stewenius 2006; in [0, 1] for
// L1-normalised vectors. L2: 1 - sqrt(1 - sum v_i w_i) (1 when the sum >= 1). Chi-square:
// 2 * sum v_i w_i / (v_i + w_i). KL: sum over v's words of v_i log(v_i / w_i), log(eps) standing
// for a missing w_i (eps = DBL_EPSILON). Bhattacharyya: sum sqrt(v_i w_i). Dot product: sum v_i w_i.
double Score(Scoring s, const BowVector& a, const BowVector& b);

}  // namespace dynref::place
