#include "reproduce/table_list.h"

#include "reproduce/table_registry.h"

namespace dynref::reproduce {

const std::vector<TableEntry>& ReproducibleTables() {
  // The registry is the one source: each table's row comes from its own file's registration.
  static const std::vector<TableEntry> t = [] {
    TableRegistry tables;
    RegisterBuiltinTables(tables);
    std::vector<TableEntry> rows;
    for (const TableDef& d : tables.Tables()) rows.push_back({d.name, d.paper, d.what});
    return rows;
  }();
  return t;
}

}  // namespace dynref::reproduce
