// Every paper table `dynref reproduce` can run (`dynref reproduce --list`): its command name, the
// seed paper, what it measures and the report it writes (reports/<name>.md by default), read from
// the table registry (table_registry.h: each table registers its row from its own file).
#pragma once
#include <string>
#include <vector>

namespace dynref::reproduce {

struct TableEntry {
  std::string name;   // the subcommand, e.g. "sgdo-table6"
  std::string paper;  // seed paper number and short name, e.g. "001 SGDO-SLAM"
  std::string what;   // one line
  std::string Report() const { return "reports/" + name + ".md"; }
};

const std::vector<TableEntry>& ReproducibleTables();

}  // namespace dynref::reproduce
