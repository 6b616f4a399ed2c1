#include "reproduce/table_registry.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <stdexcept>
#include <tuple>

namespace dynref::reproduce {

void TableRegistry::Add(TableDef table) {
  if (!table.add) throw std::logic_error("reproduce table " + table.name + " has no options/runner");
  if (Find(table.name)) throw std::logic_error("reproduce table " + table.name + " registered twice");
  const auto before = [&](const TableDef& t) {
    return std::tie(table.paper, table.name) < std::tie(t.paper, t.name);
  };
  tables_.insert(std::find_if(tables_.begin(), tables_.end(), before), std::move(table));
}

const TableDef* TableRegistry::Find(const std::string& name) const {
  for (const TableDef& t : tables_)
    if (t.name == name) return &t;
  return nullptr;
}

void AddMatrixOptions(CLI::App& app, MatrixArgs& a, const MatrixHelp& help) {
  app.add_option("--out", a.out, "Markdown report (default " + a.out + ")");
  app.add_option("--work", a.work, help.work + " (default " + a.work + ")");
  app.add_option("--frames", a.frames,
                 help.frames.empty() ? "Frames per synthetic sequence; 0 = each preset's own length, that of the real "
                                       "sequence it imitates (the paper's length) (default " + std::to_string(a.frames) + ")"
                                     : help.frames);
  CLI::Option* seeds = app.add_option("--seeds", a.seeds_text, help.seeds)->delimiter(',');
  if (!help.seed.empty()) app.add_option("--seed", a.seed_text, help.seed)->excludes(seeds);
  if (!help.detections.empty()) app.add_option("--detections", a.detections, help.detections);
  if (!help.sequences.empty()) app.add_option("--sequences", a.sequences, help.sequences)->delimiter(',');
}

void AddReuseCollect(CLI::App& app, MatrixArgs& a, const std::string& reuse, const std::string& collect) {
  app.add_flag("--reuse", a.reuse, reuse);
  if (!collect.empty()) app.add_flag("--collect", a.collect, collect);
}

std::vector<std::pair<CLI::App*, std::function<int()>>> AddTableSubcommands(CLI::App& reproduce,
                                                                           const TableRegistry& tables,
                                                                           const SeedParsers& seeds) {
  std::vector<std::pair<CLI::App*, std::function<int()>>> out;
  for (const TableDef& t : tables.Tables()) {
    CLI::App* app = reproduce.add_subcommand(t.name, t.help);
    const TableCommand c = t.add(*app);
    out.emplace_back(app, [c, seeds] {
      if (!c.args->seed_text.empty()) c.args->seeds = {seeds.one(c.args->seed_text, "--seed")};
      if (!c.args->seeds_text.empty()) c.args->seeds = seeds.list(c.args->seeds_text, "--seeds");
      return c.run();
    });
  }
  return out;
}

}  // namespace dynref::reproduce
