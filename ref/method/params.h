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
  std::string name;                  // key as written, with its stage ("sgdo.depth.eta"), for messages
  bool defaulted = false;            // filled in from the default (a backbone key the config omits)
  // InputError (file:line, naming the key) when the text is not of the requested type.
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

// A parameter's declared type and range (issue 33 part 2, issue 37): a method registers one spec
// per key of each component (MethodRegistry::AddParams, from ref/dynamic/<method>/read_options.cpp),
// and the run checks every value against it when the method's components are created, before the
// first frame (CheckParams): a key the spec does not list, a missing key, a value of the wrong
// type, NaN, an infinity (unless `inf_ok`: "no limit") or a value out of [lo, hi] is an InputError
// at the value's own line (a `--set` value: the --set argument), naming the key as written.
struct ParamSpec {
  enum class Kind { kReal, kInt, kBool, kChoice, kText, kNames, kReals };
  std::string key;
  Kind kind = Kind::kReal;
  double lo = 0, hi = 0;        // kReal, kInt, kReals: range, inclusive unless lo_open / hi_open
  bool lo_open = false, hi_open = false;
  bool inf_ok = false;          // kReal: +inf accepted (means "no limit")
  bool odd = false;             // kInt: odd values only (kernel sizes)
  std::vector<std::string> choices;  // kChoice: the allowed values
  std::string RangeText() const;     // "in [0, 1]", "in 1..100 (odd)", "one of a | b", ...
};
// Spec builders: Real("eta", 0, 10) is [0, 10]; RealAbove("eta", 0, 10) is (0, 10].
ParamSpec Real(const std::string& key, double lo, double hi);
ParamSpec RealAbove(const std::string& key, double lo, double hi);
ParamSpec Integer(const std::string& key, double lo, double hi);
ParamSpec OddInteger(const std::string& key, double lo, double hi);
ParamSpec Flag(const std::string& key);
ParamSpec Choice(const std::string& key, std::vector<std::string> choices);
ParamSpec Text(const std::string& key);   // any non-empty single value
ParamSpec Names(const std::string& key);  // a list of at least one name
ParamSpec Seed(const std::string& key);   // an integer in 0..2^53 (exact in a double)
ParamSpec BelowHi(ParamSpec spec);        // the same with hi excluded: [lo, hi)
ParamSpec InfOk(ParamSpec spec);          // the same with +inf accepted ("no limit")
// `lower` < `upper` (e.g. min_depth_m < max_depth_m): checked after both keys' ranges.
struct ParamOrder {
  std::string lower, upper;
};
struct ParamSpecs {
  std::vector<ParamSpec> keys;
  std::vector<ParamOrder> orders = {};
};
// InputError as described above; `component` names the stage in messages ("sgdo.depth.eta: ...").
void CheckParams(const ParamMap& params, const ParamSpecs& specs);
// The text of a value for messages: the scalar, or "[a, b]".
std::string ParamText(const Param& p);

// One entry of a config's `stages:` list: a stage or a map module, by registered name.
struct StageConfig {
  std::string name;
  ParamMap params;
};

}  // namespace dynref
