// `dynref diff GOLDEN CANDIDATE`: first divergence + per-stage summary (ref/trace/README.md "Diff").
#include <iostream>

#include "cli/command.h"
#include "core/error.h"
#include "trace/trace_diff.h"
#include "trace/trace_reader.h"

namespace dynref::cli {

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
                   const trace::DiffResult r = trace::DiffTraces(g, c, args->options);
                   std::cout << r.Report(g, c, args->options);
                   return r.ExitCode();
                 }});
}

}  // namespace dynref::cli
