// The working folder of a reproduction: synthetic sequences (one per preset, re-synthesised when
// their arguments change) and runs (one per variant, reused with --reuse when the sequence and the
// resolved config are unchanged), each marked with the key it was made from.
#pragma once
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "eval/statistics.h"
#include "pipeline/method_config.h"

namespace dynref::reproduce {

// configs/<config_name>.yaml without the named stages / map modules (components that do not
// influence tracking, e.g. a dense map, removed to save time). Configs as data: no YAML edited.
MethodConfig LoadConfigWithout(const std::string& config_name, const std::vector<std::string>& drop);

struct SynthSpec {
  int frames = 300;  // 0 = each preset's own length, that of the real sequence it imitates (--frames 0)
  uint64_t seed = 1;
  std::string detections = "yolo-like";  // synthetic detection mode (SEQ/detections/<mode>)
  bool blur = false;                     // dynref synth --blur (seed 003)
  bool low_light = false;                // dynref synth --low-light (seed 004)
};

// The frames `spec` gives `preset`'s sequence: spec.frames, or the preset's default length when 0.
int FramesOf(const SynthSpec& spec, const std::string& preset);

// One run of one variant on one sequence, evaluated.
struct RunSummary {
  std::string method, label, run_dir, end_state;
  int frames = 0, tracked = 0, keyframes = 0;
  bool has_ate = false;
  std::string ate_problem;
  ErrorStats ate;
  bool has_pr = false;  // precision/recall of rejected features (methods with stages)
  int64_t tp = 0, fp = 0, fn = 0, tn = 0;  // truth: the keypoint's instance moves (SEQ/gt/moving.txt)
  int64_t part_tp = 0, part_fp = 0, part_fn = 0, part_tn = 0;  // truth: its pixel moves (SEQ/gt/motion/*.png)
  // Frame lines (kind line_sample decisions), truth at the segment's midpoint: its instance moves /
  // its pixel moves. Only runs whose frames have lines (backbone lines on) count any.
  int64_t line_tp = 0, line_fp = 0, line_fn = 0, line_tn = 0;
  int64_t line_part_tp = 0, line_part_fp = 0, line_part_fn = 0, line_part_tn = 0;
  // Instance masks a stage decided on (kind instance_mask decisions, e.g. epi.vote's 60 % vote),
  // truth: the ground-truth instance under most of the mask's pixels moves. Still people (a
  // person instance that does not move, e.g. seated) and moving objects (a moving instance that is
  // not a person, e.g. a pushed chair) are counted apart too.
  int64_t mask_tp = 0, mask_fp = 0, mask_fn = 0, mask_tn = 0;
  int64_t still_person_masks = 0, still_person_kept = 0, moving_object_masks = 0, moving_object_rejected = 0;
  bool has_rpe = false;     // RPE over 1 s (evaluate_rpe.py --fixed_delta --delta 1): m/s and deg/s
  ErrorStats rpe_trans, rpe_rot;
  double ms_slam = std::nan("");  // run.json timing: mean thread-CPU ms per frame (machine-dependent)
  double ms_total = std::nan("");
  std::string commit;  // run.json dynref_commit: the build that made the run (--collect may read older runs)
  // every run.json timing module, + "stages" (sum of timing_stages) and "stage:<name>" per stage
  std::map<std::string, double> ms_modules;
};

// Adds every precision/recall count of `from` (points, lines, both truths) to `to`.
void AddRejectionCounts(RunSummary& to, const RunSummary& from);

// How a Workspace treats its folder.
enum class WorkMode {
  kMake,     // synthesise and run what is missing or out of date (with reuse: keep what is current)
  kCollect,  // only read: every sequence and run must exist, made by `dynref synth` / `dynref run`
             // (e.g. by workflow/Snakefile) with the same arguments and config, else InputError
};

// <work>/seed<S>: the folder of one synthesis seed (its seq/ and runs/), as workflow/Snakefile writes it.
std::string SeedWorkDir(const std::string& work, uint64_t seed);

// The Markdown table "dynref frames per run | paper sequence | paper frames (full sequence)" of the
// presets; paper_rows[i] names preset i's real sequence, "" when none (printed "-"). The paper's
// frame count is the preset's default length, which imitates the real TUM sequence; frames 0 runs
// every preset at that length.
std::string FramesTable(const std::vector<std::string>& presets, int frames, const std::vector<std::string>& paper_rows);

// The distinct commits that made `runs`, in order: "abc123" or "abc123, def456".
std::string RunCommits(const std::vector<RunSummary>& runs);

class Workspace {
 public:
  Workspace(std::string dir, SynthSpec spec, bool reuse, WorkMode mode = WorkMode::kMake);
  const std::string& dir() const { return dir_; }
  const SynthSpec& spec() const { return spec_; }
  // SEQ = <dir>/seq/<preset>, synthesised unless current (InputError when the folder exists and
  // was not written by reproduce). kCollect: checks SEQ/synth.yaml against the spec instead.
  std::string EnsureSequence(const std::string& preset);
  // Runs `config` on seq_dir into <dir>/runs/<run_name> (trace level full when the config has
  // stages), then ATE against ground truth and, for configs with stages, the precision/recall of
  // the features they rejected (trace Decision kept=false of any stage) against SEQ/gt/moving.txt.
  // kCollect: the run must exist, be finished and have run the same config (run.json "config").
  RunSummary Run(const std::string& seq_dir, const std::string& run_name, const MethodConfig& config,
                 const std::string& label);
  // "frames" keeps runs with stages at trace level frames (no precision/recall; for methods that
  // trace every keypoint of 3000-feature frames, where full traces of a table reach tens of GB).
  void set_stage_trace_level(const std::string& level) { stage_trace_level_ = level; }
  // With false, a run traced at level full keeps only its precision/recall counts
  // (RUN/rejection.json, also read back on --reuse / --collect) and its trace.dtr is deleted once
  // counted: full traces of a whole table would fill the disk (~250 MB per 300-frame run).
  void set_keep_full_traces(bool keep) { keep_full_traces_ = keep; }

 private:
  std::string dir_;
  SynthSpec spec_;
  bool reuse_;
  WorkMode mode_;
  std::string stage_trace_level_ = "full";
  bool keep_full_traces_ = true;
  std::set<std::string> made_;  // sequences synthesised by this Workspace (never twice)
};

}  // namespace dynref::reproduce
