// Deterministic hierarchical k-medians (see trainer.h for the rules).
#include "place/trainer.h"

#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/rng.h"

namespace dynref::place {
namespace {

// FORB::meanValue: majority bit per position, set when count >= ceil(n / 2).
Descriptor MajorityBits(const std::vector<Descriptor>& all, const std::vector<uint32_t>& members) {
  Descriptor mean{};
  if (members.size() == 1) return all[members[0]];
  int sum[kDescriptorBytes * 8] = {};
  for (uint32_t m : members) {
    const Descriptor& d = all[m];
    for (int j = 0; j < kDescriptorBytes; ++j)
      for (int b = 0; b < 8; ++b)
        if (d[j] & (1 << (7 - b))) ++sum[j * 8 + b];
  }
  const int half = static_cast<int>(members.size() / 2 + members.size() % 2);
  for (int i = 0; i < kDescriptorBytes * 8; ++i)
    if (sum[i] >= half) mean[i / 8] |= static_cast<uint8_t>(1 << (7 - i % 8));
  return mean;
}

class Trainer {
 public:
  Trainer(const std::vector<Descriptor>& all, const TrainOptions& o,
          const std::function<void(const std::string&)>& progress)
      : all_(all), o_(o), rng_(o.seed, "place.vocab.kmeans"), progress_(progress) {}

  std::vector<VocabularyNode> Build() {
    nodes_.assign(1, VocabularyNode{});
    std::vector<uint32_t> everything(all_.size());
    for (uint32_t i = 0; i < everything.size(); ++i) everything[i] = i;
    if (!everything.empty()) Step(0, everything, 1);
    return std::move(nodes_);
  }

 private:
  // DBoW2 initiateClustersKMpp over `members`.
  std::vector<Descriptor> SeedKMeansPP(const std::vector<uint32_t>& members) {
    std::vector<Descriptor> centres;
    centres.push_back(all_[members[rng_.UniformInt(0, static_cast<int64_t>(members.size()) - 1)]]);
    std::vector<int> min_dist(members.size());
    for (size_t i = 0; i < members.size(); ++i) min_dist[i] = HammingDistance(all_[members[i]], centres.back());
    while (static_cast<int>(centres.size()) < o_.k) {
      for (size_t i = 0; i < members.size(); ++i)
        if (min_dist[i] > 0) min_dist[i] = std::min(min_dist[i], HammingDistance(all_[members[i]], centres.back()));
      double sum = 0;  // sums of integers: exact
      for (int d : min_dist) sum += d;
      if (!(sum > 0)) break;  // every member coincides with a centre
      double cut = 0;
      do cut = rng_.Uniform(0, sum);
      while (cut == 0.0);
      size_t pick = members.size() - 1;
      double acc = 0;
      for (size_t i = 0; i < members.size(); ++i) {
        acc += min_dist[i];
        if (acc >= cut) {
          pick = i;
          break;
        }
      }
      centres.push_back(all_[members[pick]]);
    }
    return centres;
  }

  void Step(NodeId parent, const std::vector<uint32_t>& members, int level) {
    std::vector<Descriptor> centres;
    std::vector<std::vector<uint32_t>> groups;
    if (static_cast<int>(members.size()) <= o_.k) {
      for (size_t i = 0; i < members.size(); ++i) {
        centres.push_back(all_[members[i]]);
        groups.push_back({static_cast<uint32_t>(i)});
      }
    } else {
      centres = SeedKMeansPP(members);
      std::vector<int> last, current(members.size());
      for (int pass = 0; pass < o_.max_iterations; ++pass) {
        if (pass > 0)
          for (size_t c = 0; c < centres.size(); ++c)
            if (!groups[c].empty()) {
              std::vector<uint32_t> global;
              global.reserve(groups[c].size());
              for (uint32_t m : groups[c]) global.push_back(members[m]);
              centres[c] = MajorityBits(all_, global);
            }
        groups.assign(centres.size(), {});
        for (size_t i = 0; i < members.size(); ++i) {
          const Descriptor& d = all_[members[i]];
          int best = HammingDistance(d, centres[0]);
          int which = 0;
          for (size_t c = 1; c < centres.size(); ++c) {
            const int dist = HammingDistance(d, centres[c]);
            if (dist < best) {
              best = dist;
              which = static_cast<int>(c);
            }
          }
          groups[which].push_back(static_cast<uint32_t>(i));
          current[i] = which;
        }
        if (current == last) break;
        last = current;
      }
      // Drop emptied clusters (their centroid represents nothing).
      std::vector<Descriptor> kept_c;
      std::vector<std::vector<uint32_t>> kept_g;
      for (size_t c = 0; c < centres.size(); ++c)
        if (!groups[c].empty()) {
          kept_c.push_back(centres[c]);
          kept_g.push_back(std::move(groups[c]));
        }
      centres.swap(kept_c);
      groups.swap(kept_g);
    }
    std::vector<NodeId> children;
    for (const Descriptor& c : centres) {
      const NodeId id = static_cast<NodeId>(nodes_.size());
      nodes_.emplace_back();
      nodes_.back().parent = parent;
      nodes_.back().descriptor = c;
      nodes_[parent].children.push_back(id);
      children.push_back(id);
    }
    if (level == 1 && progress_)
      progress_("level 1: " + std::to_string(centres.size()) + " clusters of " + std::to_string(members.size()) +
                " descriptors");
    if (level >= o_.levels) return;
    for (size_t c = 0; c < centres.size(); ++c) {
      if (groups[c].size() <= 1) continue;
      std::vector<uint32_t> sub;
      sub.reserve(groups[c].size());
      for (uint32_t m : groups[c]) sub.push_back(members[m]);
      Step(children[c], sub, level + 1);
      if (level == 1 && progress_)
        progress_("cluster " + std::to_string(c + 1) + "/" + std::to_string(centres.size()) + " done, " +
                  std::to_string(nodes_.size()) + " nodes");
    }
  }

  const std::vector<Descriptor>& all_;
  const TrainOptions& o_;
  Rng rng_;
  const std::function<void(const std::string&)>& progress_;
  std::vector<VocabularyNode> nodes_;
};

}  // namespace

void TrainOptions::Check() const {
  if (k < 2 || k > 20) throw InputError("--k", "must be in 2..20 (DBoW2's range), got " + std::to_string(k));
  if (levels < 1 || levels > 10) throw InputError("--levels", "must be in 1..10 (DBoW2's range), got " + std::to_string(levels));
  if (max_iterations < 1 || max_iterations > 10000)
    throw InputError("--iterations", "must be in 1..10000, got " + std::to_string(max_iterations));
}

Vocabulary TrainVocabulary(const std::vector<std::vector<Descriptor>>& images, const TrainOptions& options,
                           const std::function<void(const std::string&)>& progress) {
  options.Check();
  std::vector<Descriptor> all;
  for (const auto& img : images) all.insert(all.end(), img.begin(), img.end());
  if (all.empty()) throw InputError("training set", "no descriptors to train a vocabulary on");
  Trainer trainer(all, options, progress);
  Vocabulary v;
  v.Assign(options.k, options.levels, options.weighting, options.scoring, trainer.Build());
  // DBoW2 setNodeWeights.
  std::vector<VocabularyNode> nodes = v.nodes();
  if (options.weighting == Weighting::kTf || options.weighting == Weighting::kBinary) {
    for (WordId w = 0; w < v.size(); ++w) nodes[v.word_node(w)].weight = 1;
  } else {
    std::vector<uint32_t> ni(v.size(), 0);
    std::vector<uint8_t> counted(v.size());
    for (const auto& img : images) {
      std::fill(counted.begin(), counted.end(), 0);
      for (const Descriptor& d : img) {
        const WordId w = v.Transform(d.data());
        if (!counted[w]) {
          ++ni[w];
          counted[w] = 1;
        }
      }
    }
    const double n_docs = static_cast<double>(images.size());
    for (WordId w = 0; w < v.size(); ++w)
      if (ni[w] > 0) nodes[v.word_node(w)].weight = std::log(n_docs / static_cast<double>(ni[w]));
  }
  v.Assign(options.k, options.levels, options.weighting, options.scoring, std::move(nodes));
  return v;
}

}  // namespace dynref::place
