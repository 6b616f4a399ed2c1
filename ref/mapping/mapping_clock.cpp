#include "mapping/mapping_clock.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace dynref::mapping {

void MappingClockOptions::Check() const {
  if (!(ms_per_keyframe >= 0 && std::isfinite(ms_per_keyframe)))
    throw InputError("mapping clock options", "ms_per_keyframe must be >= 0");
  if (!(ms_per_ba_observation >= 0 && std::isfinite(ms_per_ba_observation)))
    throw InputError("mapping clock options", "ms_per_ba_observation must be >= 0");
  if (max_queue < 1) throw InputError("mapping clock options", "max_queue must be >= 1");
}

MappingClock::MappingClock(const MappingClockOptions& options) : options_(options) { options_.Check(); }

MappingLoad MappingClock::LoadAt(double stamp) const {
  MappingLoad load;
  if (!options_.enabled) return load;
  load.idle = stamp >= free_at_;
  for (double s : starts_) load.queued += s > stamp ? 1 : 0;
  return load;
}

double MappingClock::Charge(double stamp, const LocalMapperStats& stats) {
  const double cost_ms = options_.ms_per_keyframe + options_.ms_per_ba_observation * stats.ba_observations;
  if (!options_.enabled) return cost_ms;
  while (!starts_.empty() && starts_.front() <= stamp) starts_.pop_front();
  const double start = std::max(stamp, free_at_);
  free_at_ = start + cost_ms * 1e-3;
  starts_.push_back(start);
  return cost_ms;
}

}  // namespace dynref::mapping
