#include "dynamic/epi/mask_vote.h"

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "geometry/fundamental.h"

namespace dynref::epi {

void MaskVoteOptions::Check() const {
  if (!(epi_threshold_px > 0)) throw std::invalid_argument("epi_threshold_px must be > 0");
  if (!(vote_ratio >= 0 && vote_ratio < 1)) throw std::invalid_argument("vote_ratio must be in [0, 1)");
}

std::map<int, MaskVote> VoteMasks(const std::vector<int>& instance_of, const std::vector<double>& distance,
                                  const std::vector<int>& masks, const MaskVoteOptions& o) {
  if (instance_of.size() != distance.size()) throw std::invalid_argument("VoteMasks: size mismatch");
  std::map<int, MaskVote> votes;
  for (int m : masks) votes[m];
  for (size_t i = 0; i < instance_of.size(); ++i) {
    if (instance_of[i] <= 0) continue;
    MaskVote& v = votes[instance_of[i]];
    if (std::isnan(distance[i])) continue;
    ++v.matched;
    v.violating += distance[i] > o.epi_threshold_px;
  }
  for (auto& [id, v] : votes) {
    v.ratio = v.matched > 0 ? double(v.violating) / v.matched : 0.0;
    v.dynamic = v.matched == 0 || v.ratio > o.vote_ratio;  // E8; strict > (spec 004 (c))
  }
  return votes;
}

VoteGeometry::VoteGeometry(const Eigen::Matrix3d& K, const Eigen::Matrix3d& R, const Eigen::Vector3d& t)
    : still_(t.isZero(0)),
      M_(still_ ? Eigen::Matrix3d(K * R * K.inverse()) : geometry::FundamentalFromPose(K, R, t)) {}

double VoteGeometry::Distance(const Eigen::Vector2d& p_prev, const Eigen::Vector2d& p_cur) const {
  if (still_) return (p_cur - (M_ * p_prev.homogeneous()).hnormalized()).norm();  // the limit point
  const double d = geometry::EpipolarDistance(M_, p_prev, p_cur);
  return std::isinf(d) ? std::numeric_limits<double>::quiet_NaN() : d;
}

double VoteDistance(const Eigen::Matrix3d& K, const Eigen::Matrix3d& R, const Eigen::Vector3d& t,
                    const Eigen::Vector2d& p_prev, const Eigen::Vector2d& p_cur) {
  return VoteGeometry(K, R, t).Distance(p_prev, p_cur);
}

}  // namespace dynref::epi
