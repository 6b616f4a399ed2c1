#include "trace/trace_feature.h"

#include <initializer_list>
#include <set>

#include "trace/trace_dump.h"

namespace dynref::trace {

FeatureHistory CollectFeatureHistory(TraceReader& reader, const std::string& id) {
  FeatureHistory h;
  h.id = id;
  // Landmark ids: map point mp<N>, map line ml<N>, map plane mpl<N> (digits only after the prefix).
  const auto landmark_number = [&](const std::string& prefix) {
    if (id.size() <= prefix.size() || id.compare(0, prefix.size(), prefix) != 0) return std::string();
    const std::string rest = id.substr(prefix.size());
    return rest.find_first_not_of("0123456789") == std::string::npos ? rest : std::string();
  };
  const std::string mp_number = landmark_number("mp");
  const bool is_map_point = !mp_number.empty();
  // Frame lines / planes associated with a map line / plane: structure records' input.
  const std::string ml_number = landmark_number("ml"), mpl_number = landmark_number("mpl");
  const std::string structure_input = !ml_number.empty() ? "in.map_line" : !mpl_number.empty() ? "in.map_plane" : "";
  const double structure_id = !ml_number.empty() ? std::stod(ml_number) : !mpl_number.empty() ? std::stod(mpl_number) : -1;
  for (size_t gi = 0; gi < reader.groups().size(); ++gi) {
    const std::vector<FlatRecord> recs = FlattenGroup(reader.ReadGroup(gi));
    std::set<std::string> related;  // feature observations of the map point in this frame
    if (is_map_point)
      for (const FlatRecord& f : recs)
        if (f.type == "obs")
          for (const FlatField& field : f.fields)
            if (field.name == "associated_map_point_id" && field.text == mp_number) related.insert(f.entity);
    if (!structure_input.empty())
      for (const FlatRecord& f : recs)
        for (const FlatField& field : f.fields)
          if (field.name == structure_input && field.number == structure_id) related.insert(f.entity);
    for (const FlatRecord& f : recs) {
      bool take = EntityMatches(f.entity, id);
      for (const std::string& r : related) take = take || EntityMatches(f.entity, r);
      if (take) h.rows.push_back(f);
    }
  }
  return h;
}

namespace {
bool AllDigits(const std::string& s) {
  if (s.empty()) return false;
  for (char c : s)
    if (c < '0' || c > '9') return false;
  return true;
}
// "<prefix><digits>" (dotted: "<prefix><digits>.<digits>") for one of the given prefixes.
bool PrefixedNumber(const std::string& s, std::initializer_list<const char*> prefixes, bool dotted) {
  for (const char* p : prefixes) {
    const std::string prefix(p);
    if (s.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string rest = s.substr(prefix.size());
    if (!dotted && AllDigits(rest)) return true;
    const size_t dot = rest.find('.');
    if (dotted && dot != std::string::npos && AllDigits(rest.substr(0, dot)) && AllDigits(rest.substr(dot + 1)))
      return true;
  }
  return false;
}
bool BaseEntityId(const std::string& s) {
  return PrefixedNumber(s, {"f", "i", "l", "pl", "r"}, true) || PrefixedNumber(s, {"mp", "kf", "ml", "mpl"}, false);
}
}  // namespace

bool IsCanonicalEntityId(const std::string& id) {
  const size_t at = id.find('@');
  if (at == std::string::npos) return BaseEntityId(id);
  return BaseEntityId(id.substr(0, at)) && PrefixedNumber(id.substr(at + 1), {"f", "kf"}, false);
}

void WriteFeatureTable(const FeatureHistory& history, std::ostream& out) {
  out << "frame,type,stage,kind,entity,occurrence,fields\n";
  for (const FlatRecord& f : history.rows) {
    std::string fields;
    for (const FlatField& x : f.fields) fields += (fields.empty() ? "" : " ") + x.name + "=" + FieldText(x);
    out << f.frame << "," << f.type << "," << CsvEscape(f.stage) << "," << f.kind << ","
        << CsvEscape(f.entity) << "," << f.occurrence << "," << CsvEscape(fields) << "\n";
  }
}

}  // namespace dynref::trace
