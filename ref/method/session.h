// One run's method instance (issue 12): the stages and map modules of a config, created fresh
// from a registry, with their SharedState; it runs them at their hooks in config order, forwards
// landmark events to them, and collects their outputs and errors at the end of the run.
// Nothing outlives the Session, so runs in one process are independent.
#pragma once
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "map/landmark.h"
#include "method/registry.h"

namespace dynref {

struct SessionEnd {
  std::vector<RunOutput> outputs;
  std::vector<std::string> errors;  // "<module>: <message>", in config order
  std::vector<DetectionUse> detection_use;  // per stage that thresholds detections (issue 39), config order
};

class Session : public LandmarkObserver {
 public:
  // InputError (config_path:line) for a name the registry does not know.
  Session(const std::string& config_path, const std::vector<StageConfig>& components,
          const MethodRegistry& registry);
  ~Session() override;

  void Run(Hook hook, StageContext& ctx);
  void OnKeyFrame(const MapModuleContext& ctx);
  void OnMapUpdate(const MapModuleContext& ctx);
  void OnLandmarkEvent(const LandmarkEvent& event) override;
  // Calls every stage's and map module's Finish in config order; an exception of one is recorded
  // and the others still run.
  SessionEnd Finish(const Map& map, const std::string& out_dir);

  // CPU ms spent in each stage's Run, then in each map module's OnKeyFrame + OnMapUpdate, over the
  // whole run (thread CPU clock), config order within each kind.
  std::vector<std::pair<std::string, double>> StageTimes() const;
  size_t stage_count() const { return stages_.size(); }
  size_t map_module_count() const { return map_modules_.size(); }
  SharedState& shared() { return shared_; }

 private:
  SharedState shared_;  // declared first: components hold pointers into it
  struct Component {
    std::unique_ptr<Stage> stage;
    std::unique_ptr<MapModule> map_module;
  };
  std::vector<Component> components_;  // config order
  std::vector<Stage*> stages_;
  std::vector<double> stage_ms_;  // parallel to stages_
  std::vector<double> map_ms_;    // parallel to map_modules_: OnKeyFrame + OnMapUpdate (not Finish)
  std::vector<MapModule*> map_modules_;
};

}  // namespace dynref
