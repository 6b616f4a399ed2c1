// The table of backbone keys; see backbone_options.h.
#include "pipeline/backbone_options.h"

#include <cstdio>
#include <functional>

#include "core/error.h"

namespace dynref {
namespace {

// One backbone key: default text, source, and how a (validated) value is stored.
struct KeyRow {
  const char* key;
  const char* default_value;
  const char* source;
  enum class Kind { kInt, kDouble, kBool, kText } kind;
  double lo, hi;        // inclusive range (kInt: checked before the int conversion); unused for kBool, kText
  bool lo_open;         // kDouble: lo excluded (e.g. scale_factor > 1)
  std::function<void(BackboneOptions&, double)> set;  // kInt, kDouble, kBool
  // kText: the allowed values separated by '|' (nullptr = any text) and the setter, which gets
  // the text and the config file it came from (paths are relative to that file's folder).
  const char* choices = nullptr;
  std::function<void(BackboneOptions&, const std::string&, const std::string&)> set_text = nullptr;
};

using K = KeyRow::Kind;

// A relative path read from a config file, as a path from the working directory.
// A value given by `dynref run --set` (its location is "--set ...") is relative to the working
// directory (issue 37).
std::string RelativeTo(const std::string& config_file, const std::string& path) {
  if (path.empty() || path[0] == '/' || config_file.empty() || config_file.rfind("--set", 0) == 0) return path;
  const size_t slash = config_file.find_last_of('/');
  return slash == std::string::npos ? path : config_file.substr(0, slash + 1) + path;
}

const double kMaxExactInt = 9007199254740992.0;  // 2^53: every integer below is exact in a double

// ORB-SLAM2 defaults (Examples/RGB-D/TUM*.yaml, src/Tracking.cc, src/Optimizer.cc). Ranges:
// n_features: the extractor reserves 10 * n_features candidates per level (int arithmetic);
// 100000 is 100x the default. n_levels: one image and scale per level, 16 as OrbOptions::Check.
// FAST thresholds are 8-bit intensity differences. Frame counts are added to frame indices
// (int); 100000 frames (55 min at 30 fps) keeps the sums far from overflow.
const std::vector<KeyRow>& Rows() {
  static const std::vector<KeyRow> rows = {
      {"ba_chi2_mono", "5.991", "default: ORB-SLAM2 Optimizer::LocalBundleAdjustment 95 % chi2 (2 dof)", K::kDouble, 0, 1e9, true,
       [](BackboneOptions& o, double v) { o.mapper.ba.chi2_mono = v; }},
      {"ba_chi2_stereo", "7.815", "default: ORB-SLAM2 Optimizer::LocalBundleAdjustment 95 % chi2 (3 dof)", K::kDouble, 0, 1e9, true,
       [](BackboneOptions& o, double v) { o.mapper.ba.chi2_stereo = v; }},
      {"ba_iterations_refine", "10", "default: ORB-SLAM2 Optimizer::LocalBundleAdjustment optimize(10) without outliers", K::kInt, 0, 1000, false,
       [](BackboneOptions& o, double v) { o.mapper.ba.iterations_refine = static_cast<int>(v); }},
      {"ba_weighted_outlier_test", "false",
       "dynref (issue 21): the local BA outlier test uses inv_sigma2 only, a method's weight scales the cost, not the "
       "test; true = inv_sigma2 * weight (ORB-SLAM2 has no weights)",
       K::kBool, 0, 0, false, [](BackboneOptions& o, double v) { o.mapper.ba.weighted_outlier_test = v != 0; }},
      {"ba_iterations_robust", "5", "default: ORB-SLAM2 Optimizer::LocalBundleAdjustment optimize(5) with Huber", K::kInt, 0, 1000, false,
       [](BackboneOptions& o, double v) { o.mapper.ba.iterations_robust = static_cast<int>(v); }},
      {"bow_matching", "false",
       "dynref (issue 34): false = brute-force keyframe-to-frame matching (dynref before issue 34); true = ORB-SLAM2 "
       "ORBmatcher::SearchByBoW (features under the same vocabulary node, backbone.vocabulary) in reference-keyframe "
       "tracking and relocalisation",
       K::kBool, 0, 0, false, [](BackboneOptions& o, double v) { o.tracker.bow_matching = v != 0; }},
      {"camera_rgb_flag", "true",
       "default: ORB-SLAM2 TUM1-3.yaml Camera.RGB: 1 applied to cv::imread's BGR images "
       "(Tracking::GrabImageRGBD converts with CV_RGB2GRAY, so blue gets red's weight); "
       "false = luminance of the true colours (COLOR_BGR2GRAY)",
       K::kBool, 0, 0, false, [](BackboneOptions& o, double v) { o.camera_rgb_flag = v != 0; }},
      {"depth_edge_rel", "0",
       "dynref (issue 13): not in ORB-SLAM2, whose ComputeStereoFromRGBD samples the keypoint's one pixel (0 = that); "
       "> 0: a keypoint whose 5x5 neighbourhood has a pixel without depth or one differing by more than this fraction "
       "of its depth gets no depth (monocular point): corners on silhouettes otherwise take either side's depth "
       "(a 3-5 % scale bias on static_lowtexture, reports/structure_bench.md)",
       K::kDouble, 0, 1, false, [](BackboneOptions& o, double v) { o.depth_edge_rel = v; }},
      {"descriptor_th_high", "0",
       "dynref (issue 17): projection-search gate in the extractor's distance units; 0 = the extractor's own "
       "(orb: ORBmatcher TH_HIGH 100 bits; sift: 0.60 squared L2 of unit rows; onnx: 4 * 100 / 256 squared L2, spec 004 (c))",
       K::kDouble, 0, 1e9, false, [](BackboneOptions& o, double v) { o.extractor.th_high = v; }},
      {"descriptor_th_low", "0",
       "dynref (issue 17): keyframe-matching / triangulation / fusion gate in the extractor's units; 0 = the extractor's "
       "own (orb: ORBmatcher TH_LOW 50 bits; sift: 0.20; onnx: 4 * 50 / 256)",
       K::kDouble, 0, 1e9, false, [](BackboneOptions& o, double v) { o.extractor.th_low = v; }},
      {"descriptor_th_reloc", "0",
       "dynref (issue 17): relocalisation refinement gate; 0 = the extractor's own (orb: Tracking::Relocalization 64 "
       "bits; sift: 0.30; onnx: 4 * 64 / 256)",
       K::kDouble, 0, 1e9, false, [](BackboneOptions& o, double v) { o.extractor.th_reloc = v; }},
      {"features", "orb",
       "default: ORB-SLAM2's ORBextractor; sift = OpenCV SIFT (float descriptors), onnx = a SuperPoint-style network "
       "(onnx_* keys) (issue 17, seed 004 module B; ref/features/keypoint_extractor.h)",
       K::kText, 0, 0, false, nullptr, "orb|sift|onnx",
       [](BackboneOptions& o, const std::string& v, const std::string&) { o.extractor.type = v; }},
      {"ini_th_fast", "20", "default: ORB-SLAM2 ORBextractor.iniThFAST", K::kInt, 1, 255, false,
       [](BackboneOptions& o, double v) { o.orb.ini_th_fast = static_cast<int>(v); }},
      {"keyframe_culling", "true", "default: ORB-SLAM2 LocalMapping::KeyFrameCulling", K::kBool, 0, 0, false,
       [](BackboneOptions& o, double v) { o.mapper.keyframe_culling = v != 0; }},
      {"line_collinear_m", "0.02",
       "not stated: a segment's 3-D samples must be collinear within 2 cm + 1 % of depth to create a map line "
       "(Kinect depth noise at 2-3 m)",
       K::kDouble, 0, 1e3, true, [](BackboneOptions& o, double v) { o.structure.line_collinear_m = v; }},
      {"line_count_weight", "1",
       "not stated: an inlier line counts as one point in ORB-SLAM2's tracking thresholds (PL-SLAM counts "
       "points and lines alike)",
       K::kDouble, 0, 1e3, false, [](BackboneOptions& o, double v) { o.structure.line_count_weight = v; }},
      {"line_literal_residual", "false",
       "spec 000 E15: false = residual [d_s, d_m, d_e, e_col + e_par] (proposed); true = the literal scalar "
       "e_col + e_par, which cannot constrain a perpendicular shift",
       K::kBool, 0, 0, false, [](BackboneOptions& o, double v) { o.structure.residual.literal_line = v != 0; }},
      {"line_match_angle_deg", "3", "spec 000 E14 (proposed): LBD matching gated by |dtheta| < tau_theta = 3 deg",
       K::kDouble, 0, 90, true, [](BackboneOptions& o, double v) { o.structure.line_match_angle_deg = v; }},
      {"line_match_bits", "90",
       "not stated: LBD Hamming gate, 90 of 256 bits (ORB-SLAM2's TH_HIGH = 100 of 256 for ORB)",
       K::kInt, 0, 256, false, [](BackboneOptions& o, double v) { o.structure.line_match_bits = static_cast<int>(v); }},
      {"line_match_px", "15",
       "not stated: projected and observed line midpoints within 15 px of the other line "
       "(ORB-SLAM2 motion-model window th = 15)",
       K::kDouble, 0, 1e4, true, [](BackboneOptions& o, double v) { o.structure.line_match_px = v; }},
      {"line_max", "200", "not stated: at most the 200 longest segments per frame", K::kInt, 1, 100000, false,
       [](BackboneOptions& o, double v) { o.structure.line.max_lines = static_cast<int>(v); }},
      {"line_min_length_px", "20",
       "not stated: spec 000 step 3 asks for a minimum length; 20 px: shorter FLD segments are mostly texture edges",
       K::kInt, 2, 10000, false, [](BackboneOptions& o, double v) { o.structure.line.min_length_px = static_cast<int>(v); }},
      {"line_parallel_deg", "3", "paper 000 Sec. 3.2: parallel groups within tau_theta = 3 deg", K::kDouble, 0, 89, true,
       [](BackboneOptions& o, double v) { o.structure.line.parallel_deg = v; }},
      {"line_parallel_term", "true",
       "paper 000 Sec. 3.6: e_l = e_par + e_col with the parallel companion line; false = e_col only (issue 13 measured "
       "e_par's bias: it is not zero at the true pose unless the two lines are parallel in the image)",
       K::kBool, 0, 0, false, [](BackboneOptions& o, double v) { o.structure.line_parallel_term = v != 0; }},
      {"line_sigma_px", "1", "not stated: spec 000 (c) suggests Sigma_l = 1 px^2", K::kDouble, 0, 1e3, true,
       [](BackboneOptions& o, double v) { o.structure.residual.line_sigma_px = v; }},
      {"lines", "false",
       "dynref (issue 13): ORB-SLAM2 tracks points only; true = line segments as landmarks (seed 000 Sec. 3.2)",
       K::kBool, 0, 0, false, [](BackboneOptions& o, double v) { o.structure.lines = v != 0; }},
      {"local_ba", "true", "default: ORB-SLAM2 local mapping runs local BA", K::kBool, 0, 0, false,
       [](BackboneOptions& o, double v) { o.mapper.local_ba = v != 0; }},
      {"loop_closing", "false",
       "dynref (issue 34): ORB-SLAM2 runs LoopClosing; off by default until it is validated over seeds 1-3 (reports/loop_closing.md: one seed so far; switching it on changes every golden); "
       "true = ORB-SLAM2's loop detection, SE(3) RANSAC, loop fusion, essential graph and global BA after local "
       "mapping of each keyframe (ref/loop/README.md; backbone.vocabulary)",
       K::kBool, 0, 0, false, [](BackboneOptions& o, double v) { o.loop.enabled = v != 0; }},
      {"loop_global_ba", "true", "default: ORB-SLAM2 LoopClosing::CorrectLoop starts RunGlobalBundleAdjustment (10 iterations)",
       K::kBool, 0, 0, false, [](BackboneOptions& o, double v) { o.loop.global_ba = v != 0; }},
      {"mapping_clock", "true",
       "dynref (issue 18): local mapping is busy for a virtual time charged per keyframe (ref/mapping/mapping_clock.h), "
       "as ORB-SLAM2's concurrent local mapper; false = idle at every frame (every low-inlier frame becomes a keyframe)",
       K::kBool, 0, 0, false, [](BackboneOptions& o, double v) { o.mapping_clock.enabled = v != 0; }},
      {"mapping_max_queue", "3", "default: ORB-SLAM2 Tracking::NeedNewKeyFrame KeyframesInQueue() < 3 (RGB-D)", K::kInt, 1, 1000, false,
       [](BackboneOptions& o, double v) { o.mapping_clock.max_queue = static_cast<int>(v); }},
      {"mapping_ms_per_ba_observation", "0.016",
       "dynref (issue 18): not in ORB-SLAM2; virtual cost per local-BA observation, calibrated on the reference machine (ref/mapping/README.md)",
       K::kDouble, 0, 1e6, false, [](BackboneOptions& o, double v) { o.mapping_clock.ms_per_ba_observation = v; }},
      {"mapping_ms_per_keyframe", "12",
       "dynref (issue 18): not in ORB-SLAM2; virtual cost per keyframe besides local BA, calibrated on the reference machine (ref/mapping/README.md)",
       K::kDouble, 0, 1e6, false, [](BackboneOptions& o, double v) { o.mapping_clock.ms_per_keyframe = v; }},
      {"max_frames", "30", "default: ORB-SLAM2 mMaxFrames = Camera.fps (30)", K::kInt, 1, 100000, false,
       [](BackboneOptions& o, double v) { o.tracker.max_frames = static_cast<int>(v); }},
      {"min_init_points", "500", "default: ORB-SLAM2 Tracking::StereoInitialization N > 500", K::kInt, 1, 100000, false,
       [](BackboneOptions& o, double v) { o.tracker.min_init_points = static_cast<int>(v); }},
      {"min_th_fast", "7", "default: ORB-SLAM2 ORBextractor.minThFAST", K::kInt, 1, 255, false,
       [](BackboneOptions& o, double v) { o.orb.min_th_fast = static_cast<int>(v); }},
      {"mnn2_matching", "false",
       "dynref (issue 17): false = ORB-SLAM2's brute-force rule; true = seed 004 MNN2 (Sec. 3.2: ratio, absolute gate "
       "TH_HIGH equivalent, mutual check) in keyframe-to-frame matching and the triangulation search",
       K::kBool, 0, 0, false, [](BackboneOptions& o, double v) { o.tracker.mnn2.enabled = o.mapper.mnn2.enabled = v != 0; }},
      {"mnn2_ratio", "0.95", "paper 004 Sec. 4.2: MNN2 ratio rho (used when mnn2_matching is true)", K::kDouble, 0, 1, true,
       [](BackboneOptions& o, double v) { o.tracker.mnn2.ratio = o.mapper.mnn2.ratio = v; }},
      {"n_features", "1000", "default: ORB-SLAM2 TUM RGB-D settings ORBextractor.nFeatures", K::kInt, 1, 100000, false,
       [](BackboneOptions& o, double v) { o.orb.n_features = static_cast<int>(v); }},
      {"n_levels", "8", "default: ORB-SLAM2 ORBextractor.nLevels", K::kInt, 1, 16, false,
       [](BackboneOptions& o, double v) { o.orb.n_levels = static_cast<int>(v); }},
      {"onnx_binary", "false",
       "dynref (issue 17): pack the network's descriptor signs into bits (ZippyPoint's binary head; Hamming gates)",
       K::kBool, 0, 0, false, [](BackboneOptions& o, double v) { o.extractor.onnx.binary = v != 0; }},
      {"onnx_border", "4", "not stated: SuperPoint's remove_borders default (keypoints this close to the edge are dropped)",
       K::kInt, 0, 1000, false, [](BackboneOptions& o, double v) { o.extractor.onnx.border = static_cast<int>(v); }},
      {"onnx_descriptor_output", "descriptors", "dynref (issue 17): name of the network's 1 x D x Hd x Wd descriptor output",
       K::kText, 0, 0, false, nullptr, nullptr,
       [](BackboneOptions& o, const std::string& v, const std::string&) { o.extractor.onnx.descriptor_output = v; }},
      {"onnx_model", "", "dynref (issue 17): the .onnx file of features: onnx (relative to the config file's folder)",
       K::kText, 0, 0, false, nullptr, nullptr,
       [](BackboneOptions& o, const std::string& v, const std::string& file) { o.extractor.onnx.model = RelativeTo(file, v); }},
      {"onnx_nms_radius", "3", "paper 004 Sec. 4.1: NMS radius 3", K::kInt, 0, 100, false,
       [](BackboneOptions& o, double v) { o.extractor.onnx.nms_radius = static_cast<int>(v); }},
      {"onnx_score_output", "scores",
       "dynref (issue 17): name of the network's score output (1 x 65 x H/8 x W/8 logits or 1 x 1 x H x W)",
       K::kText, 0, 0, false, nullptr, nullptr,
       [](BackboneOptions& o, const std::string& v, const std::string&) { o.extractor.onnx.score_output = v; }},
      {"onnx_score_threshold", "0.015", "paper 004 Sec. 4.1: keypoint score > 0.015", K::kDouble, 0, 1, false,
       [](BackboneOptions& o, double v) { o.extractor.onnx.score_threshold = v; }},
      {"plane_angle_sigma_deg", "1", "not stated: spec 000 (c) suggests plane angle covariance (1 deg)^2", K::kDouble, 0, 90, true,
       [](BackboneOptions& o, double v) { o.structure.residual.plane_angle_sigma_rad = v * 3.14159265358979323846 / 180; }},
      {"plane_count_weight", "3",
       "not stated: an inlier plane counts as 3 points in ORB-SLAM2's tracking thresholds (it fixes 3 dof)",
       K::kDouble, 0, 1e3, false, [](BackboneOptions& o, double v) { o.structure.plane_count_weight = v; }},
      {"plane_dist_sigma_m", "0.02", "not stated: spec 000 (c) suggests plane distance covariance (0.02 m)^2", K::kDouble, 0, 1e3, true,
       [](BackboneOptions& o, double v) { o.structure.residual.plane_dist_sigma_m = v; }},
      {"plane_match_angle_deg", "10", "not stated: observed-to-map plane normal gate", K::kDouble, 0, 90, true,
       [](BackboneOptions& o, double v) { o.structure.plane_match_angle_deg = v; }},
      {"plane_match_dist_m", "0.1", "not stated: observed-to-map plane distance gate", K::kDouble, 0, 1e3, true,
       [](BackboneOptions& o, double v) { o.structure.plane_match_dist_m = v; }},
      {"plane_merge_angle_deg", "5", "not stated: spec 000 step 4 'merge ... consistent parameters'; map planes merge within 5 deg",
       K::kDouble, 0, 90, false, [](BackboneOptions& o, double v) { o.structure.plane_merge_angle_deg = v; }},
      {"plane_merge_dist_m", "0.05", "not stated: spec 000 step 4; map planes merge within 5 cm in d", K::kDouble, 0, 1e3, false,
       [](BackboneOptions& o, double v) { o.structure.plane_merge_dist_m = v; }},
      {"plane_min_area_m2", "0.05",
       "spec 000 (c) T_plane: 'approx. 0.05 m^2 in image space' read as the metric footprint sum Z^2 / (fx fy)",
       K::kDouble, 0, 1e6, false, [](BackboneOptions& o, double v) { o.structure.plane.min_area_m2 = v; }},
      {"planes", "false",
       "dynref (issue 13): ORB-SLAM2 tracks points only; true = AHC planes as landmarks (seed 000 Sec. 3.2)",
       K::kBool, 0, 0, false, [](BackboneOptions& o, double v) { o.structure.planes = v != 0; }},
      {"pose_chi2_mono", "5.991", "default: ORB-SLAM2 Optimizer::PoseOptimization 95 % chi2 (2 dof)", K::kDouble, 0, 1e9, true,
       [](BackboneOptions& o, double v) { o.tracker.pose.chi2_mono = v; }},
      {"pose_chi2_stereo", "7.815", "default: ORB-SLAM2 Optimizer::PoseOptimization 95 % chi2 (3 dof)", K::kDouble, 0, 1e9, true,
       [](BackboneOptions& o, double v) { o.tracker.pose.chi2_stereo = v; }},
      {"pose_iterations", "10", "default: ORB-SLAM2 Optimizer::PoseOptimization optimize(its[it]) with its = 10", K::kInt, 1, 1000, false,
       [](BackboneOptions& o, double v) { o.tracker.pose.iterations = static_cast<int>(v); }},
      {"pose_min_edges", "10", "default: ORB-SLAM2 Optimizer::PoseOptimization stops when optimizer.edges().size() < 10", K::kInt, 0, 100000, false,
       [](BackboneOptions& o, double v) { o.tracker.pose.min_edges = static_cast<int>(v); }},
      {"pose_weighted_outlier_test", "false",
       "dynref (issue 21): the pose-only outlier test uses inv_sigma2 only, a method's weight scales the cost, not "
       "the test; true = inv_sigma2 * weight (ORB-SLAM2 has no weights)",
       K::kBool, 0, 0, false, [](BackboneOptions& o, double v) { o.tracker.pose.weighted_outlier_test = v != 0; }},
      {"pose_rounds", "4", "default: ORB-SLAM2 Optimizer::PoseOptimization 4 rounds", K::kInt, 1, 100, false,
       [](BackboneOptions& o, double v) { o.tracker.pose.rounds = static_cast<int>(v); }},
      {"reloc_recent_keyframes", "10",
       "not stated: dynref has no BoW database; relocalisation tries the 10 most recent keyframes", K::kInt, 1, 100000, false,
       [](BackboneOptions& o, double v) { o.tracker.reloc_recent_keyframes = static_cast<int>(v); }},
      {"relocalisation", "recent",
       "dynref (issue 34): recent = the reloc_recent_keyframes most recent keyframes (dynref before issue 34); bow = "
       "ORB-SLAM2 KeyFrameDatabase::DetectRelocalizationCandidates over the whole map (backbone.vocabulary)",
       K::kText, 0, 0, false, nullptr, "recent|bow",
       [](BackboneOptions& o, const std::string& v, const std::string&) { o.tracker.relocalisation = v; }},
      {"scale_factor", "1.2", "default: ORB-SLAM2 ORBextractor.scaleFactor", K::kDouble, 1, 1e9, true,
       [](BackboneOptions& o, double v) { o.orb.scale_factor = v; }},
      {"seed", "1", "not stated: seed of dynref's named RNG streams (relocalisation and loop-closing RANSAC)", K::kInt, 0, kMaxExactInt, false,
       [](BackboneOptions& o, double v) { o.tracker.seed = o.loop.seed = static_cast<uint64_t>(v); }},
      {"vocabulary", "default",
       "dynref (issue 34): default = the embedded models/vocab/dynref_orb_k10_l4.txt; else a vocabulary file in "
       "dynref's format or ORB-SLAM2's ORBvoc.txt (relative to the config file's folder; ref/place/README.md)",
       K::kText, 0, 0, false, nullptr, nullptr,
       [](BackboneOptions& o, const std::string& v, const std::string& file) {
         o.vocabulary = v == "default" ? v : RelativeTo(file, v);
       }},
  };
  return rows;
}

std::string RangeText(const KeyRow& r) {
  if (r.kind == K::kInt)
    return "must be in " + std::to_string(static_cast<int64_t>(r.lo)) + ".." + std::to_string(static_cast<int64_t>(r.hi));
  // Both bounds (a value above hi was told "must be > 0", issue 37).
  char lo[32], hi[32];
  std::snprintf(lo, sizeof(lo), "%g", r.lo);
  std::snprintf(hi, sizeof(hi), "%g", r.hi);
  return std::string("must be in ") + (r.lo_open ? "(" : "[") + lo + ", " + hi + "]";
}

// Value of a validated param as a double (bools 0/1).
double ReadValue(const KeyRow& r, const Param& p) {
  auto bad = [&](const std::string& what) {
    throw InputError(p.file, p.line, std::string("backbone.") + r.key + ": " + what);
  };
  if (r.kind == K::kBool) return p.AsBool() ? 1.0 : 0.0;
  if (r.kind == K::kText) {
    if (!p.list.empty()) bad("must be a single value");
    if (r.choices != nullptr) {
      const std::string allowed = std::string("|") + r.choices + "|";
      if (allowed.find("|" + p.value + "|") == std::string::npos) bad(std::string("must be one of ") + r.choices + ", got '" + p.value + "'");
    }
    return 0;
  }
  const double v = p.AsDouble();
  const bool below = r.lo_open ? !(v > r.lo) : !(v >= r.lo);
  if (below || !(v <= r.hi)) bad(RangeText(r) + ", got " + p.value);
  if (r.kind == K::kInt) (void)p.AsInt();  // integral (after the range check: no wrap-around)
  return v;
}

}  // namespace

features::ExtractorOptions BackboneOptions::Extractor() const {
  features::ExtractorOptions e = extractor;
  e.orb = orb;
  e.sift.n_features = e.onnx.n_features = orb.n_features;
  return e;
}

void BackboneOptions::Check() const {
  Extractor().Check();  // ORB options included
  tracker.Check();
  loop.Check();
  mapper.Check();
  mapping_clock.Check();
  structure.Check();
}

std::vector<BackboneKeyInfo> BackboneKeys() {
  std::vector<BackboneKeyInfo> out;
  for (const KeyRow& r : Rows()) out.push_back({r.key, r.default_value, r.source});
  return out;
}

BackboneOptions ResolveBackbone(const std::map<std::string, Param>& given, const std::string& config_path,
                                std::map<std::string, Param>* resolved) {
  for (const auto& [key, p] : given) {
    bool known = false;
    for (const KeyRow& r : Rows()) known = known || key == r.key;
    if (!known) throw InputError(p.file, p.line, "unknown backbone key '" + key + "'");
  }
  BackboneOptions o;
  std::map<std::string, Param> all;
  for (const KeyRow& r : Rows()) {
    auto it = given.find(r.key);
    Param p;
    if (it != given.end()) {
      p = it->second;
    } else {
      p.value = r.default_value;
      p.source = r.source;
      p.file = config_path;
    }
    const double v = ReadValue(r, p);
    if (r.kind == K::kText) r.set_text(o, p.value, p.file);
    else r.set(o, v);
    all[r.key] = p;
  }
  if (o.orb.min_th_fast > o.orb.ini_th_fast) {
    const Param& p = all.at("min_th_fast");
    throw InputError(p.file, p.line, "backbone.min_th_fast: need 1 <= min_th_fast <= ini_th_fast");
  }
  if (o.UsesVocabulary() && o.extractor.type != "orb") {
    const Param& p = all.at(o.loop.enabled ? "loop_closing" : o.tracker.relocalisation == "bow" ? "relocalisation" : "bow_matching");
    throw InputError(p.file, p.line, "backbone: the vocabulary needs features: orb (ref/place/README.md 'Float descriptors')");
  }
  if (o.tracker.bow_matching && o.tracker.mnn2.enabled) {
    const Param& p = all.at("bow_matching");
    throw InputError(p.file, p.line, "backbone.bow_matching and backbone.mnn2_matching are exclusive");
  }
  if (o.extractor.type == "onnx" && o.extractor.onnx.model.empty()) {
    const Param& p = all.at("features");
    throw InputError(p.file, p.line, "backbone.features: onnx needs backbone.onnx_model");
  }
  o.Check();
  if (resolved != nullptr) *resolved = std::move(all);
  return o;
}

}  // namespace dynref
