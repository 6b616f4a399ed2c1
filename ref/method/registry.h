// The registry of stage and map-module factories, passed to each run (no process-wide state).
// A method registers its components from its own folder (ref/dynamic/<method>/register.cpp,
// listed with dynref_add_method in its CMakeLists.txt); the build generates
// RegisterBuiltinMethods (dynamic/builtin_methods.h) calling every method's registration, so
// adding a method edits no pipeline file. Tests register their own components.
#pragma once
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "method/map_module.h"
#include "method/params.h"
#include "method/shared_state.h"
#include "method/stage.h"

namespace dynref {

// A factory builds one component from its config parameters; `shared` is the run's
// SharedState (the same object for every component of one run).
using StageFactory = std::function<std::unique_ptr<Stage>(const ParamMap& params, SharedState& shared)>;
using MapModuleFactory = std::function<std::unique_ptr<MapModule>(const ParamMap& params, SharedState& shared)>;

class MethodRegistry {
 public:
  // std::logic_error for a name registered twice (stage or map module).
  void AddStage(const std::string& name, StageFactory factory);
  void AddMapModule(const std::string& name, MapModuleFactory factory);
  const StageFactory* FindStage(const std::string& name) const;
  const MapModuleFactory* FindMapModule(const std::string& name) const;
  bool Has(const std::string& name) const { return FindStage(name) || FindMapModule(name); }
  // The declared keys and ranges of a component's parameters (params.h ParamSpec), checked by the
  // Session before the factory runs; std::logic_error for a name given twice.
  void AddParams(const std::string& name, ParamSpecs specs);
  const ParamSpecs* FindParams(const std::string& name) const;
  // `name` needs `needed` in the same config (e.g. mgd.boxes reads mgd.probability's options):
  // the Session refuses a config without it at the stage's line, before the first frame.
  void AddRequirement(const std::string& name, const std::string& needed);
  std::vector<std::string> Requirements(const std::string& name) const;
  std::vector<std::string> Names() const;  // sorted

 private:
  std::map<std::string, StageFactory> stages_;
  std::map<std::string, MapModuleFactory> map_modules_;
  std::map<std::string, ParamSpecs> params_;
  std::map<std::string, std::vector<std::string>> requirements_;
};

}  // namespace dynref
