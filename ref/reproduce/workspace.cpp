#include "reproduce/workspace.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/version.h"
#include "eval/trajectory_eval.h"
#include "io/sequence.h"
#include "io/trajectory.h"
#include "pipeline/pipeline.h"
#include "render/overlay.h"
#include "synth/synth.h"
#include "trace/trace_reader.h"

namespace fs = std::filesystem;

namespace dynref::reproduce {
namespace {

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open file");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string SynthKey(const SynthSpec& s, const std::string& preset) {
  return "preset " + preset + " frames " + std::to_string(s.frames) + " seed " + std::to_string(s.seed) +
         " detections " + s.detections + (s.blur ? " blur" : "") + (s.low_light ? " low-light" : "") + " dynref " + DYNREF_GIT_COMMIT + "\n";
}

// Precision/recall of the features rejected by the config's stages against GT motion labels: a
// feature is truly dynamic iff its pixel belongs to an instance listed in SEQ/gt/moving.txt.
void RejectionPrecisionRecall(const std::string& seq_dir, const std::set<std::string>& stages, RunSummary& s) {
  const Sequence seq = OpenSequence(seq_dir);
  render::GroundTruthLabels gt(seq_dir);
  trace::TraceReader reader(s.run_dir + "/trace.dtr");
  if (reader.level() != trace::Level::kFull) return;
  for (size_t g = 0; g < reader.groups().size(); ++g) {
    const int64_t frame = reader.groups()[g].frame;
    if (frame < 0 || frame >= static_cast<int64_t>(seq.frames.size())) continue;
    const std::string& stamp = seq.frames[static_cast<size_t>(frame)].rgb_stamp_text;
    if (!gt.Has(stamp)) continue;
    render::GtFrame gf;
    gf.instance_ids = gt.Read(stamp).instance_ids;
    gf.moving = gt.Moving(stamp);
    std::map<int64_t, std::pair<double, double>> obs;
    std::set<int64_t> rejected;
    const std::string prefix = "f" + std::to_string(frame) + ".";
    for (const trace::Record& r : reader.ReadGroup(g)) {
      if (r.type == trace::RecordType::kObservation) obs[r.feature_index] = {r.u, r.v};
      if (r.type == trace::RecordType::kDecision && !r.kept && r.kind == trace::EntityKind::kFeature &&
          stages.count(r.stage) && r.entity.rfind(prefix, 0) == 0)
        rejected.insert(std::stoll(r.entity.substr(prefix.size())));
    }
    for (const auto& [idx, uv] : obs) {
      const bool dyn = gf.IsDynamic(uv.first, uv.second);
      const bool rej = rejected.count(idx) > 0;
      s.tp += dyn && rej, s.fp += !dyn && rej, s.fn += dyn && !rej, s.tn += !dyn && !rej;
    }
  }
  s.has_pr = true;
}

}  // namespace

MethodConfig LoadConfigWithout(const std::string& config_name, const std::vector<std::string>& drop) {
  MethodConfig cfg = LoadMethodConfig(MethodConfigPath(config_name));
  for (const std::string& name : drop)
    cfg.stages.erase(std::remove_if(cfg.stages.begin(), cfg.stages.end(),
                                    [&](const StageConfig& s) { return s.name == name; }),
                     cfg.stages.end());
  return cfg;
}

Workspace::Workspace(std::string dir, SynthSpec spec, bool reuse)
    : dir_(std::move(dir)), spec_(std::move(spec)), reuse_(reuse) {}

std::string Workspace::EnsureSequence(const std::string& preset) {
  const std::string dir = dir_ + "/seq/" + preset;
  const std::string marker = dir + "/.dynref-reproduce";
  const bool current = fs::exists(marker) && ReadText(marker) == SynthKey(spec_, preset);
  if (current && (reuse_ || made_.count(dir))) return dir;
  if (fs::exists(dir)) {
    if (!fs::exists(marker)) throw InputError(dir, "exists and was not written by dynref reproduce; refusing to overwrite");
    fs::remove_all(dir);
  }
  fs::create_directories(dir_ + "/seq");
  synth::SynthOptions o;
  o.preset = preset;
  o.frames = spec_.frames;
  o.seed = spec_.seed;
  o.detections = spec_.detections;
  o.blur = spec_.blur;
  o.low_light = spec_.low_light;
  o.out = dir;
  std::cerr << "reproduce: synth " << preset << " (" << spec_.frames << " frames, seed " << spec_.seed
            << (spec_.blur ? ", blur" : "") << (spec_.low_light ? ", low light" : "") << ")\n";
  synth::GenerateSequence(o);
  AtomicWriteFile(marker, SynthKey(spec_, preset));
  made_.insert(dir);
  return dir;
}

RunSummary Workspace::Run(const std::string& seq_dir, const std::string& run_name, const MethodConfig& config,
                          const std::string& label) {
  RunSummary s;
  s.method = config.method;
  s.label = label;
  s.run_dir = dir_ + "/runs/" + run_name;
  const std::string marker = s.run_dir + "/.dynref-reproduce";
  const std::string key = ReadText(seq_dir + "/.dynref-reproduce") + config.ToJson();
  const bool has_stages = !config.stages.empty();
  if (!(reuse_ && fs::exists(marker) && ReadText(marker) == key)) {
    RunOptions o;
    o.sequence = seq_dir;
    o.out_dir = s.run_dir;
    o.method = config.method;
    o.config = std::make_shared<const MethodConfig>(config);
    o.trace_level = has_stages ? stage_trace_level_ : "frames";
    o.detections_dir = seq_dir + "/detections/" + spec_.detections;
    o.progress = false;
    std::cerr << "reproduce: run " << run_name << "\n";
    fs::remove(marker);
    const RunResult r = RunSequence(o);
    if (r.exit_code != 0) throw InputError(s.run_dir, "run failed: " + r.end_state);
    AtomicWriteFile(marker, key);
  }
  const TumTrajectory gt = ReadTumTrajectory(seq_dir + "/groundtruth.txt");
  TumReadOptions ro;
  ro.allow_empty = true;
  const TumTrajectory est = ReadTumTrajectory(s.run_dir + "/trajectory.txt", ro);
  s.tracked = static_cast<int>(est.poses.size());
  s.frames = static_cast<int>(OpenSequence(seq_dir).frames.size());
  try {
    const AteResult ate = ComputeAte(gt, est, AteOptions{});
    s.ate = ate.stats;
    s.has_ate = true;
  } catch (const InputError& e) {
    s.ate_problem = e.what();
  }
  if (has_stages && stage_trace_level_ == "full") {
    std::set<std::string> stages;
    for (const StageConfig& sc : config.stages) stages.insert(sc.name);
    RejectionPrecisionRecall(seq_dir, stages, s);
  }
  return s;
}

}  // namespace dynref::reproduce
