// Line segments for structure-aware tracking (seed 000 Sec. 3.2, spec 000 step 3; issue 13).
//
// Detection: ximgproc::FastLineDetector (Lee et al. 2014) rather than line_descriptor's LSD:
// on a 640x480 synthetic office frame FLD takes ~6 ms and LSD ~24 ms (single thread), FLD is
// deterministic, and its length threshold is the spec's minimum length. Description: LBD
// (line_descriptor::BinaryDescriptor::compute, Zhang & Koch 2013), 32 bytes per segment, matched
// by Hamming distance like ORB.
//
// Parallel grouping (spec 000 step 3): segments whose orientations (mod 180 deg) differ by less
// than tau_theta = 3 deg are parallel. Groups are connected components of that relation taken
// in index order after sorting by orientation (no cross-group merging). The companion of a
// segment (spec 000 E15: "the most structurally consistent parallel line") is the other member
// of its group with the smallest orientation difference, ties by the greater length, then the
// lower index.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <vector>

namespace dynref::features {

struct LineOptions {
  int min_length_px = 20;             // FLD length threshold
  double distance_threshold_px = 1.414213562;  // FLD: max distance of a pixel from the fitted line
  double canny_low = 50, canny_high = 50;       // FLD defaults
  double parallel_deg = 3.0;          // tau_theta
  int max_lines = 200;                // keep the longest (ties: lower index)
  void Check() const;                 // std::invalid_argument naming the field
};

struct Segment {
  Eigen::Vector2d s = Eigen::Vector2d::Zero(), e = Eigen::Vector2d::Zero();  // endpoints, px
  double angle = 0;        // orientation in [0, pi)
  double length = 0;       // px
  int group = -1;          // parallel group id (0..), ascending by first member
  int companion = -1;      // index of the companion segment, -1 when alone in its group
};

struct SegmentSet {
  std::vector<Segment> segments;
  cv::Mat descriptors;  // N x 32 CV_8U LBD, one row per segment
};

// Segments of a grey image, their LBD descriptors, groups and companions. Deterministic.
SegmentSet DetectSegments(const cv::Mat& grey, const LineOptions& options);

// Orientation difference of two undirected lines, in [0, pi/2].
double LineAngleDiff(double a, double b);
// Normalised homogeneous line through two pixels: l = (s_h x e_h) / ||(l1, l2)||, so that
// l . (u, v, 1) is the signed pixel distance to the line.
Eigen::Vector3d LineThrough(const Eigen::Vector2d& s, const Eigen::Vector2d& e);
// Groups + companions of segments (exposed for tests).
void GroupParallel(std::vector<Segment>* segments, double parallel_deg);

}  // namespace dynref::features
