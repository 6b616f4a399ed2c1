// Reading a config's backbone keys (backbone_keys.h) into BackboneOptions; see backbone_options.h.
#include "pipeline/backbone_options.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "core/error.h"
#include "pipeline/backbone_keys.h"

namespace dynref {
namespace {

using BackboneRowKind = BackboneKeyRow::Kind;

const BackboneKeyRow* FindBackboneRow(const std::string& key) {
  for (const BackboneKeyRow& r : BackboneKeyRows())
    if (key == r.key) return &r;
  return nullptr;
}

// The shortest text that reads back as v: integers without a decimal point ("12"), others with
// the fewest significant digits ("5.991", "0.016").
std::string BackboneNumberText(double v) {
  char text[40];
  if (v == std::floor(v) && std::fabs(v) < 1e15) {
    std::snprintf(text, sizeof(text), "%.0f", v);
    return text;
  }
  for (int digits = 1; digits <= 17; ++digits) {
    std::snprintf(text, sizeof(text), "%.*g", digits, v);
    if (std::strtod(text, nullptr) == v) break;
  }
  return text;
}

// The value of r's field(s) in o as a config writes it.
std::string BackboneValueText(const BackboneKeyRow& r, const BackboneOptions& o) {
  switch (r.kind) {
    case BackboneRowKind::kText: return r.get_text(o);
    case BackboneRowKind::kBool: return r.get(o) != 0 ? "true" : "false";
    case BackboneRowKind::kInt: return std::to_string(static_cast<int64_t>(r.get(o)));
    case BackboneRowKind::kDouble: break;
  }
  return BackboneNumberText(r.get(o));
}

std::string BackboneRangeText(const BackboneKeyRow& r) {
  if (r.kind == BackboneRowKind::kInt)
    return "must be in " + std::to_string(static_cast<int64_t>(r.lo)) + ".." + std::to_string(static_cast<int64_t>(r.hi));
  // Both bounds (a value above hi was told "must be > 0", issue 37).
  char lo[32], hi[32];
  std::snprintf(lo, sizeof(lo), "%g", r.lo);
  std::snprintf(hi, sizeof(hi), "%g", r.hi);
  return std::string("must be in ") + (r.lo_open ? "(" : "[") + lo + ", " + hi + "]";
}

// Value of a validated param as a double (bools 0/1; text: 0 after checking its choices).
double BackboneReadValue(const BackboneKeyRow& r, const Param& p) {
  auto bad = [&](const std::string& what) {
    throw InputError(p.file, p.line, std::string("backbone.") + r.key + ": " + what);
  };
  if (r.kind == BackboneRowKind::kBool) return p.AsBool() ? 1.0 : 0.0;
  if (r.kind == BackboneRowKind::kText) {
    if (!p.list.empty()) bad("must be a single value");
    if (r.choices != nullptr) {
      const std::string allowed = std::string("|") + r.choices + "|";
      if (allowed.find("|" + p.value + "|") == std::string::npos) bad(std::string("must be one of ") + r.choices + ", got '" + p.value + "'");
    }
    return 0;
  }
  const double v = p.AsDouble();
  const bool below = r.lo_open ? !(v > r.lo) : !(v >= r.lo);
  if (below || !(v <= r.hi)) bad(BackboneRangeText(r) + ", got " + p.value);
  if (r.kind == BackboneRowKind::kInt) (void)p.AsInt();  // integral (after the range check: no wrap-around)
  return v;
}

void ApplyBackboneParam(const BackboneKeyRow& r, const Param& p, BackboneOptions& o) {
  const double v = BackboneReadValue(r, p);
  if (r.kind == BackboneRowKind::kText) r.set_text(o, p.value, p.file);
  else r.set(o, v);
}

// Rules between keys, each reported at the value that breaks it.
void CheckBackboneCombinations(const BackboneOptions& o, const std::map<std::string, Param>& all) {
  auto bad = [&](const std::string& key, const std::string& what) {
    const Param& p = all.at(key);
    throw InputError(p.file, p.line, what);
  };
  if (o.orb.min_th_fast > o.orb.ini_th_fast) bad("min_th_fast", "backbone.min_th_fast: need 1 <= min_th_fast <= ini_th_fast");
  if (o.UsesVocabulary() && o.extractor.type != "orb")
    bad(o.loop.enabled ? "loop_closing" : o.tracker.relocalisation == "bow" ? "relocalisation" : "bow_matching",
        "backbone: the vocabulary needs features: orb (ref/place/README.md 'Float descriptors')");
  if (o.tracker.bow_matching && o.tracker.mnn2.enabled)
    bad("bow_matching", "backbone.bow_matching and backbone.mnn2_matching are exclusive");
  if (o.extractor.type == "onnx" && o.extractor.onnx.model.empty())
    bad("features", "backbone.features: onnx needs backbone.onnx_model");
}

const char* BackboneTypeName(BackboneRowKind kind) {
  switch (kind) {
    case BackboneRowKind::kInt: return "int";
    case BackboneRowKind::kDouble: return "real";
    case BackboneRowKind::kBool: return "bool";
    case BackboneRowKind::kText: break;
  }
  return "text";
}

}  // namespace

features::ExtractorOptions BackboneOptions::Extractor() const {
  features::ExtractorOptions e = extractor;
  e.orb = orb;
  e.sift.n_features = e.onnx.n_features = orb.n_features;
  return e;
}

void BackboneOptions::Check() const {
  Extractor().Check();  // ORB options included
  tracker.Check();
  loop.Check();
  mapper.Check();
  mapping_clock.Check();
  structure.Check();
}

std::vector<BackboneKeyInfo> BackboneKeys() {
  const BackboneOptions defaults;
  std::vector<BackboneKeyInfo> out;
  for (const BackboneKeyRow& r : BackboneKeyRows())
    out.push_back({r.key, BackboneValueText(r, defaults), r.source, BackboneTypeName(r.kind), r.lo, r.hi, r.lo_open,
                   r.choices != nullptr ? r.choices : ""});
  return out;
}

std::string BackboneKeyText(const BackboneOptions& o, const std::string& key) {
  const BackboneKeyRow* r = FindBackboneRow(key);
  if (r == nullptr) throw std::invalid_argument("unknown backbone key '" + key + "'");
  return BackboneValueText(*r, o);
}

void SetBackboneKey(BackboneOptions& o, const std::string& key, const std::string& text, const std::string& file) {
  const BackboneKeyRow* r = FindBackboneRow(key);
  if (r == nullptr) throw InputError(file, "unknown backbone key '" + key + "'");
  Param p;
  p.value = text;
  p.file = file;
  ApplyBackboneParam(*r, p, o);
}

namespace {

// The vocabulary is binary (ORB-SLAM2's): with float descriptors the keys that need it and were
// left at their defaults take dynref's vocabulary-free behaviour (no loop closing, the recent
// keyframes for relocalisation), with that reason as their source; set explicitly, they are
// refused by CheckBackboneCombinations.
void FallBackWithoutVocabulary(BackboneOptions& o, std::map<std::string, Param>& all) {
  if (o.extractor.type == "orb") return;
  for (const auto& [key, value] : {std::pair<std::string, std::string>{"loop_closing", "false"}, {"relocalisation", "recent"}}) {
    Param& p = all.at(key);
    if (!p.defaulted) continue;
    p.value = value;
    p.source = "dynref: features " + o.extractor.type +
               " has no vocabulary (ref/place/README.md 'Float descriptors'): the default falls back to " + value;
    ApplyBackboneParam(*FindBackboneRow(key), p, o);
  }
}

}  // namespace

BackboneOptions ResolveBackbone(const std::map<std::string, Param>& given, const std::string& config_path,
                                std::map<std::string, Param>* resolved) {
  for (const auto& [key, p] : given)
    if (FindBackboneRow(key) == nullptr) throw InputError(p.file, p.line, "unknown backbone key '" + key + "'");
  const BackboneOptions defaults;
  BackboneOptions o;
  std::map<std::string, Param> all;
  for (const BackboneKeyRow& r : BackboneKeyRows()) {
    auto it = given.find(r.key);
    Param p;
    if (it != given.end() && !it->second.defaulted) {
      p = it->second;
    } else {  // absent, or a default of an earlier resolution (it follows the other keys again)
      p.value = BackboneValueText(r, defaults);
      p.source = r.source;
      p.file = config_path;
      p.defaulted = true;
    }
    ApplyBackboneParam(r, p, o);
    all[r.key] = p;
  }
  FallBackWithoutVocabulary(o, all);
  CheckBackboneCombinations(o, all);
  o.Check();
  if (resolved != nullptr) *resolved = std::move(all);
  return o;
}

}  // namespace dynref
