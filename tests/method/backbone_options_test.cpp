// Typed backbone options (issue 12): the table of keys and the struct defaults agree, every key
// reaches its field, pose and BA options are configurable.
#include <catch2/catch.hpp>
#include <regex>

#include "core/error.h"
#include "pipeline/backbone_options.h"

using namespace dynref;

namespace {

Param P(const std::string& value) {
  Param p;
  p.value = value;
  p.source = "test";
  p.file = "t.yaml";
  p.line = 5;
  return p;
}

}  // namespace

TEST_CASE("backbone options: every key's default equals the struct's default") {
  std::map<std::string, Param> resolved;
  const BackboneOptions o = ResolveBackbone({}, "t.yaml", &resolved);
  const BackboneOptions d;
  CHECK(resolved.size() == BackboneKeys().size());
  CHECK(o.orb.n_features == d.orb.n_features);
  CHECK(o.orb.scale_factor == d.orb.scale_factor);
  CHECK(o.orb.n_levels == d.orb.n_levels);
  CHECK(o.orb.ini_th_fast == d.orb.ini_th_fast);
  CHECK(o.orb.min_th_fast == d.orb.min_th_fast);
  CHECK(o.tracker.min_init_points == d.tracker.min_init_points);
  CHECK(o.tracker.max_frames == d.tracker.max_frames);
  CHECK(o.tracker.reloc_recent_keyframes == d.tracker.reloc_recent_keyframes);
  CHECK(o.tracker.seed == d.tracker.seed);
  CHECK(o.tracker.pose.rounds == d.tracker.pose.rounds);
  CHECK(o.tracker.pose.iterations == d.tracker.pose.iterations);
  CHECK(o.tracker.pose.chi2_mono == d.tracker.pose.chi2_mono);
  CHECK(o.tracker.pose.chi2_stereo == d.tracker.pose.chi2_stereo);
  CHECK(o.tracker.pose.min_edges == d.tracker.pose.min_edges);
  CHECK(o.mapper.local_ba == d.mapper.local_ba);
  CHECK(o.mapper.keyframe_culling == d.mapper.keyframe_culling);
  CHECK(o.mapper.ba.iterations_robust == d.mapper.ba.iterations_robust);
  CHECK(o.mapper.ba.iterations_refine == d.mapper.ba.iterations_refine);
  CHECK(o.mapper.ba.chi2_mono == d.mapper.ba.chi2_mono);
  CHECK(o.mapper.ba.chi2_stereo == d.mapper.ba.chi2_stereo);
  CHECK(o.camera_rgb_flag == d.camera_rgb_flag);
  CHECK(o.tracker.pose.weighted_outlier_test == d.tracker.pose.weighted_outlier_test);
  CHECK(o.mapper.ba.weighted_outlier_test == d.mapper.ba.weighted_outlier_test);
  CHECK(o.mapping_clock.enabled == d.mapping_clock.enabled);
  CHECK(o.mapping_clock.ms_per_keyframe == d.mapping_clock.ms_per_keyframe);
  CHECK(o.mapping_clock.ms_per_ba_observation == d.mapping_clock.ms_per_ba_observation);
  CHECK(o.mapping_clock.max_queue == d.mapping_clock.max_queue);
  // Lines and planes (issue 13): the table's defaults are the StructureOptions defaults.
  CHECK(o.structure.lines == d.structure.lines);
  CHECK(o.structure.planes == d.structure.planes);
  CHECK(o.structure.line.min_length_px == d.structure.line.min_length_px);
  CHECK(o.structure.line.parallel_deg == d.structure.line.parallel_deg);
  CHECK(o.structure.line.max_lines == d.structure.line.max_lines);
  CHECK(o.structure.line_match_bits == d.structure.line_match_bits);
  CHECK(o.structure.line_match_angle_deg == d.structure.line_match_angle_deg);
  CHECK(o.structure.line_match_px == d.structure.line_match_px);
  CHECK(o.structure.line_collinear_m == d.structure.line_collinear_m);
  CHECK(o.structure.line_parallel_term == d.structure.line_parallel_term);
  CHECK(o.structure.residual.literal_line == d.structure.residual.literal_line);
  CHECK(o.structure.residual.line_sigma_px == d.structure.residual.line_sigma_px);
  CHECK(o.structure.residual.plane_angle_sigma_rad == Approx(d.structure.residual.plane_angle_sigma_rad));
  CHECK(o.structure.residual.plane_dist_sigma_m == d.structure.residual.plane_dist_sigma_m);
  CHECK(o.structure.plane.min_area_m2 == d.structure.plane.min_area_m2);
  CHECK(o.structure.plane_match_angle_deg == d.structure.plane_match_angle_deg);
  CHECK(o.structure.plane_match_dist_m == d.structure.plane_match_dist_m);
  CHECK(o.structure.plane_merge_angle_deg == d.structure.plane_merge_angle_deg);
  CHECK(o.structure.plane_merge_dist_m == d.structure.plane_merge_dist_m);
  CHECK(o.structure.line_count_weight == d.structure.line_count_weight);
  CHECK(o.structure.plane_count_weight == d.structure.plane_count_weight);
  // Feature plug-in (issue 17): ORB with its own gates, ORB-SLAM2's brute-force rule.
  const features::ExtractorOptions xo = o.Extractor(), xd = d.Extractor();
  CHECK(xo.type == xd.type);
  CHECK(xo.type == "orb");
  CHECK(xo.th_low == xd.th_low);
  CHECK(xo.th_high == xd.th_high);
  CHECK(xo.th_reloc == xd.th_reloc);
  CHECK(xo.onnx.model == xd.onnx.model);
  CHECK(xo.onnx.score_output == xd.onnx.score_output);
  CHECK(xo.onnx.descriptor_output == xd.onnx.descriptor_output);
  CHECK(xo.onnx.score_threshold == xd.onnx.score_threshold);
  CHECK(xo.onnx.nms_radius == xd.onnx.nms_radius);
  CHECK(xo.onnx.border == xd.onnx.border);
  CHECK(xo.onnx.binary == xd.onnx.binary);
  CHECK(o.tracker.mnn2.enabled == d.tracker.mnn2.enabled);
  CHECK(o.mapper.mnn2.enabled == d.mapper.mnn2.enabled);
  CHECK(o.tracker.mnn2.ratio == d.tracker.mnn2.ratio);
  for (const auto& [key, p] : resolved) {
    INFO(key);
    CHECK((p.source.rfind("default:", 0) == 0 || p.source.rfind("not stated:", 0) == 0 ||
           std::regex_search(p.source, std::regex("^dynref \\(issue [0-9]+\\): ")) ||
           p.source.rfind("paper 000 ", 0) == 0 || p.source.rfind("paper 004 ", 0) == 0 ||
           p.source.rfind("spec 000 ", 0) == 0));
  }
}

TEST_CASE("backbone options: given values reach their fields, bad ones name file:line") {
  const BackboneOptions o = ResolveBackbone(
      {{"pose_rounds", P("2")}, {"ba_iterations_refine", P("3")}, {"pose_chi2_stereo", P("9.5")},
       {"local_ba", P("false")}, {"n_features", P("3000")}},
      "t.yaml", nullptr);
  CHECK(o.tracker.pose.rounds == 2);
  CHECK(o.mapper.ba.iterations_refine == 3);
  CHECK(o.tracker.pose.chi2_stereo == 9.5);
  CHECK_FALSE(o.mapper.local_ba);
  CHECK(o.orb.n_features == 3000);
  using Catch::Matchers::Contains;
  CHECK_THROWS_WITH(ResolveBackbone({{"pose_rounds", P("0")}}, "t.yaml", nullptr),
                    Contains("t.yaml:5: backbone.pose_rounds: must be in 1..100, got 0"));
  CHECK_THROWS_WITH(ResolveBackbone({{"ba_chi2_mono", P("0")}}, "t.yaml", nullptr),
                    Contains("backbone.ba_chi2_mono: must be in (0, 1e+09]"));
  CHECK_THROWS_WITH(ResolveBackbone({{"scale_factor", P("1")}}, "t.yaml", nullptr),
                    Contains("backbone.scale_factor: must be in (1, 1e+09]"));
  CHECK_THROWS_WITH(ResolveBackbone({{"nope", P("1")}}, "t.yaml", nullptr), Contains("unknown backbone key 'nope'"));
  CHECK_THROWS_AS(ResolveBackbone({{"local_ba", P("1")}}, "t.yaml", nullptr), InputError);
}

TEST_CASE("backbone options: the feature plug-in keys (issue 17) reach the extractor options, bad ones name file:line") {
  Param model = P("models/sp.onnx");
  model.file = "cfg/t.yaml";
  const BackboneOptions o = ResolveBackbone(
      {{"features", P("onnx")}, {"onnx_model", model}, {"onnx_binary", P("true")},
       {"descriptor_th_low", P("0.3")}, {"mnn2_matching", P("true")}, {"mnn2_ratio", P("0.9")}, {"n_features", P("800")}},
      "cfg/t.yaml", nullptr);
  const features::ExtractorOptions x = o.Extractor();
  CHECK(x.type == "onnx");
  // A relative model path is relative to the config file's folder.
  CHECK(x.onnx.model == "cfg/models/sp.onnx");
  CHECK(x.onnx.binary);
  CHECK(x.onnx.n_features == 800);
  CHECK(x.sift.n_features == 800);
  CHECK(x.th_low == 0.3);
  CHECK(o.tracker.mnn2.enabled);
  CHECK(o.mapper.mnn2.enabled);
  CHECK(o.mapper.mnn2.ratio == 0.9);
  using Catch::Matchers::Contains;
  CHECK_THROWS_WITH(ResolveBackbone({{"features", P("surf")}}, "t.yaml", nullptr),
                    Contains("t.yaml:5: backbone.features: must be one of orb|sift|onnx, got 'surf'"));
  CHECK_THROWS_WITH(ResolveBackbone({{"features", P("onnx")}}, "t.yaml", nullptr),
                    Contains("t.yaml:5: backbone.features: onnx needs backbone.onnx_model"));
  CHECK_THROWS_WITH(ResolveBackbone({{"mnn2_ratio", P("0")}}, "t.yaml", nullptr), Contains("backbone.mnn2_ratio: must be in (0, 1], got 0"));
}
