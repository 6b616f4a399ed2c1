// A DBoW2-compatible vocabulary of binary words (DBoW2 TemplatedVocabulary<FORB::TDescriptor,
// FORB> as ORB-SLAM2 uses it: ORBVocabulary.h): a k-ary tree of 256-bit descriptor centroids
// whose leaves are the words, each with an IDF weight.
//
// Transform follows TemplatedVocabulary::transform: a descriptor descends from the root to the
// child at the smallest Hamming distance (the first child wins a tie), to a leaf; its word's
// weight is added to the BowVector (TF-IDF / TF: summed per word, IDF / binary: first value kept;
// weight 0 = stopped word, the feature is skipped), and the feature index is recorded under the
// node at level L - levels_up of the path (ORB-SLAM2 uses levels_up 4 with ORBvoc.txt's L = 6,
// i.e. level 2) in the FeatureVector. The vector is then normalised as the scoring wants
// (L1 for ORB-SLAM2's L1 score); without normalisation TF / TF-IDF weights are divided by the
// number of words.
//
// Files (README.md "Formats"): dynref's own versioned text format (Save/Serialize, lossless
// weights, hex descriptors, CRC-32C trailer) and ORB-SLAM2's ORBvoc.txt text format
// (TemplatedVocabulary::loadFromTextFile / saveToTextFile). Load() tells them apart by the
// first line. Every malformed file is an InputError(file, line, what).
#pragma once
#include <array>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "place/bow.h"

namespace dynref::place {

constexpr int kDescriptorBytes = 32;  // FORB::L: ORB's 256-bit rBRIEF
using Descriptor = std::array<uint8_t, kDescriptorBytes>;

// Hamming distance of two 256-bit descriptors (FORB::distance).
int HammingDistance(const Descriptor& a, const Descriptor& b);
int HammingDistance(const uint8_t* a, const uint8_t* b);
// Rows of an N x 32 CV_8U matrix as descriptors; std::invalid_argument naming `what` for any
// other type or width (float descriptors have no vocabulary: README "Float descriptors").
std::vector<Descriptor> DescriptorRows(const cv::Mat& descriptors, const std::string& what);

struct VocabularyNode {
  NodeId parent = 0;
  std::vector<NodeId> children;  // in file / creation order (the order Transform compares them)
  Descriptor descriptor{};
  double weight = 0;             // IDF of a word; 0 for inner nodes and stopped words
  WordId word_id = 0;            // valid for leaves
  bool leaf() const { return children.empty(); }
};

// One node line of a file before the tree is assembled: node i + 1 of the list (the root, id 0,
// is implicit).
struct NodeRecord {
  NodeId parent = 0;
  bool leaf = false;
  Descriptor descriptor{};
  double weight = 0;
  int line = 0;  // source line for errors (0 = not from a file)
};

class Vocabulary {
 public:
  Vocabulary() = default;

  // Builds the tree. `nodes[i]` is node i + 1. InputError(file, line) when a parent id is not an
  // earlier node, a node marked leaf has children or one marked inner has none, a weight is not
  // finite or negative, or k / levels are out of DBoW2's range (k 2..20, L 1..10).
  static Vocabulary FromNodes(int k, int levels, Weighting weighting, Scoring scoring,
                              const std::vector<NodeRecord>& nodes, const std::string& file = "<memory>");

  // dynref format or ORBvoc.txt, chosen by the first line ("dynref-vocabulary ..." or not).
  static Vocabulary Load(const std::string& path);
  static Vocabulary LoadOrbSlamText(const std::string& path);
  // Parsers of text already in memory; `file` names it in errors.
  static Vocabulary ParseOrbSlamText(const std::string& text, const std::string& file);
  static Vocabulary ParseDynref(const std::string& text, const std::string& file);
  // The vocabulary embedded in the binary (README "The default vocabulary").
  static const Vocabulary& Default();

  // dynref's format (byte-identical for equal vocabularies) and ORB-SLAM2's text format
  // (saveToTextFile: weights with 6 significant digits, as ORB-SLAM2 writes them).
  std::string Serialize() const;
  std::string SerializeOrbSlamText() const;
  void Save(const std::string& path) const;  // Serialize() through AtomicWriteFile

  int k() const { return k_; }
  int levels() const { return levels_; }
  Weighting weighting() const { return weighting_; }
  Scoring scoring() const { return scoring_; }
  size_t size() const { return words_.size(); }  // number of words
  bool empty() const { return words_.empty(); }
  const std::vector<VocabularyNode>& nodes() const { return nodes_; }
  NodeId word_node(WordId w) const { return words_[w]; }
  // Depth of the deepest leaf (root = 0) and the mean leaf depth (DBoW2 getEffectiveLevels).
  int MaxDepth() const;
  double EffectiveLevels() const;

  // One descriptor: its word, the word's weight and (when node != nullptr) the node at level
  // levels() - levels_up of its path: the root when that level is <= 0, the leaf itself when the
  // leaf lies above that level (DBoW2 leaves the id unset there). Requires !empty().
  WordId Transform(const uint8_t* descriptor, double* weight = nullptr, NodeId* node = nullptr,
                   int levels_up = 0) const;
  // N x 32 CV_8U rows -> BowVector (and FeatureVector when fv != nullptr), as DBoW2.
  void Transform(const cv::Mat& descriptors, BowVector* bow, FeatureVector* fv = nullptr, int levels_up = 0) const;
  void Transform(const std::vector<Descriptor>& descriptors, BowVector* bow, FeatureVector* fv = nullptr,
                 int levels_up = 0) const;

  double Score(const BowVector& a, const BowVector& b) const { return place::Score(scoring_, a, b); }
  // DBoW2 getParentNode: the node levels_up above word w's leaf (stops at the root).
  NodeId ParentNode(WordId w, int levels_up) const;
  // DBoW2 getWordsFromNode: the words under node n (n's own word when it is a leaf).
  std::vector<WordId> WordsFromNode(NodeId n) const;

  // Set by the trainer: the tree and its words (words in node order, as DBoW2 createWords).
  void Assign(int k, int levels, Weighting weighting, Scoring scoring, std::vector<VocabularyNode> nodes);

 private:
  void CreateWords();

  int k_ = 10, levels_ = 5;
  Weighting weighting_ = Weighting::kTfIdf;
  Scoring scoring_ = Scoring::kL1;
  std::vector<VocabularyNode> nodes_;  // nodes_[0] = root
  std::vector<NodeId> words_;          // word id -> node id
};

}  // namespace dynref::place
