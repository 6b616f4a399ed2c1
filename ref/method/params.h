// Method parameters as they appear in a config (configs/<method>.yaml): every value carries its
// source ("paper Sec. ..." / "not stated: chosen because ...") and the file:line it came from,
// so that a stage rejecting a value names where it was written.
#pragma once
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace dynref {

// One parameter: a scalar (as text) or a list of scalars, with its source and location.
struct Param {
  std::string value;                 // scalar text (empty for a list)
  std::vector<std::string> list;     // list values (empty for a scalar)
  std::string source;
  std::string file;                  // config file and line (for error messages)
  int line = 0;
  // InputError (file:line) when the text is not of the requested type.
  double AsDouble() const;
  int64_t AsInt() const;
  bool AsBool() const;
  std::vector<double> AsDoubleList() const;
};

// Parameters of one stage or map module, by name (id ordered). Get* throw InputError for a
// missing key.
class ParamMap {
 public:
  std::map<std::string, Param> params;
  std::string stage_name;
  std::string file;
  int line = 0;

  bool Has(const std::string& key) const { return params.count(key) > 0; }
  const Param& Get(const std::string& key) const;
  double GetDouble(const std::string& key) const { return Get(key).AsDouble(); }
  int64_t GetInt(const std::string& key) const { return Get(key).AsInt(); }
  bool GetBool(const std::string& key) const { return Get(key).AsBool(); }
  std::string GetString(const std::string& key) const { return Get(key).value; }
  double GetDouble(const std::string& key, double fallback) const { return Has(key) ? GetDouble(key) : fallback; }
  // COCO ids of a list of class names (io/coco_classes.h); InputError (file:line) for an unknown
  // name or an empty list.
  std::vector<int> GetCocoClassIds(const std::string& key) const;
  // InputError naming the config file/line of the first key not in `known`.
  void RequireKnownKeys(const std::set<std::string>& known) const;
};

// One entry of a config's `stages:` list: a stage or a map module, by registered name.
struct StageConfig {
  std::string name;
  ParamMap params;
};

}  // namespace dynref
