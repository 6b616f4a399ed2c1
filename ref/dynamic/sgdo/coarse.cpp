#include "dynamic/sgdo/coarse.h"

#include <map>
#include <stdexcept>

namespace dynref::sgdo {

CoarseMode ParseCoarseMode(const std::string& text) {
  if (text == "per_point") return CoarseMode::kPerPoint;
  if (text == "instance_vote") return CoarseMode::kInstanceVote;
  if (text == "mask_only") return CoarseMode::kMaskOnly;
  if (text == "epipolar_only") return CoarseMode::kEpipolarOnly;
  throw std::invalid_argument("combination must be per_point|instance_vote|mask_only|epipolar_only, got '" +
                              text + "'");
}

const char* CoarseModeName(CoarseMode mode) {
  switch (mode) {
    case CoarseMode::kPerPoint: return "per_point";
    case CoarseMode::kInstanceVote: return "instance_vote";
    case CoarseMode::kMaskOnly: return "mask_only";
    case CoarseMode::kEpipolarOnly: return "epipolar_only";
  }
  return "?";
}

void CoarseOptions::Check() const {
  if (!(epipolar_threshold_px > 0)) throw std::invalid_argument("epipolar_threshold_px must be > 0");
  if (!(vote_ratio > 0 && vote_ratio <= 1)) throw std::invalid_argument("vote_ratio must be in (0, 1]");
}

CoarseResult CombineCoarse(const std::vector<CoarseInput>& inputs, const CoarseOptions& options) {
  options.Check();
  CoarseResult out;
  out.decisions.resize(inputs.size());
  const double th = options.epipolar_threshold_px;
  auto geometric_dynamic = [&](const CoarseInput& in) {
    return in.has_distance && in.epipolar_distance_px > th;
  };
  std::map<int, CoarseResult::Vote> votes;
  if (options.mode == CoarseMode::kInstanceVote) {
    for (const CoarseInput& in : inputs) {
      if (in.instance == 0) continue;
      auto& v = votes.try_emplace(in.instance, CoarseResult::Vote{in.instance, 0, 0, false}).first->second;
      if (in.has_distance) {
        ++v.paired;
        if (geometric_dynamic(in)) ++v.dynamic;
      }
    }
    for (auto& [id, v] : votes) {
      v.moving = v.paired == 0 || static_cast<double>(v.dynamic) >= options.vote_ratio * v.paired;
      out.votes.push_back(v);
    }
  }
  for (size_t i = 0; i < inputs.size(); ++i) {
    const CoarseInput& in = inputs[i];
    CoarseDecision& d = out.decisions[i];
    const bool in_mask = in.instance != 0;
    switch (options.mode) {
      case CoarseMode::kMaskOnly:
        d = in_mask ? CoarseDecision{false, "mask"} : CoarseDecision{true, "static"};
        break;
      case CoarseMode::kEpipolarOnly:
        d = geometric_dynamic(in) ? CoarseDecision{false, "epipolar"}
                                  : CoarseDecision{true, in.has_distance ? "static" : in.no_distance};
        break;
      case CoarseMode::kPerPoint:
        if (geometric_dynamic(in)) d = {false, "epipolar"};
        else if (in_mask && !in.has_distance) d = {false, "mask-" + in.no_distance};
        else d = {true, in.has_distance ? "static" : in.no_distance};
        break;
      case CoarseMode::kInstanceVote:
        if (in_mask) {
          d = votes.at(in.instance).moving ? CoarseDecision{false, "instance-vote"}
                                           : CoarseDecision{true, "instance-still"};
        } else {
          d = geometric_dynamic(in) ? CoarseDecision{false, "epipolar"}
                                    : CoarseDecision{true, in.has_distance ? "static" : in.no_distance};
        }
        break;
    }
  }
  return out;
}

}  // namespace dynref::sgdo
