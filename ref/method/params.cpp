#include "method/params.h"

#include <cstdlib>

#include "core/error.h"
#include "io/coco_classes.h"

namespace dynref {
namespace {

double ParseDouble(const Param& p, const std::string& text) {
  if (text.empty()) throw InputError(p.file, p.line, "expected a number, got an empty value");
  char* end = nullptr;
  const double d = std::strtod(text.c_str(), &end);
  if (end == nullptr || *end != '\0') throw InputError(p.file, p.line, "not a number: " + text);
  return d;
}

}  // namespace

double Param::AsDouble() const { return ParseDouble(*this, value); }

int64_t Param::AsInt() const {
  const double d = AsDouble();
  if (d != static_cast<double>(static_cast<int64_t>(d))) throw InputError(file, line, "not an integer: " + value);
  return static_cast<int64_t>(d);
}

bool Param::AsBool() const {
  if (value == "true") return true;
  if (value == "false") return false;
  throw InputError(file, line, "not a boolean (true/false): " + value);
}

std::vector<double> Param::AsDoubleList() const {
  std::vector<double> out;
  for (const std::string& v : list) out.push_back(ParseDouble(*this, v));
  return out;
}

const Param& ParamMap::Get(const std::string& key) const {
  auto it = params.find(key);
  if (it == params.end()) throw InputError(file, line, "stage " + stage_name + ": missing parameter " + key);
  return it->second;
}

std::vector<int> ParamMap::GetCocoClassIds(const std::string& key) const {
  const Param& p = Get(key);
  std::vector<int> ids;
  for (const std::string& name : p.list) {
    const int id = CocoClassId(name);
    if (id < 0) throw InputError(p.file, p.line, "unknown COCO class '" + name + "'");
    ids.push_back(id);
  }
  if (ids.empty()) throw InputError(p.file, p.line, key + " must list at least one class");
  return ids;
}

void ParamMap::RequireKnownKeys(const std::set<std::string>& known) const {
  for (const auto& [key, p] : params)
    if (!known.count(key))
      throw InputError(p.file.empty() ? file : p.file, p.line ? p.line : line,
                       "stage " + stage_name + ": unknown parameter '" + key + "'");
}

}  // namespace dynref
