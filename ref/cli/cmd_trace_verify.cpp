// `dynref trace verify RUN|TRACE [--stage S] [--frames A-B]`: recompute every PROB, DECISION and
// RESIDUAL record from the trace alone (ref/verify/README.md). Exit 0 all verified, 1 a mismatch
// or an unverifiable record, 2 bad input.
#include <iostream>

#include "cli/command.h"
#include "core/error.h"
#include "core/frame_range.h"
#include "verify/verify_run.h"

namespace dynref::cli {

void AddTraceVerify(CLI::App* parent, CommandList& out) {
  struct Args {
    std::string run, stage, frames;
    int examples = 3;
  };
  auto args = std::make_shared<Args>();
  CLI::App* app = parent->add_subcommand(
      "verify", "Recompute every probability update, decision and residual from the trace alone "
                "(an independent implementation of each stage's equations)");
  app->add_option("run", args->run, "Run directory or trace file")->required();
  app->add_option("--stage", args->stage, "Only records of this stage (or optimiser call family, e.g. localba)");
  app->add_option("--frames", args->frames, "Only these frames: A, A-B or A- (0-based, inclusive)");
  app->add_option("--examples", args->examples, "Mismatches / unverifiable records listed per stage (default 3)");
  app->footer("Exit 0: every record verified. Exit 1: a mismatch or an unverifiable record. Exit 2: bad input.");
  out.push_back({app, [args] {
                   verify::VerifyOptions options;
                   options.stage = args->stage;
                   if (args->examples < 0) throw InputError("--examples", "must be >= 0");
                   options.max_examples = args->examples;
                   if (!args->frames.empty()) {
                     const FrameRange range = ParseFrameRange(args->frames);
                     options.first_frame = range.first;
                     if (!range.open_ended()) options.last_frame = range.last;
                   }
                   trace::TraceReader reader(trace::ResolveTracePath(args->run));
                   if (reader.level() != trace::Level::kFull)
                     throw InputError(reader.path(), std::string("trace level is '") + trace::LevelName(reader.level()) +
                                                         "': only a --trace full run holds the records to verify");
                   const verify::TraceModel model(reader);
                   const verify::VerifyReport report = VerifyTrace(model, verify::AllVerifiers(), options);
                   WriteVerifyReport(report, model, std::cout);
                   std::cout.flush();
                   if (!std::cout) throw InputError("stdout", "write failed");
                   return report.ok() ? int{kExitOk} : int{kExitCheckFailed};
                 }});
}

}  // namespace dynref::cli
