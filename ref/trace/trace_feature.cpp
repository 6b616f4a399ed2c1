#include "trace/trace_feature.h"

#include <set>

#include "trace/trace_dump.h"

namespace dynref::trace {

FeatureHistory CollectFeatureHistory(TraceReader& reader, const std::string& id) {
  FeatureHistory h;
  h.id = id;
  const bool is_map_point = id.size() > 2 && id.compare(0, 2, "mp") == 0;
  const std::string mp_number = is_map_point ? id.substr(2) : "";
  for (size_t gi = 0; gi < reader.groups().size(); ++gi) {
    const std::vector<FlatRecord> recs = FlattenGroup(reader.ReadGroup(gi));
    std::set<std::string> related;  // feature observations of the map point in this frame
    if (is_map_point)
      for (const FlatRecord& f : recs)
        if (f.type == "obs" && f.fields.at(0).text == mp_number) related.insert(f.entity);
    for (const FlatRecord& f : recs) {
      bool take = EntityMatches(f.entity, id);
      for (const std::string& r : related) take = take || EntityMatches(f.entity, r);
      if (take) h.rows.push_back(f);
    }
  }
  return h;
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
