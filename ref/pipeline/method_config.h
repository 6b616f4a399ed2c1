// Method configuration (configs/<method>.yaml): every parameter is {value: X, source: "..."}
// where source is "paper Sec. ..." or "not stated: chosen because ...". Structure:
//   method: NAME
//   backbone: {n_features: {value: 1000, source: "..."}, ...}   (keys of BackboneConfig)
//   stages: [ {name: "sgdo.mask", params: {key: {value: ..., source: "..."}}}, ... ]
// Unknown keys, duplicate keys, a stage listed twice and out-of-range backbone values are
// InputErrors naming the file and line. Backbone keys left out take the
// ORB-SLAM2 default and are recorded with the source "default: ORB-SLAM2 ...".
#pragma once
#include <map>
#include <string>
#include <vector>

#include "method/params.h"
#include "pipeline/backbone_options.h"

namespace dynref {

struct MethodConfig {
  std::string path;
  std::string method;
  std::map<std::string, Param> backbone_params;  // every backbone key, resolved (defaults filled in)
  BackboneOptions backbone;                      // the same, typed
  std::vector<StageConfig> stages;               // stages and map modules, in config order
  // Fully resolved configuration as JSON text (sorted keys; every value with its source).
  std::string ToJson() const;
  // Replaces one stage parameter's value (e.g. a sensitivity sweep), keeping its key and
  // recording `source`. InputError when the stage or key is not in the config.
  void SetStageParam(const std::string& stage, const std::string& key, const std::string& value,
                     const std::string& source);
  // The same for a backbone key (re-validated with the whole backbone table): `stage` "backbone".
  void SetBackboneParam(const std::string& key, const std::string& value, const std::string& source);
  // `dynref run --set STAGE.KEY=VALUE ...` (issue 37): every item applied first, then the backbone
  // checked once (order-free: backbone.features=onnx with backbone.onnx_model in either order); a
  // value [a, b] is a list; each value's location is its --set argument (messages name it, a
  // relative path in it is relative to the working directory). Stage values are checked by the
  // run's Session like config values. InputError("--set ...") for a malformed item, an unknown
  // stage or key.
  void ApplySets(const std::vector<std::string>& items, const std::string& source);
};

// Reads and validates a config file (InputError naming file:line on any problem).
MethodConfig LoadMethodConfig(const std::string& path);
// configs/<method>.yaml in the source tree (DYNREF_SOURCE_DIR at compile time).
std::string MethodConfigPath(const std::string& method);

}  // namespace dynref
