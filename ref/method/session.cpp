#include "method/session.h"

#include <exception>
#include <set>

#include "core/cpu_clock.h"
#include "core/error.h"

namespace dynref {

namespace {

// Every component's parameters against its declared specs and its required companions, all
// before the first factory runs (a config error never waits for a frame: issue 33, 37).
void CheckComponents(const std::string& config_path, const std::vector<StageConfig>& components,
                     const MethodRegistry& registry) {
  std::set<std::string> names;
  for (const StageConfig& sc : components) names.insert(sc.name);
  for (const StageConfig& sc : components) {
    if (const ParamSpecs* specs = registry.FindParams(sc.name)) CheckParams(sc.params, *specs);
    for (const std::string& needed : registry.Requirements(sc.name))
      if (!names.count(needed))
        throw InputError(config_path, sc.params.line, "stage " + sc.name + " needs " + needed + " in the stage list");
  }
}

}  // namespace

Session::Session(const std::string& config_path, const std::vector<StageConfig>& components,
                 const MethodRegistry& registry) {
  CheckComponents(config_path, components, registry);
  for (const StageConfig& sc : components) {
    Component c;
    if (const StageFactory* f = registry.FindStage(sc.name)) {
      c.stage = (*f)(sc.params, shared_);
      stages_.push_back(c.stage.get());
      stage_ms_.push_back(0.0);
    } else if (const MapModuleFactory* m = registry.FindMapModule(sc.name)) {
      c.map_module = (*m)(sc.params, shared_);
      map_modules_.push_back(c.map_module.get());
      map_ms_.push_back(0.0);
    } else {
      std::string known;
      for (const std::string& n : registry.Names()) known += (known.empty() ? "" : ", ") + n;
      throw InputError(config_path, sc.params.line,
                       "unknown stage '" + sc.name + "' (known: " + (known.empty() ? "none" : known) + ")");
    }
    components_.push_back(std::move(c));
  }
}

Session::~Session() = default;

void Session::Run(Hook hook, StageContext& ctx) {
  ctx.frame.set_hook(hook);
  if (ctx.new_keyframe_edit != nullptr) ctx.new_keyframe_edit->set_hook(hook);
  for (size_t i = 0; i < stages_.size(); ++i) {
    if (stages_[i]->hook() != hook) continue;
    const double t0 = ThreadCpuMs();
    stages_[i]->Run(ctx);
    stage_ms_[i] += ThreadCpuMs() - t0;
  }
}

std::vector<std::pair<std::string, double>> Session::StageTimes() const {
  std::vector<std::pair<std::string, double>> out;
  for (size_t i = 0; i < stages_.size(); ++i) out.emplace_back(stages_[i]->name(), stage_ms_[i]);
  for (size_t i = 0; i < map_modules_.size(); ++i) out.emplace_back(map_modules_[i]->name(), map_ms_[i]);
  return out;
}

void Session::OnKeyFrame(const MapModuleContext& ctx) {
  for (size_t i = 0; i < map_modules_.size(); ++i) {
    const double t0 = ThreadCpuMs();
    map_modules_[i]->OnKeyFrame(ctx);
    map_ms_[i] += ThreadCpuMs() - t0;
  }
}

void Session::OnMapUpdate(const MapModuleContext& ctx) {
  for (size_t i = 0; i < map_modules_.size(); ++i) {
    const double t0 = ThreadCpuMs();
    map_modules_[i]->OnMapUpdate(ctx);
    map_ms_[i] += ThreadCpuMs() - t0;
  }
}

void Session::OnLandmarkEvent(const LandmarkEvent& event) {
  for (Component& c : components_) {
    if (c.stage) c.stage->OnLandmarkEvent(event);
    if (c.map_module) c.map_module->OnLandmarkEvent(event);
  }
}

SessionEnd Session::Finish(const Map& map, const std::string& out_dir) {
  SessionEnd out;
  RunEnd end(out_dir);
  for (Component& c : components_) {
    const std::string name = c.stage ? c.stage->name() : c.map_module->name();
    try {
      if (c.stage) c.stage->Finish(end);
      else c.map_module->Finish(map, end);
    } catch (const std::exception& e) {
      out.errors.push_back(name + ": " + e.what());
    }
  }
  out.outputs = end.outputs();
  out.detection_use = end.detection_use();
  return out;
}

}  // namespace dynref
