// seed 002 Sec. 3.2: the interaction test between a prior-dynamic instance A and a prior-static
// instance B (equations lost in the extraction; spec 002 step 3, reconstructed):
//   Q = {(a, b) : a in A, b in B, ||a - b|| <= d_max}, both depths valid;
//   dz_mean = (1 / |Q|) sum |Z(a) - Z(b)|;  B is non-prior dynamic iff |Q| > 0 and dz_mean < T_int.
// Enumeration is deterministic: pixels a of A in row-major order, for each the window of
// (2 d_max + 1)^2 pixels b in row-major order (the sum's order is fixed).
#pragma once
#include <cstdint>
#include <map>
#include <opencv2/core.hpp>

namespace dynref::semantic {

struct InteractionResult {
  int64_t pairs = 0;
  double dz_mean_m = 0;  // 0 when pairs = 0
  bool interacting = false;
};

// Bounding box of every instance id > 0 in a CV_16U instance-id image (one pass).
std::map<int, cv::Rect> InstanceBounds(const cv::Mat& instance_ids);

// instance_ids: CV_16U per-pixel instance id (the mask format); depth_m: CV_32F, 0 = invalid;
// bounds from InstanceBounds (only pixels of A within d_max of B's box are scanned).
InteractionResult TestInteraction(const cv::Mat& instance_ids, const cv::Mat& depth_m,
                                  const std::map<int, cv::Rect>& bounds, int id_a, int id_b, int d_max_px,
                                  double t_int_m);

}  // namespace dynref::semantic
