// Canonical flat view of records (README "Canonical view"): the one place that names fields.
#include <cinttypes>
#include <cstdio>
#include <map>

#include "trace/trace_reader.h"

namespace dynref::trace {

std::string FlatRecord::Key() const {
  return type + "|" + stage + "|" + kind + "|" + entity + "|" + std::to_string(occurrence);
}

namespace {
void AddFloat(FlatRecord& f, std::string name, double v) {
  FlatField x;
  x.name = std::move(name);
  x.number = v;
  f.fields.push_back(std::move(x));
}
void AddExact(FlatRecord& f, std::string name, std::string text) {
  FlatField x;
  x.name = std::move(name);
  x.exact = true;
  x.text = std::move(text);
  f.fields.push_back(std::move(x));
}
}  // namespace

FlatRecord Flatten(const Record& r) {
  FlatRecord f;
  f.frame = r.frame;
  f.type = RecordTypeName(r.type);
  switch (r.type) {
    case RecordType::kFrame:
      f.kind = "frame";
      AddFloat(f, "timestamp", r.timestamp);
      break;
    case RecordType::kPose:
      f.stage = r.name;
      f.kind = "frame";
      for (int i = 0; i < 12; ++i) AddFloat(f, "T_wc[" + std::to_string(i) + "]", r.T_wc[i]);
      break;
    case RecordType::kCount:
      f.stage = r.stage;
      f.entity = r.name;
      AddExact(f, "value", std::to_string(r.value));
      break;
    case RecordType::kObservation: {
      f.kind = EntityKindName(EntityKind::kFeature);
      f.entity = "f" + std::to_string(r.frame) + "." + std::to_string(r.feature_index);
      AddExact(f, "map_point_id", std::to_string(r.map_point_id));
      AddExact(f, "associated_map_point_id", std::to_string(r.associated_map_point_id));
      AddFloat(f, "u", r.u);
      AddFloat(f, "v", r.v);
      AddFloat(f, "depth_m", r.depth_m);
      AddExact(f, "octave", std::to_string(r.octave));
      char hex[20];
      std::snprintf(hex, sizeof(hex), "%016" PRIx64, r.descriptor_hash);
      AddExact(f, "descriptor_hash", hex);
      break;
    }
    case RecordType::kProbability:
      f.stage = r.stage;
      f.kind = EntityKindName(r.kind);
      f.entity = r.entity;
      for (const NamedValue& nv : r.inputs) AddFloat(f, "in." + nv.name, nv.value);
      AddFloat(f, "before", r.before);
      AddFloat(f, "after", r.after);
      break;
    case RecordType::kResidual:
      f.stage = r.stage;
      f.entity = r.entity;
      AddExact(f, "residual_kind", r.residual_kind);
      for (size_t i = 0; i < r.residual_start.size(); ++i)
        AddFloat(f, "start[" + std::to_string(i) + "]", r.residual_start[i]);
      for (size_t i = 0; i < r.residual_end.size(); ++i)
        AddFloat(f, "end[" + std::to_string(i) + "]", r.residual_end[i]);
      AddFloat(f, "information", r.information);
      AddFloat(f, "weight", r.weight);
      AddFloat(f, "robust_loss", r.robust_loss);
      AddFloat(f, "chi2", r.chi2);
      AddExact(f, "inlier", r.inlier ? "1" : "0");
      break;
    case RecordType::kDecision:
      f.stage = r.stage;
      f.kind = EntityKindName(r.kind);
      f.entity = r.entity;
      AddExact(f, "kept", r.kept ? "1" : "0");
      AddExact(f, "reason", r.reason);
      break;
  }
  return f;
}

std::vector<FlatRecord> FlattenGroup(const std::vector<Record>& records) {
  std::vector<FlatRecord> out;
  out.reserve(records.size());
  std::map<std::string, int> seen;
  for (const Record& r : records) {
    FlatRecord f = Flatten(r);
    const std::string k = f.type + "|" + f.stage + "|" + f.kind + "|" + f.entity;
    f.occurrence = seen[k]++;
    out.push_back(std::move(f));
  }
  return out;
}

}  // namespace dynref::trace
