// Typed backbone options (issue 12): one source per default (issue 33: a key's default text is
// read from the struct, and every key reads and writes the same field(s)), every key reaches its
// field, pose and BA options are configurable.
#include <catch2/catch.hpp>
#include <cstdint>
#include <map>
#include <regex>
#include <stdexcept>
#include <string>

#include "core/error.h"
#include "core/format.h"
#include "pipeline/backbone_options.h"

using namespace dynref;

namespace {

Param BackboneTestParam(const std::string& value) {
  Param p;
  p.value = value;
  p.source = "test";
  p.file = "t.yaml";
  p.line = 5;
  return p;
}

std::map<std::string, std::string> BackboneTexts(const BackboneOptions& o) {
  std::map<std::string, std::string> texts;
  for (const BackboneKeyInfo& k : BackboneKeys()) texts[k.key] = BackboneKeyText(o, k.key);
  return texts;
}

// A valid value of the key other than its default.
std::string OtherBackboneValue(const BackboneKeyInfo& k) {
  if (k.type == "bool") return k.default_value == "true" ? "false" : "true";
  if (k.type == "text") {
    std::string rest = k.choices;
    while (!rest.empty()) {
      const size_t bar = rest.find('|');
      const std::string choice = rest.substr(0, bar);
      if (choice != k.default_value) return choice;
      rest = bar == std::string::npos ? "" : rest.substr(bar + 1);
    }
    return "other/value.txt";
  }
  const double v = std::stod(k.default_value);
  const double other = v != k.hi ? k.hi : k.lo_open ? (k.lo + k.hi) / 2 : k.lo;
  return k.type == "int" ? std::to_string(static_cast<int64_t>(other)) : FormatDouble17(other);
}

}  // namespace

TEST_CASE("backbone options: every key's default is the struct's and reads back as the struct's value") {
  std::map<std::string, Param> resolved;
  const BackboneOptions o = ResolveBackbone({}, "t.yaml", &resolved);
  const std::map<std::string, std::string> defaults = BackboneTexts(BackboneOptions{});
  REQUIRE(resolved.size() == BackboneKeys().size());
  REQUIRE(defaults.size() == BackboneKeys().size());
  for (const BackboneKeyInfo& k : BackboneKeys()) {
    INFO(k.key);
    CHECK(k.default_value == defaults.at(k.key));
    CHECK(resolved.at(k.key).value == k.default_value);
    // The default text, read and set as a config value, gives the struct's value back.
    CHECK(BackboneKeyText(o, k.key) == k.default_value);
  }
  // Beyond the keys' text: fields compared as numbers.
  const BackboneOptions d;
  CHECK(o.structure.residual.plane_angle_sigma_rad == d.structure.residual.plane_angle_sigma_rad);
  CHECK(o.mapper.mnn2.ratio == d.mapper.mnn2.ratio);
  CHECK(o.loop.seed == d.loop.seed);
  const features::ExtractorOptions xo = o.Extractor(), xd = d.Extractor();
  CHECK(xo.type == "orb");
  CHECK(xo.sift.n_features == xd.sift.n_features);
  CHECK(xo.onnx.n_features == xd.onnx.n_features);
  for (const auto& [key, p] : resolved) {
    INFO(key);
    CHECK((p.source.rfind("default:", 0) == 0 || p.source.rfind("not stated:", 0) == 0 ||
           std::regex_search(p.source, std::regex("^dynref \\(issue [0-9]+\\): ")) ||
           p.source.rfind("paper 000 ", 0) == 0 || p.source.rfind("paper 004 ", 0) == 0 ||
           p.source.rfind("spec 000 ", 0) == 0));
  }
}

TEST_CASE("backbone options: every key writes the field(s) it reads and no other key's") {
  const std::map<std::string, std::string> defaults = BackboneTexts(BackboneOptions{});
  for (const BackboneKeyInfo& k : BackboneKeys()) {
    INFO(k.key);
    const std::string other = OtherBackboneValue(k);
    BackboneOptions o;
    SetBackboneKey(o, k.key, other, "");
    std::map<std::string, std::string> expected = defaults;
    const std::map<std::string, std::string> texts = BackboneTexts(o);  // throws if mirrored fields differ
    if (k.type == "int" || k.type == "real") {
      CHECK(std::stod(texts.at(k.key)) == std::stod(other));
      expected[k.key] = texts.at(k.key);
    } else {
      expected[k.key] = other;
    }
    CHECK(texts.at(k.key) != k.default_value);
    CHECK(texts == expected);
  }
}

TEST_CASE("backbone options: given values reach their fields, bad ones name file:line") {
  const BackboneOptions o = ResolveBackbone(
      {{"pose_rounds", BackboneTestParam("2")}, {"ba_iterations_refine", BackboneTestParam("3")},
       {"pose_chi2_stereo", BackboneTestParam("9.5")}, {"local_ba", BackboneTestParam("false")},
       {"n_features", BackboneTestParam("3000")}},
      "t.yaml", nullptr);
  CHECK(o.tracker.pose.rounds == 2);
  CHECK(o.mapper.ba.iterations_refine == 3);
  CHECK(o.tracker.pose.chi2_stereo == 9.5);
  CHECK_FALSE(o.mapper.local_ba);
  CHECK(o.orb.n_features == 3000);
  using Catch::Matchers::Contains;
  CHECK_THROWS_WITH(ResolveBackbone({{"pose_rounds", BackboneTestParam("0")}}, "t.yaml", nullptr),
                    Contains("t.yaml:5: backbone.pose_rounds: must be in 1..100, got 0"));
  CHECK_THROWS_WITH(ResolveBackbone({{"ba_chi2_mono", BackboneTestParam("0")}}, "t.yaml", nullptr),
                    Contains("backbone.ba_chi2_mono: must be in (0, 1e+09]"));
  CHECK_THROWS_WITH(ResolveBackbone({{"scale_factor", BackboneTestParam("1")}}, "t.yaml", nullptr),
                    Contains("backbone.scale_factor: must be in (1, 1e+09]"));
  CHECK_THROWS_WITH(ResolveBackbone({{"nope", BackboneTestParam("1")}}, "t.yaml", nullptr),
                    Contains("unknown backbone key 'nope'"));
  CHECK_THROWS_AS(ResolveBackbone({{"local_ba", BackboneTestParam("1")}}, "t.yaml", nullptr), InputError);
  BackboneOptions s;
  CHECK_THROWS_WITH(SetBackboneKey(s, "pose_rounds", "0", "cli"), Contains("backbone.pose_rounds: must be in 1..100, got 0"));
  CHECK_THROWS_AS(BackboneKeyText(s, "nope"), std::invalid_argument);
}

TEST_CASE("backbone options: the feature plug-in keys (issue 17) reach the extractor options, bad ones name file:line") {
  Param model = BackboneTestParam("models/sp.onnx");
  model.file = "cfg/t.yaml";
  const BackboneOptions o = ResolveBackbone(
      {{"features", BackboneTestParam("onnx")}, {"onnx_model", model}, {"onnx_binary", BackboneTestParam("true")},
       {"descriptor_th_low", BackboneTestParam("0.3")}, {"mnn2_matching", BackboneTestParam("true")},
       {"mnn2_ratio", BackboneTestParam("0.9")}, {"n_features", BackboneTestParam("800")}},
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
  CHECK_THROWS_WITH(ResolveBackbone({{"features", BackboneTestParam("surf")}}, "t.yaml", nullptr),
                    Contains("t.yaml:5: backbone.features: must be one of orb|sift|onnx, got 'surf'"));
  CHECK_THROWS_WITH(ResolveBackbone({{"features", BackboneTestParam("onnx")}}, "t.yaml", nullptr),
                    Contains("t.yaml:5: backbone.features: onnx needs backbone.onnx_model"));
  CHECK_THROWS_WITH(ResolveBackbone({{"mnn2_ratio", BackboneTestParam("0")}}, "t.yaml", nullptr),
                    Contains("backbone.mnn2_ratio: must be in (0, 1], got 0"));
}

TEST_CASE("backbone options: loop closing and BoW relocalisation on by default, off by default without a vocabulary") {
  std::map<std::string, Param> resolved;
  const BackboneOptions orb = ResolveBackbone({}, "t.yaml", &resolved);
  CHECK(orb.loop.enabled);  // ORB-SLAM2 runs LoopClosing (issue 34)
  CHECK(orb.tracker.relocalisation == "bow");
  CHECK(resolved.at("loop_closing").defaulted);
  // Float descriptors have no vocabulary: the defaults fall back, and the source says why.
  const BackboneOptions sift = ResolveBackbone({{"features", BackboneTestParam("sift")}}, "t.yaml", &resolved);
  CHECK_FALSE(sift.loop.enabled);
  CHECK(sift.tracker.relocalisation == "recent");
  CHECK(resolved.at("loop_closing").source.find("has no vocabulary") != std::string::npos);
  // Resolved again with ORB (as `--set backbone.features=orb` does): the defaults come back.
  resolved.at("features") = BackboneTestParam("orb");
  const BackboneOptions again = ResolveBackbone(resolved, "t.yaml", &resolved);
  CHECK(again.loop.enabled);
  CHECK(again.tracker.relocalisation == "bow");
  // Set explicitly with float descriptors: refused at the key's line.
  using Catch::Matchers::Contains;
  CHECK_THROWS_WITH(ResolveBackbone({{"features", BackboneTestParam("sift")}, {"loop_closing", BackboneTestParam("true")}},
                                    "t.yaml", nullptr),
                    Contains("t.yaml:5: backbone: the vocabulary needs features: orb"));
}
