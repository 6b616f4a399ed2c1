// `dynref reproduce <table>`: one subcommand per registered table (reproduce/table_registry.h;
// each table registers itself, its options and its runner from its own file), and --list.
#include <iostream>
#include <memory>

#include "cli/command.h"
#include "core/error.h"
#include "reproduce/claims_ledger.h"
#include "reproduce/table_registry.h"

namespace dynref::cli {

void RegisterReproduceCommand(CLI::App& root, CommandList& out) {
  CLI::App* rep = root.add_subcommand("reproduce", "Reproduce a paper table end to end on synthetic data");
  rep->require_subcommand(0, 1);
  auto list = std::make_shared<bool>(false);
  rep->add_flag("--list", *list, "Name every table with a runnable row, its paper and its report");

  reproduce::TableRegistry tables;
  reproduce::RegisterBuiltinTables(tables);
  for (auto& [app, run] : reproduce::AddTableSubcommands(*rep, tables, {ParseSeed, ParseSeedList}))
    out.push_back({app, run});

  // `dynref reproduce claims`: the claims ledger from the committed reports (no runs).
  auto claims = std::make_shared<reproduce::ClaimsArgs>();
  CLI::App* cl = rep->add_subcommand(
      "claims", "Write the claims ledger: every relative claim of the five papers, our numbers from the reports, "
                "a verdict each (reports/CLAIMS.md)");
  cl->add_option("--out", claims->out, "The ledger (default reports/CLAIMS.md)");
  cl->add_option("--reports", claims->reports,
                 "Folder of the reports and of paper-tables/ to read (default reports)");
  out.push_back({cl, [claims] { return reproduce::RunClaimsLedger(*claims); }});

  // `dynref reproduce --list` (the node itself; last, so a parsed table wins the dispatch in main).
  out.push_back({rep, [list, tables] {
                   if (!*list)
                     throw InputError("reproduce", "name a table (dynref reproduce --list shows them)");
                   std::cout << "table\tpaper\treport\twhat\n";
                   for (const auto& t : tables.Tables())
                     std::cout << t.name << "\t" << t.paper << "\t" << t.Report() << "\t" << t.what << "\n";
                   return kExitOk;
                 }});
}

}  // namespace dynref::cli
