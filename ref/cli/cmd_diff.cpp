// `dynref diff GOLDEN CANDIDATE`: first divergence + per-stage summary (ref/trace/README.md "Diff").
#include <fstream>
#include <iostream>

#include "cli/command.h"
#include "core/error.h"
#include "trace/trace_diff.h"
#include "trace/trace_reader.h"

namespace dynref::cli {

namespace {

// A canonical .jsonl trace without a single record is unreadable input (exit 2), as an empty
// binary trace is, not a trace that diverged (issue 37).
void RequireRecords(const std::string& path) {
  if (path.size() < 6 || path.compare(path.size() - 6, 6, ".jsonl") != 0) return;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line))
    if (line.find_first_not_of(" \t\r") != std::string::npos) return;
  throw InputError(path, "empty JSONL trace (no records)");
}

// A --tol FIELD that names no float field of the compared records (nor its base name, "T_wc" for
// "T_wc[3]") would silently do nothing: refused with the fields there are (issue 37).
void RequireToleranceFields(const trace::DiffOptions& options, const trace::DiffResult& r) {
  for (const auto& [field, tol] : options.field_abs_tol) {
    (void)tol;
    bool found = false;
    std::string known;
    for (const auto& [name, err] : r.field_errors) {
      (void)err;
      const std::string base = name.substr(0, name.find('['));
      found = found || name == field || base == field;
      if (known.find(" " + base + ",") == std::string::npos) known += " " + base + ",";
    }
    if (!found)
      throw InputError("--tol", "no float field '" + field + "' in the compared records (fields:" +
                                    (known.empty() ? " none" : known.substr(0, known.size() - 1)) + ")");
  }
}

}  // namespace

void RegisterDiffCommand(CLI::App& root, CommandList& out) {
  struct Args {
    std::string golden, candidate;
    trace::DiffOptions options;
    std::vector<std::string> tolerances;
  };
  auto args = std::make_shared<Args>();
  CLI::App* app = root.add_subcommand(
      "diff", "Compare two traces by key; report the first divergence in processing order "
              "(exit 0 match, 1 diverged, 2 unreadable/truncated/other schema version)");
  app->add_option("golden", args->golden, "Golden run directory, trace file or canonical .jsonl")->required();
  app->add_option("candidate", args->candidate, "Candidate run directory, trace file or canonical .jsonl")->required();
  app->add_option("--abs", args->options.abs_tol, "Absolute float tolerance (default 0: exact)");
  app->add_option("--rel", args->options.rel_tol, "Relative float tolerance (default 0)");
  app->add_option("--tol", args->tolerances, "Per-field absolute tolerance FIELD=X (repeatable)");
  app->add_option("--max-report", args->options.max_report, "Divergences listed (default 20)");
  app->add_flag("--summary", args->options.summary,
                "Also summarise how far the candidate strays: final pose deviation (mm, deg) and the "
                "distribution of probability differences per stage over the records both runs share");
  out.push_back({app, [args] {
                   for (const std::string& t : args->tolerances) args->options.AddFieldTolerance(t);
                   const std::string g = trace::ResolveTracePath(args->golden);
                   const std::string c = trace::ResolveTracePath(args->candidate);
                   RequireRecords(g);
                   RequireRecords(c);
                   const trace::DiffResult r = trace::DiffTraces(g, c, args->options);
                   RequireToleranceFields(args->options, r);
                   std::cout << r.Report(g, c, args->options);
                   return r.ExitCode();
                 }});
}

}  // namespace dynref::cli
