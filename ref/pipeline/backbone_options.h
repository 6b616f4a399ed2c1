// Typed backbone options (issue 12): one struct with the ORB-SLAM2 defaults, read once from a
// config's `backbone:` map through a single table of keys (backbone_keys.cpp), so that a new
// backbone parameter is one struct field (with its default) plus one table row (key, field, range,
// source). The struct is the only place of a default (issue 33): a key's default text is read
// from BackboneOptions{}. Each key's default and source are recorded in the resolved config
// (run.json, trace header).
#pragma once
#include <map>
#include <string>
#include <vector>

#include "features/keypoint_extractor.h"
#include "loop/loop_closer.h"
#include "mapping/local_mapper.h"
#include "mapping/mapping_clock.h"
#include "structure/structure_options.h"
#include "method/params.h"
#include "tracking/tracker.h"

namespace dynref {

struct BackboneOptions {
  features::OrbOptions orb;
  // Extractor choice, SIFT / ONNX settings and gate overrides (issue 17); Extractor() completes
  // it with orb and n_features.
  features::ExtractorOptions extractor;
  tracking::TrackerOptions tracker;    // includes the pose-only optimisation options
  mapping::LocalMapperOptions mapper;  // includes the local BA options
  mapping::MappingClockOptions mapping_clock;  // when local mapping counts as busy (issue 18)
  structure::StructureOptions structure;       // lines and planes (issue 13), off by default
  // ORB-SLAM2 TUM1-3.yaml Camera.RGB: 1 applied to cv::imread's BGR images (see the key's source).
  bool camera_rgb_flag = true;
  // Keypoints on depth discontinuities get no depth when > 0 (Frame::FinishFeatures; 0 = ORB-SLAM2).
  double depth_edge_rel = 0;
  // Issue 34: "default" (embedded) or a vocabulary file; read when UsesVocabulary().
  std::string vocabulary = "default";
  loop::LoopClosingOptions loop;  // issue 34, ref/loop (seed: tracker.seed)
  bool UsesVocabulary() const { return tracker.relocalisation == "bow" || tracker.bow_matching || loop.enabled; }
  features::ExtractorOptions Extractor() const;
  void Check() const;  // InputError naming the bad field
};

struct BackboneKeyInfo {
  std::string key;
  std::string default_value;  // as written in the resolved config: BackboneOptions{}'s value
  std::string source;         // ORB-SLAM2 file / function the default comes from
  std::string type;           // int | real | bool | text
  double lo = 0, hi = 0;      // int, real: the inclusive range (real: lo excluded when lo_open)
  bool lo_open = false;
  std::string choices;        // text: the allowed values separated by '|' (empty: any)
};
// Every backbone key, in name order.
std::vector<BackboneKeyInfo> BackboneKeys();
// The value of a key in `o` as a config writes it ("5.991", "true", "orb"); std::invalid_argument
// for an unknown key.
std::string BackboneKeyText(const BackboneOptions& o, const std::string& key);
// Sets one key from its text as a config value would (range-checked; InputError naming `file`).
void SetBackboneKey(BackboneOptions& o, const std::string& key, const std::string& text, const std::string& file = "");

// Fills `params` with every backbone key (given ones as given, the others with their default and
// source, file = config path) and returns the typed options. InputError (file:line) for an
// unknown key, a value of the wrong type or out of range.
BackboneOptions ResolveBackbone(const std::map<std::string, Param>& given, const std::string& config_path,
                                std::map<std::string, Param>* resolved);

}  // namespace dynref
