// The vocabulary tree and Transform (DBoW2 TemplatedVocabulary, see vocabulary.h). Files: vocabulary_io.cpp.
#include "place/vocabulary.h"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "core/error.h"
#include "features/descriptor.h"

namespace dynref::place {

int HammingDistance(const uint8_t* a, const uint8_t* b) {
  static_assert(kDescriptorBytes == 32, "ORB descriptors");
  return features::DescriptorDistance(a, b);  // POPCNT where the CPU has it (features/descriptor.cpp)
}

int HammingDistance(const Descriptor& a, const Descriptor& b) { return HammingDistance(a.data(), b.data()); }

std::vector<Descriptor> DescriptorRows(const cv::Mat& descriptors, const std::string& what) {
  std::vector<Descriptor> out;
  if (descriptors.empty()) return out;
  if (descriptors.type() != CV_8U || descriptors.cols != kDescriptorBytes)
    throw std::invalid_argument(what + ": a vocabulary needs N x 32 CV_8U (ORB) descriptors, got " +
                                std::to_string(descriptors.rows) + " x " + std::to_string(descriptors.cols) +
                                " of type " + std::to_string(descriptors.type()) +
                                " (float descriptors have no vocabulary: ref/place/README.md)");
  out.resize(descriptors.rows);
  for (int r = 0; r < descriptors.rows; ++r) std::memcpy(out[r].data(), descriptors.ptr<uint8_t>(r), kDescriptorBytes);
  return out;
}

Vocabulary Vocabulary::FromNodes(int k, int levels, Weighting weighting, Scoring scoring,
                                 const std::vector<NodeRecord>& records, const std::string& file) {
  // DBoW2 loadFromTextFile's range check (k 0..20, L 1..10); k < 2 cannot branch.
  if (k < 2 || k > 20) throw InputError(file, 1, "branching factor k = " + std::to_string(k) + " is outside 2..20");
  if (levels < 1 || levels > 10) throw InputError(file, 1, "levels L = " + std::to_string(levels) + " is outside 1..10");
  std::vector<VocabularyNode> nodes(records.size() + 1);
  for (size_t i = 0; i < records.size(); ++i) {
    const NodeRecord& r = records[i];
    const NodeId id = static_cast<NodeId>(i + 1);
    if (r.parent >= id)
      throw InputError(file, r.line, "node " + std::to_string(id) + " names parent " + std::to_string(r.parent) +
                                         ", which is not an earlier node");
    if (!std::isfinite(r.weight) || r.weight < 0)
      throw InputError(file, r.line, "node " + std::to_string(id) + " has weight " + std::to_string(r.weight) +
                                         " (a weight is finite and >= 0)");
    if (r.parent != 0 && records[r.parent - 1].leaf)
      throw InputError(file, r.line, "node " + std::to_string(id) + " has parent " + std::to_string(r.parent) +
                                         ", which is marked as a leaf (line " +
                                         std::to_string(records[r.parent - 1].line) + ")");
    if (static_cast<int>(nodes[r.parent].children.size()) >= k)
      throw InputError(file, r.line, "node " + std::to_string(r.parent) + " gets more than k = " +
                                         std::to_string(k) + " children");
    nodes[id].parent = r.parent;
    nodes[id].descriptor = r.descriptor;
    nodes[id].weight = r.weight;
    nodes[r.parent].children.push_back(id);
  }
  for (size_t i = 0; i < records.size(); ++i)
    if (!records[i].leaf && nodes[i + 1].children.empty())
      throw InputError(file, records[i].line, "node " + std::to_string(i + 1) + " is marked inner but has no children");
  if (records.empty()) throw InputError(file, 1, "the vocabulary has no nodes");
  Vocabulary v;
  v.Assign(k, levels, weighting, scoring, std::move(nodes));
  return v;
}

void Vocabulary::Assign(int k, int levels, Weighting weighting, Scoring scoring, std::vector<VocabularyNode> nodes) {
  k_ = k;
  levels_ = levels;
  weighting_ = weighting;
  scoring_ = scoring;
  nodes_ = std::move(nodes);
  CreateWords();
}

void Vocabulary::CreateWords() {
  // DBoW2 createWords: leaves in node order, the root excluded.
  words_.clear();
  for (NodeId id = 1; id < nodes_.size(); ++id)
    if (nodes_[id].leaf()) {
      nodes_[id].word_id = static_cast<WordId>(words_.size());
      words_.push_back(id);
    }
}

int Vocabulary::MaxDepth() const {
  int best = 0;
  for (NodeId w : words_) {
    int d = 0;
    for (NodeId n = w; n != 0; n = nodes_[n].parent) ++d;
    best = std::max(best, d);
  }
  return best;
}

double Vocabulary::EffectiveLevels() const {
  if (words_.empty()) return 0;
  long sum = 0;
  for (NodeId w : words_)
    for (NodeId n = w; n != 0; n = nodes_[n].parent) ++sum;
  return static_cast<double>(sum) / static_cast<double>(words_.size());
}

WordId Vocabulary::Transform(const uint8_t* descriptor, double* weight, NodeId* node, int levels_up) const {
  const int node_level = levels_ - levels_up;
  if (node != nullptr && node_level <= 0) *node = 0;
  NodeId id = 0;
  int level = 0;
  bool node_set = node_level <= 0;
  do {
    ++level;
    const std::vector<NodeId>& children = nodes_[id].children;
    id = children[0];
    int best = HammingDistance(descriptor, nodes_[id].descriptor.data());
    for (size_t c = 1; c < children.size(); ++c) {
      const int d = HammingDistance(descriptor, nodes_[children[c]].descriptor.data());
      if (d < best) {
        best = d;
        id = children[c];
      }
    }
    if (node != nullptr && level == node_level) {
      *node = id;
      node_set = true;
    }
  } while (!nodes_[id].leaf());
  if (node != nullptr && !node_set) *node = id;  // leaf above the FeatureVector level
  if (weight != nullptr) *weight = nodes_[id].weight;
  return nodes_[id].word_id;
}

void Vocabulary::Transform(const std::vector<Descriptor>& descriptors, BowVector* bow, FeatureVector* fv,
                           int levels_up) const {
  bow->clear();
  if (fv != nullptr) fv->clear();
  if (empty()) return;
  Norm norm;
  const bool must = MustNormalize(scoring_, &norm);
  const bool tf = weighting_ == Weighting::kTf || weighting_ == Weighting::kTfIdf;
  for (size_t i = 0; i < descriptors.size(); ++i) {
    double w = 0;
    NodeId nid = 0;
    const WordId id = Transform(descriptors[i].data(), &w, fv != nullptr ? &nid : nullptr, levels_up);
    if (!(w > 0)) continue;  // stopped word
    if (tf)
      AddWeight(bow, id, w);
    else
      AddIfNotExist(bow, id, w);
    if (fv != nullptr) AddFeature(fv, nid, static_cast<uint32_t>(i));
  }
  if (tf && !bow->empty() && !must) {
    const double nd = static_cast<double>(bow->size());
    for (auto& [id, w] : *bow) w /= nd;
  }
  if (must) Normalize(bow, norm);
}

void Vocabulary::Transform(const cv::Mat& descriptors, BowVector* bow, FeatureVector* fv, int levels_up) const {
  Transform(DescriptorRows(descriptors, "Vocabulary::Transform"), bow, fv, levels_up);
}

NodeId Vocabulary::ParentNode(WordId w, int levels_up) const {
  NodeId n = words_.at(w);
  while (levels_up > 0 && n != 0) {
    --levels_up;
    n = nodes_[n].parent;
  }
  return n;
}

std::vector<WordId> Vocabulary::WordsFromNode(NodeId n) const {
  std::vector<WordId> words;
  if (nodes_.at(n).leaf()) {
    words.push_back(nodes_[n].word_id);
    return words;
  }
  // DBoW2 getWordsFromNode: a stack of inner nodes, children in order.
  std::vector<NodeId> parents{n};
  while (!parents.empty()) {
    const NodeId p = parents.back();
    parents.pop_back();
    for (NodeId c : nodes_[p].children) {
      if (nodes_[c].leaf())
        words.push_back(nodes_[c].word_id);
      else
        parents.push_back(c);
    }
  }
  return words;
}

}  // namespace dynref::place
