#include "reproduce/workspace.h"


#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/rng.h"
#include "core/version.h"
#include "eval/trajectory_eval.h"
#include "io/camera.h"
#include "io/mask_format.h"
#include "io/sequence.h"
#include "io/trajectory.h"
#include "pipeline/pipeline.h"
#include "render/overlay.h"
#include "synth/synth.h"
#include "synth/world.h"
#include "trace/trace_reader.h"
#include "io/image_file.h"

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

// One cell of a confusion matrix: truth = truly dynamic, rejected = a stage took it out.
void Count(bool truth, bool rejected, int64_t& tp, int64_t& fp, int64_t& fn, int64_t& tn) {
  tp += truth && rejected, fp += !truth && rejected, fn += truth && !rejected, tn += !truth && !rejected;
}

// The instance masks a stage decided on against the ground truth: a detection mask's truth is the
// ground-truth instance under most of its pixels (none: static), moving per SEQ/gt/moving.txt.
void CountMasks(const FrameDetections& det, const FrameDetections& truth, const std::set<int>& moving_ids,
                const std::map<int, bool>& kept, RunSummary& s) {
  // detection id -> gt instance id -> pixels (ascending gt id: ties keep the lower), one pass.
  std::map<int, std::map<int, int64_t>> votes;
  if (!det.instance_ids.empty() && det.instance_ids.size() == truth.instance_ids.size())
    for (int y = 0; y < det.instance_ids.rows; ++y) {
      const uint16_t* d = det.instance_ids.ptr<uint16_t>(y);
      const uint16_t* t = truth.instance_ids.ptr<uint16_t>(y);
      for (int x = 0; x < det.instance_ids.cols; ++x)
        if (d[x] != 0 && t[x] != 0 && kept.count(d[x]) != 0) ++votes[d[x]][t[x]];
    }
  for (const auto& [id, keep] : kept) {
    int gt_id = 0;
    int64_t best = 0;
    for (const auto& [tid, n] : votes[id])
      if (n > best) best = n, gt_id = tid;
    const bool moving = gt_id != 0 && moving_ids.count(gt_id) > 0;
    std::string gt_class;
    for (const DetectedInstance& in : truth.instances)
      if (in.id == gt_id) gt_class = in.class_name;
    Count(moving, !keep, s.mask_tp, s.mask_fp, s.mask_fn, s.mask_tn);
    if (gt_class == "person" && !moving) ++s.still_person_masks, s.still_person_kept += keep;
    if (gt_id != 0 && gt_class != "person" && moving) ++s.moving_object_masks, s.moving_object_rejected += !keep;
  }
}

// Precision/recall of the features (and frame lines) rejected by the config's stages against GT
// motion labels: a feature is truly dynamic iff its pixel (a line: its midpoint) belongs to an
// instance listed in SEQ/gt/moving.txt; "part" truth: that pixel itself moves (SEQ/gt/motion/).
void RejectionPrecisionRecall(const std::string& seq_dir, const std::string& detections_dir,
                              const std::set<std::string>& stages, RunSummary& s) {
  const Sequence seq = OpenSequence(seq_dir);
  render::GroundTruthLabels gt(seq_dir);
  std::unique_ptr<DetectionsReader> detections;  // none: no mask decisions to score
  if (fs::is_directory(detections_dir)) detections = std::make_unique<DetectionsReader>(detections_dir);
  trace::TraceReader reader(s.run_dir + "/trace.dtr");
  if (reader.level() != trace::Level::kFull) return;
  for (size_t g = 0; g < reader.groups().size(); ++g) {
    const int64_t frame = reader.groups()[g].frame;
    if (frame < 0 || frame >= static_cast<int64_t>(seq.frames.size())) continue;
    const std::string& stamp = seq.frames[static_cast<size_t>(frame)].rgb_stamp_text;
    if (!gt.Has(stamp)) continue;
    const FrameDetections truth = gt.Read(stamp);
    render::GtFrame gf;
    gf.instance_ids = truth.instance_ids;
    gf.moving = gt.Moving(stamp);
    std::map<int64_t, std::pair<double, double>> obs;
    std::set<int64_t> rejected;
    std::map<std::string, std::pair<double, double>> line_mid;  // the geometry record's segment midpoint
    std::set<std::string> line_rejected;
    std::map<int, bool> mask_kept;  // detection instance id -> the stage's decision
    const std::string prefix = "f" + std::to_string(frame) + ".", mask_prefix = "i" + std::to_string(frame) + ".";
    for (const trace::Record& r : reader.ReadGroup(g)) {
      const bool rejection = r.type == trace::RecordType::kDecision && !r.kept && stages.count(r.stage);
      if (r.type == trace::RecordType::kDecision && stages.count(r.stage) && r.kind == trace::EntityKind::kInstanceMask &&
          r.entity.rfind(mask_prefix, 0) == 0)
        mask_kept[std::stoi(r.entity.substr(mask_prefix.size()))] = r.kept;
      if (r.type == trace::RecordType::kObservation) obs[r.feature_index] = {r.u, r.v};
      if (rejection && r.kind == trace::EntityKind::kFeature && r.entity.rfind(prefix, 0) == 0)
        rejected.insert(std::stoll(r.entity.substr(prefix.size())));
      if (r.kind != trace::EntityKind::kLineSample) continue;
      if (rejection) line_rejected.insert(r.entity);
      if (r.type == trace::RecordType::kProbability && r.stage == trace::kGeometryStage) {
        double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
        for (const trace::NamedValue& nv : r.inputs) {
          if (nv.name == "x0") x0 = nv.value;
          if (nv.name == "y0") y0 = nv.value;
          if (nv.name == "x1") x1 = nv.value;
          if (nv.name == "y1") y1 = nv.value;
        }
        line_mid[r.entity] = {0.5 * (x0 + x1), 0.5 * (y0 + y1)};
      }
    }
    // Per-part truth: the moving pixels of the frame (a seated person's arm, not their still legs).
    const cv::Mat motion = dynref::ImageRead(seq_dir + "/gt/motion/" + stamp + ".png", cv::IMREAD_UNCHANGED);
    const auto moving_pixel = [&](double u, double v) {
      const int x = static_cast<int>(std::floor(u + 0.5)), y = static_cast<int>(std::floor(v + 0.5));
      return !motion.empty() && x >= 0 && y >= 0 && x < motion.cols && y < motion.rows && motion.at<uint8_t>(y, x) != 0;
    };
    for (const auto& [idx, uv] : obs) {
      const bool rej = rejected.count(idx) > 0;
      Count(gf.IsDynamic(uv.first, uv.second), rej, s.tp, s.fp, s.fn, s.tn);
      Count(moving_pixel(uv.first, uv.second), rej, s.part_tp, s.part_fp, s.part_fn, s.part_tn);
    }
    for (const auto& [id, uv] : line_mid) {
      const bool rej = line_rejected.count(id) > 0;
      Count(gf.IsDynamic(uv.first, uv.second), rej, s.line_tp, s.line_fp, s.line_fn, s.line_tn);
      Count(moving_pixel(uv.first, uv.second), rej, s.line_part_tp, s.line_part_fp, s.line_part_fn, s.line_part_tn);
    }
    if (!mask_kept.empty() && detections != nullptr && detections->Has(stamp))
      CountMasks(detections->Read(stamp), truth, gf.moving, mask_kept, s);
  }
  s.has_pr = true;
}

// RUN/rejection.json: the counts of RejectionPrecisionRecall, kept when the full trace is dropped.
const char* const kRejectionFields[] = {"tp", "fp", "fn", "tn", "part_tp", "part_fp", "part_fn", "part_tn",
                                        "line_tp", "line_fp", "line_fn", "line_tn", "line_part_tp", "line_part_fp",
                                        "line_part_fn", "line_part_tn", "mask_tp", "mask_fp", "mask_fn", "mask_tn",
                                        "still_person_masks", "still_person_kept", "moving_object_masks",
                                        "moving_object_rejected"};
int64_t RunSummary::* const kRejectionCounts[] = {
    &RunSummary::tp,      &RunSummary::fp,      &RunSummary::fn,      &RunSummary::tn,
    &RunSummary::part_tp, &RunSummary::part_fp, &RunSummary::part_fn, &RunSummary::part_tn,
    &RunSummary::line_tp, &RunSummary::line_fp, &RunSummary::line_fn, &RunSummary::line_tn,
    &RunSummary::line_part_tp, &RunSummary::line_part_fp, &RunSummary::line_part_fn, &RunSummary::line_part_tn,
    &RunSummary::mask_tp, &RunSummary::mask_fp, &RunSummary::mask_fn, &RunSummary::mask_tn,
    &RunSummary::still_person_masks, &RunSummary::still_person_kept, &RunSummary::moving_object_masks,
    &RunSummary::moving_object_rejected};
static_assert(std::size(kRejectionFields) == std::size(kRejectionCounts));

void WriteRejectionCounts(const RunSummary& s, const std::string& key) {
  nlohmann::json j;
  j["key"] = Fnv1a64(key);  // of the run's marker: sequence, commit and config
  for (size_t i = 0; i < std::size(kRejectionCounts); ++i) j[kRejectionFields[i]] = s.*kRejectionCounts[i];
  AtomicWriteFile(s.run_dir + "/rejection.json", j.dump(1) + "\n");
}

// false when the file is missing or was counted for another run (key).
bool ReadRejectionCounts(RunSummary& s, const std::string& key) {
  const std::string path = s.run_dir + "/rejection.json";
  if (!fs::exists(path)) return false;
  const nlohmann::json j = nlohmann::json::parse(ReadText(path), nullptr, false);
  if (j.is_discarded() || j.value("key", uint64_t{0}) != Fnv1a64(key)) return false;
  for (size_t i = 0; i < std::size(kRejectionCounts); ++i) s.*kRejectionCounts[i] = j.value(kRejectionFields[i], int64_t{0});
  s.has_pr = true;
  return true;
}

// kCollect: SEQ/synth.yaml (written by `dynref synth`) must state the spec's arguments.
void CheckSynthesisedAs(const std::string& dir, const SynthSpec& spec, const std::string& preset) {
  const std::string path = dir + "/synth.yaml";
  if (!fs::exists(path))
    throw InputError(dir, "missing: --collect reads sequences made by `dynref synth --preset " + preset +
                              "` (run the workflow first)");
  std::map<std::string, std::string> kv;
  std::istringstream in(ReadText(path));
  for (std::string line; std::getline(in, line);) {
    const size_t colon = line.find(": ");
    if (line.empty() || line[0] == '#' || colon == std::string::npos) continue;
    kv[line.substr(0, colon)] = line.substr(colon + 2);
  }
  const std::vector<std::pair<std::string, std::string>> want = {
      {"preset", preset},
      {"frames", std::to_string(FramesOf(spec, preset))},
      {"seed", std::to_string(spec.seed)},
      {"blur", spec.blur ? "true" : "false"},
      {"low_light", spec.low_light ? "true" : "false"}};
  for (const auto& [key, value] : want)
    if (kv[key] != value)
      throw InputError(path, key + " is '" + kv[key] + "', this table needs '" + value + "'");
  // Tables synthesise full-size images (no --width); a `width:` line (written only for --width)
  // must then be the camera's own width.
  const std::string full_width = std::to_string(CameraPreset("synthetic").width);
  if (kv.count("width") && kv["width"] != full_width)
    throw InputError(path, "width is '" + kv["width"] + "', this table needs '" + full_width +
                               "' (a sequence made without --width)");
  if (!fs::is_directory(dir + "/detections/" + spec.detections))
    throw InputError(dir, "has no detections/" + spec.detections + " (dynref synth --detections " + spec.detections + ")");
}

// A config's JSON without its file path and the parameters' sources (values decide a run).
nlohmann::json ConfigValues(nlohmann::json j) {
  j.erase("config_file");
  const auto strip = [](nlohmann::json& params) {
    for (auto& [key, p] : params.items())
      if (p.is_object()) p.erase("source");
  };
  if (j.contains("backbone")) strip(j["backbone"]);
  if (j.contains("stages"))
    for (auto& st : j["stages"])
      if (st.contains("params")) strip(st["params"]);
  return j;
}

// kCollect: RUN/run.json must be a finished run of `config` (its path and sources aside) at `trace_level`
// on seq_dir with seq_dir/detections/<mode>.
void CheckRunAs(const std::string& run_dir, const std::string& seq_dir, const MethodConfig& config,
                const std::string& trace_level, const std::string& detections) {
  const std::string path = run_dir + "/run.json";
  if (!fs::exists(path))
    throw InputError(run_dir, "missing: --collect reads runs made by `dynref run` (run the workflow first)");
  const nlohmann::json j = nlohmann::json::parse(ReadText(path), nullptr, false);
  if (j.is_discarded() || !j.is_object()) throw InputError(path, "not valid JSON");
  if (j.value("end_state", std::string()).empty()) throw InputError(path, "run did not finish (no end_state)");
  if (ConfigValues(j.value("config", nlohmann::json::object())) != ConfigValues(nlohmann::json::parse(config.ToJson())))
    throw InputError(path, "ran a different config than " + config.path + " (method " + config.method + ")");
  if (j.value("trace_level", std::string()) != trace_level)
    throw InputError(path, "trace level is '" + j.value("trace_level", std::string()) + "', this table needs '" +
                               trace_level + "'");
  const auto canonical = [](const std::string& p) { return fs::weakly_canonical(fs::absolute(p)).string(); };
  if (!config.stages.empty() && canonical(j.value("detections", std::string())) != canonical(seq_dir + "/detections/" + detections))
    throw InputError(path, "used detections " + j.value("detections", std::string()) + ", this table needs " +
                               seq_dir + "/detections/" + detections);
}

}  // namespace

void AddRejectionCounts(RunSummary& to, const RunSummary& from) {
  for (int64_t RunSummary::* c : kRejectionCounts) to.*c += from.*c;
}

MethodConfig LoadConfigWithout(const std::string& config_name, const std::vector<std::string>& drop) {
  MethodConfig cfg = LoadMethodConfig(MethodConfigPath(config_name));
  for (const std::string& name : drop)
    cfg.stages.erase(std::remove_if(cfg.stages.begin(), cfg.stages.end(),
                                    [&](const StageConfig& s) { return s.name == name; }),
                     cfg.stages.end());
  return cfg;
}

int FramesOf(const SynthSpec& spec, const std::string& preset) {
  return spec.frames > 0 ? spec.frames : synth::GetPreset(preset).default_frames;
}

std::string SeedWorkDir(const std::string& work, uint64_t seed) { return work + "/seed" + std::to_string(seed); }

std::string FramesTable(const std::vector<std::string>& presets, int frames, const std::vector<std::string>& paper_rows) {
  std::string md = "| Sequence | dynref frames per run | paper sequence | paper frames (full sequence) |\n|---|---|---|---|\n";
  for (size_t i = 0; i < presets.size(); ++i) {
    const bool has = i < paper_rows.size() && !paper_rows[i].empty();
    const int run_frames = FramesOf(SynthSpec{frames}, presets[i]);
    md += "| " + presets[i] + " | " + std::to_string(run_frames) + " | " + (has ? paper_rows[i] : "-") + " | " +
          (has ? std::to_string(synth::GetPreset(presets[i]).default_frames) : "-") + " |\n";
  }
  return md;
}

std::string RunCommits(const std::vector<RunSummary>& runs) {
  std::set<std::string> seen;
  std::string out;
  for (const RunSummary& r : runs)
    if (seen.insert(r.commit).second) out += (out.empty() ? "" : ", ") + r.commit;
  return out;
}

Workspace::Workspace(std::string dir, SynthSpec spec, bool reuse, WorkMode mode)
    : dir_(std::move(dir)), spec_(std::move(spec)), reuse_(reuse), mode_(mode) {}

std::string Workspace::EnsureSequence(const std::string& preset) {
  const std::string dir = dir_ + "/seq/" + preset;
  if (mode_ == WorkMode::kCollect) {
    CheckSynthesisedAs(dir, spec_, preset);
    return dir;
  }
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
  std::cerr << "reproduce: synth " << preset << " (" << FramesOf(spec_, preset) << " frames, seed " << spec_.seed
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
  const bool has_stages = !config.stages.empty();
  const std::string trace_level = has_stages ? stage_trace_level_ : "frames";
  const std::string marker = s.run_dir + "/.dynref-reproduce";
  if (mode_ == WorkMode::kCollect) {
    CheckRunAs(s.run_dir, seq_dir, config, trace_level, spec_.detections);
  } else if (const std::string key = ReadText(seq_dir + "/.dynref-reproduce") + config.ToJson();
             !(reuse_ && fs::exists(marker) && ReadText(marker) == key)) {
    RunOptions o;
    o.sequence = seq_dir;
    o.out_dir = s.run_dir;
    o.method = config.method;
    o.config = std::make_shared<const MethodConfig>(config);
    o.trace_level = trace_level;
    o.detections_dir = seq_dir + "/detections/" + spec_.detections;
    o.progress = false;
    std::cerr << "reproduce: run " << run_name << "\n";
    fs::remove(marker);
    const RunResult r = RunSequence(o);
    // A method that never finds enough features to start (e.g. SIFT in the dark) is a result of
    // the table (0 % tracked, no ATE), not a failure of the reproducer.
    const bool never_started = r.end_state == kEndStateTooFewFeatures;
    if (r.exit_code != 0 && !never_started) throw InputError(s.run_dir, "run failed: " + r.end_state);
    if (never_started) std::cerr << "reproduce: " << run_name << " never initialised (kept as 0 % tracked)\n";
    AtomicWriteFile(marker, key);
  }
  const TumTrajectory gt = ReadTumTrajectory(seq_dir + "/groundtruth.txt");
  TumReadOptions ro;
  ro.allow_empty = true;
  const TumTrajectory est = ReadTumTrajectory(s.run_dir + "/trajectory.txt", ro);
  s.tracked = static_cast<int>(est.poses.size());
  const nlohmann::json run = nlohmann::json::parse(ReadText(s.run_dir + "/run.json"), nullptr, false);
  // The run's own count of the sequence's frames: a table's report reads no image once its runs
  // are counted, so the workflow may prune the sequence's images (workflow/Snakefile).
  s.frames = !run.is_discarded() && run.contains("frames_in_sequence")
                 ? run["frames_in_sequence"].get<int>()
                 : static_cast<int>(OpenSequence(seq_dir).frames.size());
  try {
    const AteResult ate = ComputeAte(gt, est, AteOptions{});
    s.ate = ate.stats;
    s.has_ate = true;
  } catch (const InputError& e) {
    s.ate_problem = e.what();
  }
  try {  // evaluate_rpe.py --fixed_delta --delta 1 (the read above keeps the last of equal stamps, as TUM)
    const RpeResult rpe = ComputeRpe(gt, est, RpeOptions{});
    s.rpe_trans = rpe.trans_m;
    s.rpe_rot = rpe.rot_deg;
    s.has_rpe = true;
  } catch (const InputError&) {
    // fewer than 2 pairs: the tables print n/a
  }
  if (!run.is_discarded()) s.commit = run.value("dynref_commit", std::string("unknown"));
  if (!run.is_discarded()) s.end_state = run.value("end_state", std::string());
  if (!run.is_discarded() && run.contains("timing")) {
    s.ms_slam = run["timing"]["slam"].value("mean_ms_per_frame", std::nan(""));
    s.ms_total = run["timing"]["total"].value("mean_ms_per_frame", std::nan(""));
    for (const auto& [module, t] : run["timing"].items())
      if (t.is_object() && t.contains("mean_ms_per_frame")) s.ms_modules[module] = t["mean_ms_per_frame"].get<double>();
    double stages = 0;
    const nlohmann::json timing_stages = run.value("timing_stages", nlohmann::json::object());
    for (const auto& [stage, ms] : timing_stages.items())
      if (ms.is_number()) stages += ms.get<double>(), s.ms_modules["stage:" + stage] = ms.get<double>();
    s.ms_modules["stages"] = stages;
  }
  if (has_stages && stage_trace_level_ == "full") {
    const std::string key = fs::exists(marker) ? ReadText(marker) : config.ToJson();
    if (fs::exists(s.run_dir + "/trace.dtr")) {
      std::set<std::string> stages;
      for (const StageConfig& sc : config.stages) stages.insert(sc.name);
      RejectionPrecisionRecall(seq_dir, seq_dir + "/detections/" + spec_.detections, stages, s);
      if (mode_ == WorkMode::kMake) WriteRejectionCounts(s, key);
      if (!keep_full_traces_ && mode_ == WorkMode::kMake) fs::remove(s.run_dir + "/trace.dtr");
    } else if (!ReadRejectionCounts(s, key)) {
      throw InputError(s.run_dir, "has neither trace.dtr nor a current rejection.json (run it again without --reuse)");
    }
  }
  return s;
}

}  // namespace dynref::reproduce
