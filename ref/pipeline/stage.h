// Stage API of dynamic methods (HEADER-ONLY: method libraries in ref/dynamic/<method> include it
// while the pipeline library links them). A method is a list of stages, each run at one hook.
//
// Per-frame order (backbone issue 5):
//   extract -> kAfterExtraction -> kBeforeInitialPose -> initial pose (motion model / reference
//   keyframe matching + pose optimisation, non-excluded features only) -> kAfterInitialPose ->
//   local-map tracking -> kBeforeFinalPose -> final pose optimisation -> keyframe decision ->
//   kOnKeyFrameCreated (only when a keyframe was made) -> local mapping -> kOnMapUpdate.
// Stages change the frame only through Frame::Exclude / Frame::SetWeight (and may read
// everything else). Excluding at kAfterInitialPose / kBeforeFinalPose removes the feature's
// map point association, so the final optimisation does not use it. At kOnKeyFrameCreated the
// keyframe already holds its own copy of the frame: exclude / weight through
// ctx.new_keyframe->frame so that local mapping and local BA see it (kOnMapUpdate also runs only
// when a keyframe was made, after local mapping).
#pragma once
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/camera.h"
#include "map/frame.h"
#include "map/map.h"
#include "trace/trace_writer.h"

namespace dynref {

enum class Hook {
  kAfterExtraction,
  kBeforeInitialPose,
  kAfterInitialPose,
  kBeforeFinalPose,
  kOnKeyFrameCreated,
  kOnMapUpdate,
};

inline const char* HookName(Hook h) {
  switch (h) {
    case Hook::kAfterExtraction: return "after_extraction";
    case Hook::kBeforeInitialPose: return "before_initial_pose";
    case Hook::kAfterInitialPose: return "after_initial_pose";
    case Hook::kBeforeFinalPose: return "before_final_pose";
    case Hook::kOnKeyFrameCreated: return "on_keyframe_created";
    case Hook::kOnMapUpdate: return "on_map_update";
  }
  return "?";
}

struct StageContext {
  Frame& frame;                     // the current frame (T_cw valid when frame.has_pose)
  const Frame* previous;            // previous frame (nullptr for the first), with its pose
  const KeyFrame* reference_kf;     // tracking reference keyframe (nullptr before init)
  const Map& map;                   // keyframes (with rgb, depth_m, keys) and map points
  const Camera& camera;
  trace::TraceWriter& trace;
  KeyFrame* new_keyframe;           // set only at kOnKeyFrameCreated / kOnMapUpdate when one was made
  Map* mutable_map = nullptr;       // only at kOnKeyFrameCreated / kOnMapUpdate (e.g. to flag points)
  bool initialised = false;         // map initialised (a pose exists for previous frames)
  bool lost = false;                // tracking state before this frame
  std::string run_dir = {};         // the run's output folder (stages may write files there)
};

class Stage {
 public:
  virtual ~Stage() = default;
  virtual std::string name() const = 0;
  virtual Hook hook() const = 0;
  virtual void Run(StageContext& ctx) = 0;
};

// One method parameter as it appears in the config: value (scalar as text, or a list of
// scalars) and the source it comes from ("paper Sec. ..." / "not stated: chosen because ...").
struct Param {
  std::string value;                 // scalar text (empty for a list)
  std::vector<std::string> list;     // list values (empty for a scalar)
  std::string source;
  std::string file;                  // config file and line (for error messages)
  int line = 0;
  double AsDouble() const { return ParseDouble(value); }
  int64_t AsInt() const {
    const double d = AsDouble();
    if (d != static_cast<double>(static_cast<int64_t>(d))) throw InputError(file, line, "not an integer: " + value);
    return static_cast<int64_t>(d);
  }
  bool AsBool() const {
    if (value == "true") return true;
    if (value == "false") return false;
    throw InputError(file, line, "not a boolean (true/false): " + value);
  }
  std::vector<double> AsDoubleList() const {
    std::vector<double> out;
    for (const std::string& v : list) out.push_back(ParseDouble(v));
    return out;
  }

 private:
  double ParseDouble(const std::string& text) const {
    if (text.empty()) throw InputError(file, line, "expected a number, got an empty value");
    char* end = nullptr;
    const double d = std::strtod(text.c_str(), &end);
    if (end == nullptr || *end != '\0') throw InputError(file, line, "not a number: " + text);
    return d;
  }
};

// Parameters of one stage, by name (id ordered). Get* throw InputError for a missing key.
class ParamMap {
 public:
  std::map<std::string, Param> params;
  std::string stage_name;
  std::string file;
  int line = 0;

  bool Has(const std::string& key) const { return params.count(key) > 0; }
  const Param& Get(const std::string& key) const {
    auto it = params.find(key);
    if (it == params.end()) throw InputError(file, line, "stage " + stage_name + ": missing parameter " + key);
    return it->second;
  }
  double GetDouble(const std::string& key) const { return Get(key).AsDouble(); }
  int64_t GetInt(const std::string& key) const { return Get(key).AsInt(); }
  bool GetBool(const std::string& key) const { return Get(key).AsBool(); }
  std::string GetString(const std::string& key) const { return Get(key).value; }
  double GetDouble(const std::string& key, double fallback) const { return Has(key) ? GetDouble(key) : fallback; }
};

using StageFactory = std::function<std::unique_ptr<Stage>(const ParamMap&)>;

class StageRegistry {
 public:
  // InputError-free: a duplicate name is a programming error (std::logic_error).
  void Register(const std::string& stage_name, StageFactory factory) {
    if (factories_.count(stage_name)) throw std::logic_error("duplicate stage " + stage_name);
    factories_[stage_name] = std::move(factory);
  }
  bool Has(const std::string& stage_name) const { return factories_.count(stage_name) > 0; }
  const StageFactory* Find(const std::string& stage_name) const {
    auto it = factories_.find(stage_name);
    return it == factories_.end() ? nullptr : &it->second;
  }
  std::vector<std::string> Names() const {
    std::vector<std::string> out;
    for (const auto& kv : factories_) out.push_back(kv.first);
    return out;
  }

 private:
  std::map<std::string, StageFactory> factories_;
};

}  // namespace dynref
