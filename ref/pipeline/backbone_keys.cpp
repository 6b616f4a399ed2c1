// The backbone keys by part of the backbone; see backbone_keys.h. A row names its field with a
// lambda `[](auto& o) -> auto& { return o.<field>; }` that serves for reading (const options) and
// writing; the builders check the field's type against the key's.
#include "pipeline/backbone_keys.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <type_traits>
#include <utility>

namespace dynref {
namespace {

using BackboneKind = BackboneKeyRow::Kind;

const double kBackboneMaxExactInt = 9007199254740992.0;  // 2^53: every integer below is exact in a double
const double kBackbonePi = 3.14159265358979323846;

template <class Field>
using BackboneFieldType = std::decay_t<decltype(std::declval<Field>()(std::declval<BackboneOptions&>()))>;

// A number (or on/off) key stored in one or more fields, the same value in each.
template <class... Fields>
BackboneKeyRow NumberKey(const char* key, BackboneKind kind, double lo, double hi, bool lo_open, const char* source,
                         Fields... fields) {
  BackboneKeyRow r;
  r.key = key;
  r.source = source;
  r.kind = kind;
  r.lo = lo;
  r.hi = hi;
  r.lo_open = lo_open;
  r.get = [key, fields...](const BackboneOptions& o) {
    const double values[] = {static_cast<double>(fields(o))...};
    for (double v : values)
      if (!(v == values[0])) throw std::logic_error(std::string("backbone.") + key + ": its fields differ");
    return values[0];
  };
  r.set = [fields...](BackboneOptions& o, double v) { ((fields(o) = static_cast<BackboneFieldType<Fields>>(v)), ...); };
  return r;
}

// Integers in lo..hi (int fields; the seed: uint64_t).
template <class... Fields>
BackboneKeyRow IntKey(const char* key, double lo, double hi, const char* source, Fields... fields) {
  static_assert(((std::is_integral_v<BackboneFieldType<Fields>> && !std::is_same_v<BackboneFieldType<Fields>, bool>) && ...));
  return NumberKey(key, BackboneKind::kInt, lo, hi, false, source, fields...);
}

// Reals in [lo, hi].
template <class... Fields>
BackboneKeyRow RealKey(const char* key, double lo, double hi, const char* source, Fields... fields) {
  static_assert((std::is_same_v<BackboneFieldType<Fields>, double> && ...));
  return NumberKey(key, BackboneKind::kDouble, lo, hi, false, source, fields...);
}

// Reals in (lo, hi].
template <class... Fields>
BackboneKeyRow RealAboveKey(const char* key, double lo, double hi, const char* source, Fields... fields) {
  static_assert((std::is_same_v<BackboneFieldType<Fields>, double> && ...));
  return NumberKey(key, BackboneKind::kDouble, lo, hi, true, source, fields...);
}

template <class... Fields>
BackboneKeyRow FlagKey(const char* key, const char* source, Fields... fields) {
  static_assert((std::is_same_v<BackboneFieldType<Fields>, bool> && ...));
  return NumberKey(key, BackboneKind::kBool, 0, 0, false, source, fields...);
}

// Text, one of `choices` ('|'-separated; nullptr = any).
template <class Field>
BackboneKeyRow TextKey(const char* key, const char* choices, const char* source, Field field) {
  static_assert(std::is_same_v<BackboneFieldType<Field>, std::string>);
  BackboneKeyRow r;
  r.key = key;
  r.source = source;
  r.kind = BackboneKind::kText;
  r.choices = choices;
  r.get_text = [field](const BackboneOptions& o) { return field(o); };
  r.set_text = [field](BackboneOptions& o, const std::string& v, const std::string&) { field(o) = v; };
  return r;
}

// A relative path read from a config file, as a path from the working directory.
// A value given by `dynref run --set` (its location is "--set ...") is relative to the working
// directory (issue 37).
std::string BackbonePathFrom(const std::string& config_file, const std::string& path) {
  if (path.empty() || path[0] == '/' || config_file.empty() || config_file.rfind("--set", 0) == 0) return path;
  const size_t slash = config_file.find_last_of('/');
  return slash == std::string::npos ? path : config_file.substr(0, slash + 1) + path;
}

// A file path relative to the config file's folder; `keep` (if not nullptr) is a name kept as is.
template <class Field>
BackboneKeyRow PathKey(const char* key, const char* keep, const char* source, Field field) {
  BackboneKeyRow r = TextKey(key, nullptr, source, field);
  r.set_text = [field, keep](BackboneOptions& o, const std::string& v, const std::string& file) {
    field(o) = keep != nullptr && v == keep ? v : BackbonePathFrom(file, v);
  };
  return r;
}

// ORB-SLAM2 defaults (Examples/RGB-D/TUM*.yaml, src/Tracking.cc, src/Optimizer.cc). Ranges:
// n_features: the extractor reserves 10 * n_features candidates per level (int arithmetic);
// 100000 is 100x the default. n_levels: one image and scale per level, 16 as OrbOptions::Check.
// FAST thresholds are 8-bit intensity differences.
std::vector<BackboneKeyRow> FeatureKeys() {
  return {
      RealKey("descriptor_th_high", 0, 1e9,
              "dynref (issue 17): projection-search gate in the extractor's distance units; 0 = the extractor's own "
              "(orb: ORBmatcher TH_HIGH 100 bits; sift: 0.60 squared L2 of unit rows; onnx: 4 * 100 / 256 squared L2, spec 004 (c))",
              [](auto& o) -> auto& { return o.extractor.th_high; }),
      RealKey("descriptor_th_low", 0, 1e9,
              "dynref (issue 17): keyframe-matching / triangulation / fusion gate in the extractor's units; 0 = the extractor's "
              "own (orb: ORBmatcher TH_LOW 50 bits; sift: 0.20; onnx: 4 * 50 / 256)",
              [](auto& o) -> auto& { return o.extractor.th_low; }),
      RealKey("descriptor_th_reloc", 0, 1e9,
              "dynref (issue 17): relocalisation refinement gate; 0 = the extractor's own (orb: Tracking::Relocalization 64 "
              "bits; sift: 0.30; onnx: 4 * 64 / 256)",
              [](auto& o) -> auto& { return o.extractor.th_reloc; }),
      TextKey("features", "orb|sift|onnx",
              "default: ORB-SLAM2's ORBextractor; sift = OpenCV SIFT (float descriptors), onnx = a SuperPoint-style network "
              "(onnx_* keys) (issue 17, seed 004 module B; ref/features/keypoint_extractor.h)",
              [](auto& o) -> auto& { return o.extractor.type; }),
      IntKey("ini_th_fast", 1, 255, "default: ORB-SLAM2 ORBextractor.iniThFAST", [](auto& o) -> auto& { return o.orb.ini_th_fast; }),
      IntKey("min_th_fast", 1, 255, "default: ORB-SLAM2 ORBextractor.minThFAST", [](auto& o) -> auto& { return o.orb.min_th_fast; }),
      IntKey("n_features", 1, 100000, "default: ORB-SLAM2 TUM RGB-D settings ORBextractor.nFeatures",
             [](auto& o) -> auto& { return o.orb.n_features; }),
      IntKey("n_levels", 1, 16, "default: ORB-SLAM2 ORBextractor.nLevels", [](auto& o) -> auto& { return o.orb.n_levels; }),
      RealAboveKey("scale_factor", 1, 1e9, "default: ORB-SLAM2 ORBextractor.scaleFactor",
                   [](auto& o) -> auto& { return o.orb.scale_factor; }),
  };
}

// The ONNX extractor (issue 17, seed 004 module B).
std::vector<BackboneKeyRow> OnnxKeys() {
  return {
      FlagKey("onnx_binary", "dynref (issue 17): pack the network's descriptor signs into bits (ZippyPoint's binary head; Hamming gates)",
              [](auto& o) -> auto& { return o.extractor.onnx.binary; }),
      IntKey("onnx_border", 0, 1000, "not stated: SuperPoint's remove_borders default (keypoints this close to the edge are dropped)",
             [](auto& o) -> auto& { return o.extractor.onnx.border; }),
      TextKey("onnx_descriptor_output", nullptr, "dynref (issue 17): name of the network's 1 x D x Hd x Wd descriptor output",
              [](auto& o) -> auto& { return o.extractor.onnx.descriptor_output; }),
      PathKey("onnx_model", nullptr, "dynref (issue 17): the .onnx file of features: onnx (relative to the config file's folder)",
              [](auto& o) -> auto& { return o.extractor.onnx.model; }),
      IntKey("onnx_nms_radius", 0, 100, "paper 004 Sec. 4.1: NMS radius 3", [](auto& o) -> auto& { return o.extractor.onnx.nms_radius; }),
      TextKey("onnx_score_output", nullptr,
              "dynref (issue 17): name of the network's score output (1 x 65 x H/8 x W/8 logits or 1 x 1 x H x W)",
              [](auto& o) -> auto& { return o.extractor.onnx.score_output; }),
      RealKey("onnx_score_threshold", 0, 1, "paper 004 Sec. 4.1: keypoint score > 0.015",
              [](auto& o) -> auto& { return o.extractor.onnx.score_threshold; }),
  };
}

// Frame counts are added to frame indices (int); 100000 frames (55 min at 30 fps) keeps the
// sums far from overflow.
std::vector<BackboneKeyRow> TrackingKeys() {
  return {
      FlagKey("camera_rgb_flag",
              "default: ORB-SLAM2 TUM1-3.yaml Camera.RGB: 1 applied to cv::imread's BGR images "
              "(Tracking::GrabImageRGBD converts with CV_RGB2GRAY, so blue gets red's weight); "
              "false = luminance of the true colours (COLOR_BGR2GRAY)",
              [](auto& o) -> auto& { return o.camera_rgb_flag; }),
      RealKey("depth_edge_rel", 0, 1,
              "dynref (issue 13): not in ORB-SLAM2, whose ComputeStereoFromRGBD samples the keypoint's one pixel (0 = that); "
              "> 0: a keypoint whose 5x5 neighbourhood has a pixel without depth or one differing by more than this fraction "
              "of its depth gets no depth (monocular point): corners on silhouettes otherwise take either side's depth "
              "(a 3-5 % scale bias on static_lowtexture, reports/structure_bench.md)",
              [](auto& o) -> auto& { return o.depth_edge_rel; }),
      IntKey("max_frames", 1, 100000, "default: ORB-SLAM2 mMaxFrames = Camera.fps (30)", [](auto& o) -> auto& { return o.tracker.max_frames; }),
      IntKey("min_init_points", 1, 100000, "default: ORB-SLAM2 Tracking::StereoInitialization N > 500",
             [](auto& o) -> auto& { return o.tracker.min_init_points; }),
      FlagKey("mnn2_matching",
              "dynref (issue 17): false = ORB-SLAM2's brute-force rule; true = seed 004 MNN2 (Sec. 3.2: ratio, absolute gate "
              "TH_HIGH equivalent, mutual check) in keyframe-to-frame matching and the triangulation search",
              [](auto& o) -> auto& { return o.tracker.mnn2.enabled; }, [](auto& o) -> auto& { return o.mapper.mnn2.enabled; }),
      RealAboveKey("mnn2_ratio", 0, 1, "paper 004 Sec. 4.2: MNN2 ratio rho (used when mnn2_matching is true)",
                   [](auto& o) -> auto& { return o.tracker.mnn2.ratio; }, [](auto& o) -> auto& { return o.mapper.mnn2.ratio; }),
      IntKey("seed", 0, kBackboneMaxExactInt,
             "not stated: seed of dynref's named RNG streams (relocalisation and loop-closing RANSAC)",
             [](auto& o) -> auto& { return o.tracker.seed; }, [](auto& o) -> auto& { return o.loop.seed; }),
  };
}

// Pose-only optimisation (ORB-SLAM2 Optimizer::PoseOptimization).
std::vector<BackboneKeyRow> PoseKeys() {
  return {
      RealAboveKey("pose_chi2_mono", 0, 1e9, "default: ORB-SLAM2 Optimizer::PoseOptimization 95 % chi2 (2 dof)",
                   [](auto& o) -> auto& { return o.tracker.pose.chi2_mono; }),
      RealAboveKey("pose_chi2_stereo", 0, 1e9, "default: ORB-SLAM2 Optimizer::PoseOptimization 95 % chi2 (3 dof)",
                   [](auto& o) -> auto& { return o.tracker.pose.chi2_stereo; }),
      IntKey("pose_iterations", 1, 1000, "default: ORB-SLAM2 Optimizer::PoseOptimization optimize(its[it]) with its = 10",
             [](auto& o) -> auto& { return o.tracker.pose.iterations; }),
      IntKey("pose_min_edges", 0, 100000, "default: ORB-SLAM2 Optimizer::PoseOptimization stops when optimizer.edges().size() < 10",
             [](auto& o) -> auto& { return o.tracker.pose.min_edges; }),
      FlagKey("pose_weighted_outlier_test",
              "dynref (issue 21): the pose-only outlier test uses inv_sigma2 only, a method's weight scales the cost, not "
              "the test; true = inv_sigma2 * weight (ORB-SLAM2 has no weights)",
              [](auto& o) -> auto& { return o.tracker.pose.weighted_outlier_test; }),
      IntKey("pose_rounds", 1, 100, "default: ORB-SLAM2 Optimizer::PoseOptimization 4 rounds", [](auto& o) -> auto& { return o.tracker.pose.rounds; }),
  };
}

// Relocalisation, bag of words and loop closing (issue 34).
std::vector<BackboneKeyRow> PlaceKeys() {
  return {
      FlagKey("bow_matching",
              "dynref (issue 34): false = brute-force keyframe-to-frame matching (dynref before issue 34); true = ORB-SLAM2 "
              "ORBmatcher::SearchByBoW (features under the same vocabulary node, backbone.vocabulary) in reference-keyframe "
              "tracking and relocalisation",
              [](auto& o) -> auto& { return o.tracker.bow_matching; }),
      FlagKey("loop_closing",
              "default: ORB-SLAM2 runs LoopClosing (validated over seeds 1-3, reports/loop_closing.md); false = dynref before issue 34; "
              "true = ORB-SLAM2's loop detection, SE(3) RANSAC, loop fusion, essential graph and global BA after local "
              "mapping of each keyframe (ref/loop/README.md; backbone.vocabulary)",
              [](auto& o) -> auto& { return o.loop.enabled; }),
      FlagKey("loop_global_ba", "default: ORB-SLAM2 LoopClosing::CorrectLoop starts RunGlobalBundleAdjustment (10 iterations)",
              [](auto& o) -> auto& { return o.loop.global_ba; }),
      IntKey("reloc_recent_keyframes", 1, 100000,
             "not stated: dynref has no BoW database; relocalisation tries the 10 most recent keyframes",
             [](auto& o) -> auto& { return o.tracker.reloc_recent_keyframes; }),
      TextKey("relocalisation", "recent|bow",
              "default: ORB-SLAM2 KeyFrameDatabase::DetectRelocalizationCandidates over the whole map (bow; backbone.vocabulary); "
              "recent = the reloc_recent_keyframes most recent keyframes (dynref before issue 34; reports/loop_closing.md "
              "compares them)",
              [](auto& o) -> auto& { return o.tracker.relocalisation; }),
      PathKey("vocabulary", "default",
              "dynref (issue 34): default = the embedded models/vocab/dynref_orb_k10_l4.txt; else a vocabulary file in "
              "dynref's format or ORB-SLAM2's ORBvoc.txt (relative to the config file's folder; ref/place/README.md)",
              [](auto& o) -> auto& { return o.vocabulary; }),
  };
}

// Local mapping, local BA and the mapping clock (issue 18).
std::vector<BackboneKeyRow> MappingKeys() {
  return {
      RealAboveKey("ba_chi2_mono", 0, 1e9, "default: ORB-SLAM2 Optimizer::LocalBundleAdjustment 95 % chi2 (2 dof)",
                   [](auto& o) -> auto& { return o.mapper.ba.chi2_mono; }),
      RealAboveKey("ba_chi2_stereo", 0, 1e9, "default: ORB-SLAM2 Optimizer::LocalBundleAdjustment 95 % chi2 (3 dof)",
                   [](auto& o) -> auto& { return o.mapper.ba.chi2_stereo; }),
      IntKey("ba_iterations_refine", 0, 1000, "default: ORB-SLAM2 Optimizer::LocalBundleAdjustment optimize(10) without outliers",
             [](auto& o) -> auto& { return o.mapper.ba.iterations_refine; }),
      FlagKey("ba_weighted_outlier_test",
              "dynref (issue 21): the local BA outlier test uses inv_sigma2 only, a method's weight scales the cost, not the "
              "test; true = inv_sigma2 * weight (ORB-SLAM2 has no weights)",
              [](auto& o) -> auto& { return o.mapper.ba.weighted_outlier_test; }),
      IntKey("ba_iterations_robust", 0, 1000, "default: ORB-SLAM2 Optimizer::LocalBundleAdjustment optimize(5) with Huber",
             [](auto& o) -> auto& { return o.mapper.ba.iterations_robust; }),
      FlagKey("keyframe_culling", "default: ORB-SLAM2 LocalMapping::KeyFrameCulling", [](auto& o) -> auto& { return o.mapper.keyframe_culling; }),
      FlagKey("local_ba", "default: ORB-SLAM2 local mapping runs local BA", [](auto& o) -> auto& { return o.mapper.local_ba; }),
      FlagKey("mapping_clock",
              "dynref (issue 18): local mapping is busy for a virtual time charged per keyframe (ref/mapping/mapping_clock.h), "
              "as ORB-SLAM2's concurrent local mapper; false = idle at every frame (every low-inlier frame becomes a keyframe)",
              [](auto& o) -> auto& { return o.mapping_clock.enabled; }),
      IntKey("mapping_max_queue", 1, 1000, "default: ORB-SLAM2 Tracking::NeedNewKeyFrame KeyframesInQueue() < 3 (RGB-D)",
             [](auto& o) -> auto& { return o.mapping_clock.max_queue; }),
      RealKey("mapping_ms_per_ba_observation", 0, 1e6,
              "dynref (issue 18): not in ORB-SLAM2; virtual cost per local-BA observation, calibrated on the reference machine (ref/mapping/README.md)",
              [](auto& o) -> auto& { return o.mapping_clock.ms_per_ba_observation; }),
      RealKey("mapping_ms_per_keyframe", 0, 1e6,
              "dynref (issue 18): not in ORB-SLAM2; virtual cost per keyframe besides local BA, calibrated on the reference machine (ref/mapping/README.md)",
              [](auto& o) -> auto& { return o.mapping_clock.ms_per_keyframe; }),
  };
}

// Line segments as landmarks (issue 13, seed 000 Sec. 3.2).
std::vector<BackboneKeyRow> LineKeys() {
  return {
      RealAboveKey("line_collinear_m", 0, 1e3,
                   "not stated: a segment's 3-D samples must be collinear within 2 cm + 1 % of depth to create a map line "
                   "(Kinect depth noise at 2-3 m)",
                   [](auto& o) -> auto& { return o.structure.line_collinear_m; }),
      RealKey("line_count_weight", 0, 1e3,
              "not stated: an inlier line counts as one point in ORB-SLAM2's tracking thresholds (PL-SLAM counts "
              "points and lines alike)",
              [](auto& o) -> auto& { return o.structure.line_count_weight; }),
      FlagKey("line_literal_residual",
              "spec 000 E15: false = residual [d_s, d_m, d_e, e_col + e_par] (proposed); true = the literal scalar "
              "e_col + e_par, which cannot constrain a perpendicular shift",
              [](auto& o) -> auto& { return o.structure.residual.literal_line; }),
      RealAboveKey("line_match_angle_deg", 0, 90, "spec 000 E14 (proposed): LBD matching gated by |dtheta| < tau_theta = 3 deg",
                   [](auto& o) -> auto& { return o.structure.line_match_angle_deg; }),
      IntKey("line_match_bits", 0, 256, "not stated: LBD Hamming gate, 90 of 256 bits (ORB-SLAM2's TH_HIGH = 100 of 256 for ORB)",
             [](auto& o) -> auto& { return o.structure.line_match_bits; }),
      RealAboveKey("line_match_px", 0, 1e4,
                   "not stated: projected and observed line midpoints within 15 px of the other line "
                   "(ORB-SLAM2 motion-model window th = 15)",
                   [](auto& o) -> auto& { return o.structure.line_match_px; }),
      IntKey("line_max", 1, 100000, "not stated: at most the 200 longest segments per frame",
             [](auto& o) -> auto& { return o.structure.line.max_lines; }),
      IntKey("line_min_length_px", 2, 10000,
             "not stated: spec 000 step 3 asks for a minimum length; 20 px: shorter FLD segments are mostly texture edges",
             [](auto& o) -> auto& { return o.structure.line.min_length_px; }),
      RealAboveKey("line_parallel_deg", 0, 89, "paper 000 Sec. 3.2: parallel groups within tau_theta = 3 deg",
                   [](auto& o) -> auto& { return o.structure.line.parallel_deg; }),
      FlagKey("line_parallel_term",
              "paper 000 Sec. 3.6: e_l = e_par + e_col with the parallel companion line; false = e_col only (issue 13 measured "
              "e_par's bias: it is not zero at the true pose unless the two lines are parallel in the image)",
              [](auto& o) -> auto& { return o.structure.line_parallel_term; }),
      RealAboveKey("line_sigma_px", 0, 1e3, "not stated: spec 000 (c) suggests Sigma_l = 1 px^2",
                   [](auto& o) -> auto& { return o.structure.residual.line_sigma_px; }),
      FlagKey("lines", "dynref (issue 13): ORB-SLAM2 tracks points only; true = line segments as landmarks (seed 000 Sec. 3.2)",
              [](auto& o) -> auto& { return o.structure.lines; }),
  };
}

// The plane angle sigma is given in degrees and kept in radians.
BackboneKeyRow PlaneAngleSigmaKey() {
  BackboneKeyRow r = RealAboveKey("plane_angle_sigma_deg", 0, 90, "not stated: spec 000 (c) suggests plane angle covariance (1 deg)^2",
                                  [](auto& o) -> auto& { return o.structure.residual.plane_angle_sigma_rad; });
  r.get = [](const BackboneOptions& o) { return o.structure.residual.plane_angle_sigma_rad * 180 / kBackbonePi; };
  r.set = [](BackboneOptions& o, double v) { o.structure.residual.plane_angle_sigma_rad = v * kBackbonePi / 180; };
  return r;
}

// Planes as landmarks (issue 13, seed 000 Sec. 3.2).
std::vector<BackboneKeyRow> PlaneKeys() {
  return {
      PlaneAngleSigmaKey(),
      RealKey("plane_count_weight", 0, 1e3,
              "not stated: an inlier plane counts as 3 points in ORB-SLAM2's tracking thresholds (it fixes 3 dof)",
              [](auto& o) -> auto& { return o.structure.plane_count_weight; }),
      RealAboveKey("plane_dist_sigma_m", 0, 1e3, "not stated: spec 000 (c) suggests plane distance covariance (0.02 m)^2",
                   [](auto& o) -> auto& { return o.structure.residual.plane_dist_sigma_m; }),
      RealAboveKey("plane_match_angle_deg", 0, 90, "not stated: observed-to-map plane normal gate",
                   [](auto& o) -> auto& { return o.structure.plane_match_angle_deg; }),
      RealAboveKey("plane_match_dist_m", 0, 1e3, "not stated: observed-to-map plane distance gate",
                   [](auto& o) -> auto& { return o.structure.plane_match_dist_m; }),
      RealKey("plane_merge_angle_deg", 0, 90,
              "not stated: spec 000 step 4 'merge ... consistent parameters'; map planes merge within 5 deg",
              [](auto& o) -> auto& { return o.structure.plane_merge_angle_deg; }),
      RealKey("plane_merge_dist_m", 0, 1e3, "not stated: spec 000 step 4; map planes merge within 5 cm in d",
              [](auto& o) -> auto& { return o.structure.plane_merge_dist_m; }),
      RealKey("plane_min_area_m2", 0, 1e6,
              "spec 000 (c) T_plane: 'approx. 0.05 m^2 in image space' read as the metric footprint sum Z^2 / (fx fy)",
              [](auto& o) -> auto& { return o.structure.plane.min_area_m2; }),
      FlagKey("planes", "dynref (issue 13): ORB-SLAM2 tracks points only; true = AHC planes as landmarks (seed 000 Sec. 3.2)",
              [](auto& o) -> auto& { return o.structure.planes; }),
  };
}

std::vector<BackboneKeyRow> AllBackboneKeys() {
  std::vector<BackboneKeyRow> rows;
  for (auto part : {FeatureKeys, OnnxKeys, TrackingKeys, PoseKeys, PlaceKeys, MappingKeys, LineKeys, PlaneKeys})
    for (BackboneKeyRow& r : part()) rows.push_back(std::move(r));
  std::stable_sort(rows.begin(), rows.end(),
                   [](const BackboneKeyRow& a, const BackboneKeyRow& b) { return std::strcmp(a.key, b.key) < 0; });
  return rows;
}

}  // namespace

const std::vector<BackboneKeyRow>& BackboneKeyRows() {
  static const std::vector<BackboneKeyRow> rows = AllBackboneKeys();
  return rows;
}

}  // namespace dynref
