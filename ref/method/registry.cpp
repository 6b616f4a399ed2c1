#include "method/registry.h"

#include <stdexcept>

namespace dynref {

void MethodRegistry::AddStage(const std::string& name, StageFactory factory) {
  if (Has(name)) throw std::logic_error("duplicate stage or map module " + name);
  stages_[name] = std::move(factory);
}

void MethodRegistry::AddMapModule(const std::string& name, MapModuleFactory factory) {
  if (Has(name)) throw std::logic_error("duplicate stage or map module " + name);
  map_modules_[name] = std::move(factory);
}

const StageFactory* MethodRegistry::FindStage(const std::string& name) const {
  auto it = stages_.find(name);
  return it == stages_.end() ? nullptr : &it->second;
}

const MapModuleFactory* MethodRegistry::FindMapModule(const std::string& name) const {
  auto it = map_modules_.find(name);
  return it == map_modules_.end() ? nullptr : &it->second;
}

void MethodRegistry::AddParams(const std::string& name, ParamSpecs specs) {
  if (params_.count(name)) throw std::logic_error("parameters of " + name + " declared twice");
  params_[name] = std::move(specs);
}

const ParamSpecs* MethodRegistry::FindParams(const std::string& name) const {
  auto it = params_.find(name);
  return it == params_.end() ? nullptr : &it->second;
}

void MethodRegistry::AddRequirement(const std::string& name, const std::string& needed) {
  requirements_[name].push_back(needed);
}

std::vector<std::string> MethodRegistry::Requirements(const std::string& name) const {
  auto it = requirements_.find(name);
  return it == requirements_.end() ? std::vector<std::string>{} : it->second;
}

std::vector<std::string> MethodRegistry::Names() const {
  std::map<std::string, int> all;
  for (const auto& kv : stages_) all[kv.first] = 0;
  for (const auto& kv : map_modules_) all[kv.first] = 0;
  std::vector<std::string> out;
  for (const auto& kv : all) out.push_back(kv.first);
  return out;
}

}  // namespace dynref
