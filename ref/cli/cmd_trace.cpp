// `dynref trace dump|feature|bench`: read traces (ref/trace/README.md).
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <iostream>

#include "cli/command.h"
#include "core/error.h"
#include "core/format.h"
#include "render/feature_plot.h"
#include "trace/trace_copy.h"
#include "trace/trace_dump.h"
#include "trace/trace_feature.h"
#include "trace/trace_reader.h"

namespace dynref::cli {
namespace {

// --frame must name a frame group of the trace (exit 2 otherwise, like --frames beyond a sequence).
void CheckFrameInTrace(trace::TraceReader& reader, int64_t frame) {
  int64_t lo = 0, hi = -1;
  bool any = false;
  for (const auto& g : reader.groups()) {
    if (g.frame == frame) return;
    lo = any ? std::min(lo, g.frame) : g.frame;
    hi = any ? std::max(hi, g.frame) : g.frame;
    any = true;
  }
  throw InputError(reader.path(), "--frame " + std::to_string(frame) + ": no such frame in this trace (" +
                                      (any ? "frames " + std::to_string(lo) + ".." + std::to_string(hi)
                                           : std::string("no frames")) +
                                      ")");
}

void AddDump(CLI::App* parent, CommandList& out) {
  struct Args {
    std::string run;
    int64_t frame = 0;
    trace::DumpOptions options;
  };
  auto args = std::make_shared<Args>();
  CLI::App* app = parent->add_subcommand("dump", "Canonical text dump (one CSV row per field, or JSONL)");
  app->add_option("run", args->run, "Run directory or trace file")->required();
  app->footer(
      "Exit 0 also when the filters match no record (a query, like an empty grep; a note goes to "
      "stderr). Exit 2: unreadable trace, bad option, or a --frame that is not in the trace.");
  CLI::Option* frame = app->add_option("--frame", args->frame,
                                       "Only this frame (-1 = records before the first frame)");
  app->add_option("--stage", args->options.stage, "Only this stage / optimiser call id");
  app->add_option("--entity", args->options.entity, "Only this entity id (and its residuals ID@...)");
  app->add_option("--format", args->options.format, "csv (default) or jsonl");
  app->add_flag("--header", args->options.header, "Print the run header instead of records");
  out.push_back({app, [args, frame] {
                   if (frame->count()) {
                     if (args->frame < -1)
                       throw InputError("--frame", "must be a frame index >= 0 (or -1 for the records before "
                                                   "the first frame), got " + std::to_string(args->frame));
                     args->options.frame = args->frame;
                   }
                   args->options.Check();
                   trace::TraceReader reader(trace::ResolveTracePath(args->run));
                   if (args->options.frame) CheckFrameInTrace(reader, *args->options.frame);
                   const uint64_t written = trace::WriteDump(reader, args->options, std::cout);
                   std::cout.flush();
                   if (written == 0 && !args->options.header && reader.record_count() > 0)
                     std::cerr << "dynref: note: no record of " << reader.path() << " matched"
                               << (args->options.frame ? " --frame " + std::to_string(*args->options.frame) : "")
                               << (args->options.stage.empty() ? "" : " --stage " + args->options.stage)
                               << (args->options.entity.empty() ? "" : " --entity " + args->options.entity)
                               << " (nothing dumped)\n";
                   return std::cout ? int{kExitOk} : int{kExitBadInput};
                 }});
}

void AddFeature(CLI::App* parent, CommandList& out) {
  struct Args {
    std::string run, id, plot;
    bool follow = false;
  };
  auto args = std::make_shared<Args>();
  CLI::App* app = parent->add_subcommand(
      "feature", "Whole life of one feature (f<frame>.<index>) or map point (mp<id>): every "
                 "observation, update, residual and decision across frames");
  app->add_option("run", args->run, "Run directory or trace file")->required();
  app->add_option("id", args->id, "Entity id, e.g. mp17 or f42.3 (any canonical id: f|i|l|pl|r<frame>.<n>, mp|kf|ml|mpl<n>)")
      ->required();
  app->footer(
      "--follow chains the entity across the run: previous-frame links (PROB input prev_index), "
      "map point / map line links (PROB inputs map_point, map_line; OBS associated_map_point_id) and "
      "instance masks with the same id; it prints the chain as '# <frame> -> <entity>' lines, then "
      "the records of every entity in it (ref/trace/README.md \"Following a feature\").\n"
      "Exit 1 if no record mentions ID; exit 2 for a malformed ID or an unreadable trace.");
  app->add_option("--plot", args->plot, "Write probability vs frame to this PNG");
  app->add_flag("--follow", args->follow,
                "Follow the feature / line / mask / map point across frames (chain, then its records)");
  out.push_back({app, [args] {
                   if (!trace::IsCanonicalEntityId(args->id))
                     throw InputError("id", "'" + args->id + "' is not an entity id (expected f<frame>.<index>, "
                                            "mp<id>, kf<id>, i|l|pl|r<frame>.<index>, optionally @f<frame>|@kf<id>)");
                   trace::TraceReader reader(trace::ResolveTracePath(args->run));
                   const trace::FeatureHistory h = args->follow ? trace::CollectFollowHistory(reader, args->id)
                                                                : trace::CollectFeatureHistory(reader, args->id);
                   // The plot first: a reader closing stdout early (| head) must not lose it.
                   if (!args->plot.empty()) render::WriteFeaturePlot(h, args->plot);
                   if (args->follow) trace::WriteChainSection(h, std::cout);
                   trace::WriteFeatureTable(h, std::cout);
                   if (h.rows.empty()) {
                     std::cerr << "dynref: no record of " << reader.path() << " mentions " << args->id << "\n";
                     return int{kExitCheckFailed};
                   }
                   return int{kExitOk};
                 }});
}

// Re-writes every record of `path` through a TraceWriter, timing only the writer calls.
int Replay(const std::string& path, const std::string& out_path) {
  using namespace trace;
  TraceReader in(path);
  std::vector<std::vector<Record>> groups;
  for (size_t g = 0; g < in.groups().size(); ++g) groups.push_back(in.ReadGroup(g));
  const auto t0 = std::chrono::steady_clock::now();
  const std::clock_t c0 = std::clock();
  TraceWriter w(out_path, in.level(), RunHeader{});
  for (const auto& recs : groups)
    for (const Record& r : recs) WriteRecord(w, r);
  w.Close(in.end_state());
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  const double n = static_cast<double>(in.record_count());
  std::cout << "replayed " << path << "\nrecords " << in.record_count() << "\nframes "
            << groups.size() << "\nwriter_seconds " << FormatFixed(s, 3) << "\nrecords_per_s "
            << FormatFixed(n / s, 0) << "\nwriter_ms_per_frame "
            << FormatFixed(1000 * s / std::max<size_t>(groups.size(), 1), 3) << "\nwriter_cpu_seconds "
            << FormatFixed(cpu, 3) << "\nwriter_cpu_ms_per_frame "
            << FormatFixed(1000 * cpu / std::max<size_t>(groups.size(), 1), 3) << "\n";
  return int{kExitOk};
}

// Writer throughput on a synthetic SLAM-like workload (speed is measured here, never in tests).
void AddBench(CLI::App* parent, CommandList& out) {
  struct Args {
    int frames = 200, features = 1000, residuals = 3000;
    std::string out = "/tmp/dynref_trace_bench.dtr", replay;
  };
  auto args = std::make_shared<Args>();
  CLI::App* app = parent->add_subcommand("bench", "Measure trace writer throughput");
  app->add_option("--frames", args->frames, "Frames (default 200)");
  app->add_option("--features", args->features, "Features per frame (default 1000)");
  app->add_option("--residuals", args->residuals, "Residuals per frame (default 3000)");
  app->add_option("--out", args->out, "Trace file written (default /tmp/dynref_trace_bench.dtr)");
  app->add_option("--replay", args->replay,
                  "Instead: re-write the records of this run/trace through the writer (its exact "
                  "record mix) and time only the writer calls");
  out.push_back({app, [args] {
                   using namespace trace;
                   if (args->frames < 1) throw InputError("--frames", "must be >= 1, got " + std::to_string(args->frames));
                   if (args->features < 1)
                     throw InputError("--features", "must be >= 1, got " + std::to_string(args->features));
                   if (args->residuals < 0)
                     throw InputError("--residuals", "must be >= 0, got " + std::to_string(args->residuals));
                   if (!args->replay.empty()) return Replay(trace::ResolveTracePath(args->replay), args->out);
                   const auto t0 = std::chrono::steady_clock::now();
                   const std::clock_t c0 = std::clock();
                   TraceWriter w(args->out, Level::kFull, RunHeader{});
                   std::vector<std::string> mp_ids(args->features), obs_ids(args->features);
                   for (int i = 0; i < args->features; ++i) mp_ids[i] = "mp" + std::to_string(i * 7);
                   std::vector<double> r0 = {0.5, -0.25, 0.125}, r1 = {0.01, -0.02, 0.003};
                   for (int f = 0; f < args->frames; ++f) {
                     w.BeginFrame(f, 0.033 * f);
                     w.FramePose("initial", SE3::Identity());
                     w.FrameCount("extract", "keypoints", args->features);
                     const std::string fsuffix = "@f" + std::to_string(f);
                     for (int i = 0; i < args->features; ++i) {
                       w.Observation(i, i * 7, i * 7, 100.5 + i, 200.25, 1.5, i % 8, 0x9e3779b97f4a7c15ULL * i);
                       w.ProbabilityUpdate("mgd.temporal", EntityKind::kMapPoint, mp_ids[i],
                                           {{"d_px", 0.25 * i}, {"prior", 0.5}}, 0.5, 0.25);
                       if (i % 5 == 0)
                         w.Decision("sgdo.epipolar", EntityKind::kFeature,
                                    "f" + std::to_string(f) + "." + std::to_string(i), true, "inlier");
                     }
                     for (int i = 0; i < args->residuals; ++i)
                       w.Residual(i < args->residuals / 2 ? "track.pose#1" : "track.pose#2", "rgbd3",
                                  mp_ids[i % args->features] + fsuffix, r0, r1, 1.0, 1.0, 0.5, 0.25,
                                  true);
                     w.FramePose("final", SE3::Identity());
                   }
                   w.Close("complete");
                   const double s =
                       std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                   const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
                   TraceReader r(args->out);
                   std::FILE* f = std::fopen(args->out.c_str(), "rb");
                   std::fseek(f, 0, SEEK_END);
                   const double bytes = static_cast<double>(std::ftell(f));
                   std::fclose(f);
                   const double n = static_cast<double>(r.record_count());
                   std::cout << "records " << r.record_count() << "\nseconds " << FormatFixed(s, 3)
                             << "\nrecords_per_s " << FormatFixed(n / s, 0) << "\nbytes_per_record "
                             << FormatFixed(bytes / n, 1) << "\nms_per_frame "
                             << FormatFixed(1000 * s / args->frames, 3) << "\ncpu_seconds "
                             << FormatFixed(cpu, 3) << "\ncpu_ms_per_frame "
                             << FormatFixed(1000 * cpu / args->frames, 3) << "\n";
                   return int{kExitOk};
                 }});
}

}  // namespace

void AddTraceVerify(CLI::App* parent, CommandList& out);  // cmd_trace_verify.cpp

void RegisterTraceCommand(CLI::App& root, CommandList& out) {
  CLI::App* trace = root.add_subcommand("trace", "Read traces: dump, feature history, verify, bench");
  trace->require_subcommand(1);
  AddDump(trace, out);
  AddFeature(trace, out);
  AddTraceVerify(trace, out);
  AddBench(trace, out);
}

}  // namespace dynref::cli
