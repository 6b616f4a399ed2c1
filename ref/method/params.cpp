#include "method/params.h"

#include <charconv>
#include <cmath>
#include <cstdlib>

#include "core/error.h"
#include "io/coco_classes.h"

namespace dynref {
namespace {

// "key: " for messages (empty when the param was built without a name, e.g. in a test).
std::string Prefix(const Param& p) { return p.name.empty() ? "" : p.name + ": "; }

double ParseDouble(const Param& p, const std::string& text) {
  if (text.empty()) {
    if (!p.list.empty() && p.value.empty())
      throw InputError(p.file, p.line, Prefix(p) + "expected a number, got a list " + ParamText(p));
    throw InputError(p.file, p.line, Prefix(p) + "expected a number, got an empty value");
  }
  char* end = nullptr;
  const double d = std::strtod(text.c_str(), &end);
  if (end == nullptr || *end != '\0') throw InputError(p.file, p.line, Prefix(p) + "not a number: " + text);
  return d;
}

// Shortest decimal text of a bound ("0.5", "1e+06").
std::string BoundText(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof(buf), v);
  return std::string(buf, r.ptr);
}

void CheckNumber(const Param& p, const ParamSpec& s, double v) {
  auto bad = [&](const std::string& what) {
    throw InputError(p.file, p.line, p.name + ": " + what + ", got " + ParamText(p));
  };
  if (std::isnan(v)) bad("must be a number " + s.RangeText() + ", not NaN");
  if (std::isinf(v) && !(s.inf_ok && v > 0)) bad("must be finite and " + s.RangeText());
  if (std::isinf(v)) return;  // +inf accepted: "no limit"
  const bool below = s.lo_open ? !(v > s.lo) : !(v >= s.lo);
  const bool above = s.hi_open ? !(v < s.hi) : !(v <= s.hi);
  if (below || above) bad("must be " + s.RangeText());
}

void CheckOne(const Param& p, const ParamSpec& s) {
  using K = ParamSpec::Kind;
  const bool scalar = s.kind != K::kNames && s.kind != K::kReals;
  if (scalar && !p.list.empty())
    throw InputError(p.file, p.line, p.name + ": expected a single value, got a list " + ParamText(p));
  switch (s.kind) {
    case K::kReal: CheckNumber(p, s, p.AsDouble()); break;
    case K::kInt: {
      const double v = p.AsDouble();
      CheckNumber(p, s, v);  // range first: a huge value never reaches the integer conversion
      (void)p.AsInt();
      if (s.odd && static_cast<int64_t>(v) % 2 == 0)
        throw InputError(p.file, p.line, p.name + ": must be " + s.RangeText() + ", got " + p.value);
      break;
    }
    case K::kBool: (void)p.AsBool(); break;
    case K::kChoice: {
      for (const std::string& c : s.choices)
        if (p.value == c) return;
      throw InputError(p.file, p.line, p.name + ": must be " + s.RangeText() + ", got '" + p.value + "'");
    }
    case K::kText:
      if (p.value.empty()) throw InputError(p.file, p.line, p.name + ": must not be empty");
      break;
    case K::kNames:
      if (p.list.empty())
        throw InputError(p.file, p.line, p.name + ": expected a list of names [a, b], got '" + p.value + "'");
      break;
    case K::kReals:
      if (p.list.empty())
        throw InputError(p.file, p.line, p.name + ": expected a list of numbers [a, b], got '" + p.value + "'");
      for (double v : p.AsDoubleList()) CheckNumber(p, s, v);
      break;
  }
}

ParamSpec Make(const std::string& key, ParamSpec::Kind kind, double lo, double hi, bool lo_open) {
  ParamSpec s;
  s.key = key;
  s.kind = kind;
  s.lo = lo;
  s.hi = hi;
  s.lo_open = lo_open;
  return s;
}

}  // namespace

std::string ParamSpec::RangeText() const {
  switch (kind) {
    case Kind::kInt:
      return "an integer in " + BoundText(lo) + ".." + BoundText(hi) + (odd ? " (odd)" : "");
    case Kind::kChoice: {
      std::string t = "one of ";
      for (size_t i = 0; i < choices.size(); ++i) t += (i ? " | " : "") + choices[i];
      return t;
    }
    case Kind::kBool: return "true or false";
    case Kind::kText: return "a non-empty text";
    case Kind::kNames: return "a list of names";
    default:
      return std::string("in ") + (lo_open ? "(" : "[") + BoundText(lo) + ", " + BoundText(hi) + (hi_open ? ")" : "]") +
             (inf_ok ? " or inf" : "");
  }
}

ParamSpec Real(const std::string& key, double lo, double hi) { return Make(key, ParamSpec::Kind::kReal, lo, hi, false); }
ParamSpec RealAbove(const std::string& key, double lo, double hi) {
  return Make(key, ParamSpec::Kind::kReal, lo, hi, true);
}
ParamSpec Integer(const std::string& key, double lo, double hi) { return Make(key, ParamSpec::Kind::kInt, lo, hi, false); }
ParamSpec OddInteger(const std::string& key, double lo, double hi) {
  ParamSpec s = Make(key, ParamSpec::Kind::kInt, lo, hi, false);
  s.odd = true;
  return s;
}
ParamSpec Flag(const std::string& key) { return Make(key, ParamSpec::Kind::kBool, 0, 0, false); }
ParamSpec Choice(const std::string& key, std::vector<std::string> choices) {
  ParamSpec s = Make(key, ParamSpec::Kind::kChoice, 0, 0, false);
  s.choices = std::move(choices);
  return s;
}
ParamSpec Text(const std::string& key) { return Make(key, ParamSpec::Kind::kText, 0, 0, false); }
ParamSpec Names(const std::string& key) { return Make(key, ParamSpec::Kind::kNames, 0, 0, false); }

ParamSpec Seed(const std::string& key) { return Integer(key, 0, 9007199254740992.0); }
ParamSpec BelowHi(ParamSpec spec) {
  spec.hi_open = true;
  return spec;
}
ParamSpec InfOk(ParamSpec spec) {
  spec.inf_ok = true;
  return spec;
}

std::string ParamText(const Param& p) {
  if (p.list.empty()) return p.value;
  std::string t = "[";
  for (size_t i = 0; i < p.list.size(); ++i) t += (i ? ", " : "") + p.list[i];
  return t + "]";
}

void CheckParams(const ParamMap& params, const ParamSpecs& specs) {
  std::set<std::string> known;
  for (const ParamSpec& s : specs.keys) known.insert(s.key);
  params.RequireKnownKeys(known);
  for (const ParamSpec& s : specs.keys) {
    const Param& p = params.Get(s.key);  // InputError at the stage line for a missing key
    Param named = p;
    if (named.name.empty()) named.name = params.stage_name + "." + s.key;
    CheckOne(named, s);
  }
  for (const ParamOrder& o : specs.orders) {
    const double lower = params.GetDouble(o.lower), upper = params.GetDouble(o.upper);
    if (lower < upper) continue;
    const Param& p = params.Get(o.upper);
    throw InputError(p.file, p.line,
                     params.stage_name + "." + o.upper + ": must be > " + o.lower + " (" + params.Get(o.lower).value +
                         "), got " + ParamText(p));
  }
}

double Param::AsDouble() const { return ParseDouble(*this, value); }

int64_t Param::AsInt() const {
  const double d = AsDouble();
  if (!(std::fabs(d) <= 9007199254740992.0) || d != std::floor(d))
    throw InputError(file, line, Prefix(*this) + "not an integer: " + value);
  return static_cast<int64_t>(d);
}

bool Param::AsBool() const {
  if (value == "true") return true;
  if (value == "false") return false;
  throw InputError(file, line, Prefix(*this) + "not a boolean (true/false): " + ParamText(*this));
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
    if (id < 0) throw InputError(p.file, p.line, Prefix(p) + "unknown COCO class '" + name + "'");
    ids.push_back(id);
  }
  if (ids.empty()) throw InputError(p.file, p.line, stage_name + "." + key + " must list at least one class");
  return ids;
}

void ParamMap::RequireKnownKeys(const std::set<std::string>& known) const {
  for (const auto& [key, p] : params)
    if (!known.count(key))
      throw InputError(p.file.empty() ? file : p.file, p.line ? p.line : line,
                       "stage " + stage_name + ": unknown parameter '" + key + "'");
}

}  // namespace dynref
