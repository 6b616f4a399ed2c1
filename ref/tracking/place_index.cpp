// The backbone's place recognition state; see place_index.h.
#include "tracking/place_index.h"

#include <algorithm>
#include <vector>

namespace dynref::tracking {
namespace {

std::unique_ptr<place::Vocabulary> LoadUnlessDefault(const std::string& vocabulary) {
  if (vocabulary == "default") return nullptr;
  return std::make_unique<place::Vocabulary>(place::Vocabulary::Load(vocabulary));
}

}  // namespace

PlaceIndex::PlaceIndex(const std::string& vocabulary)
    : owned_(LoadUnlessDefault(vocabulary)),
      vocabulary_(owned_ != nullptr ? owned_.get() : &place::Vocabulary::Default()),
      database_(*vocabulary_),
      levels_up_(std::max(0, vocabulary_->levels() - 2)) {}

PlaceBow PlaceIndex::Compute(const Frame& f) const {
  PlaceBow out;
  if (f.descriptors.empty()) return out;
  std::vector<int> kept;  // keypoint index of each row handed to the vocabulary
  kept.reserve(f.N());
  for (size_t i = 0; i < f.N(); ++i)
    if (!f.IsExcluded(static_cast<int>(i))) kept.push_back(static_cast<int>(i));
  const std::vector<place::Descriptor> all = place::DescriptorRows(f.descriptors, "backbone.vocabulary");
  std::vector<place::Descriptor> rows;
  rows.reserve(kept.size());
  for (int i : kept) rows.push_back(all[static_cast<size_t>(i)]);
  place::FeatureVector by_row;
  vocabulary_->Transform(rows, &out.bow, &by_row, levels_up_);
  // Row numbers -> keypoint indices (increasing, so each list stays ascending).
  for (const auto& [node, list] : by_row) {
    std::vector<uint32_t>& dst = out.features[node];
    dst.reserve(list.size());
    for (uint32_t r : list) dst.push_back(static_cast<uint32_t>(kept[r]));
  }
  return out;
}

void PlaceIndex::Add(const KeyFrame& kf) {
  PlaceBow b = Compute(kf.frame);
  database_.Add(static_cast<place::KeyFrameId>(kf.id), b.bow);
  keyframes_[kf.id] = std::move(b);
}

void PlaceIndex::EraseBad(const Map& map) {
  std::vector<int64_t> bad;
  for (const auto& [id, b] : keyframes_) {
    const KeyFrame* k = map.kf(id);
    if (k == nullptr || k->bad) bad.push_back(id);
  }
  for (int64_t id : bad) {
    database_.Erase(static_cast<place::KeyFrameId>(id));
    keyframes_.erase(id);
  }
}

void PlaceIndex::AddAfterMapping(const KeyFrame& kf, const Map& map) {
  EraseBad(map);
  if (!kf.bad) Add(kf);
}

const PlaceBow* PlaceIndex::Of(int64_t kf_id) const {
  const auto it = keyframes_.find(kf_id);
  return it == keyframes_.end() ? nullptr : &it->second;
}

place::CovisibleFn PlaceIndex::Covisible(const Map& map) {
  return [&map](place::KeyFrameId id, int n) {
    std::vector<place::KeyFrameId> out;
    const KeyFrame* k = map.kf(static_cast<int64_t>(id));
    if (k == nullptr) return out;
    for (int64_t c : k->BestCovisibles(n)) out.push_back(static_cast<place::KeyFrameId>(c));
    return out;
  };
}

}  // namespace dynref::tracking
