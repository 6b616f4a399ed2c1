// Deterministic vocabulary training: DBoW2's hierarchical k-medians for binary descriptors
// (TemplatedVocabulary::create / HKmeansStep / initiateClustersKMpp / setNodeWeights, FORB
// meanValue), with dynref's random stream and written-down tie-breaks:
//  - k-means++ seeding from Rng(seed, "place.vocab.kmeans"), one stream consumed in the
//    depth-first order DBoW2 builds the tree in: the first centre is a uniform index, each next one
//    is drawn with probability proportional to D(x), the Hamming distance to the nearest chosen
//    centre (DBoW2 uses D, not D^2), by cumulative sum >= u, u uniform in (0, sum D];
//  - centroids: majority bit per position, a bit set when at least ceil(n/2) members have it;
//  - assignment: nearest centroid, the lowest cluster index wins a tie;
//  - iterate until no assignment changes, at most max_iterations passes (DBoW2 has no cap);
//  - an emptied cluster keeps its previous centroid while iterating and is dropped at the end
//    (DBoW2 would take the mean of nothing);
//  - a node with <= k descriptors gets one child per descriptor; a child is split further while
//    its level < L and it holds more than one descriptor;
//  - words are the leaves in node order; IDF weight of a word = ln(N / N_i), N training images,
//    N_i of them containing the word (tf / binary weighting: 1).
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "place/vocabulary.h"

namespace dynref::place {

struct TrainOptions {
  int k = 10;               // branching factor (DBoW2 k)
  int levels = 4;           // depth L
  uint64_t seed = 1;        // Rng(seed, "place.vocab.kmeans")
  int max_iterations = 50;  // assignment passes per k-means (stops earlier when stable)
  Weighting weighting = Weighting::kTfIdf;
  Scoring scoring = Scoring::kL1;
  void Check() const;       // InputError naming the bad field
};

// `images`: the descriptors of each training image (an image is one IDF document). `progress`
// (may be empty) gets a line of text now and then.
Vocabulary TrainVocabulary(const std::vector<std::vector<Descriptor>>& images, const TrainOptions& options,
                           const std::function<void(const std::string&)>& progress = {});

}  // namespace dynref::place
