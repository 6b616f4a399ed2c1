#!/usr/bin/env bash
# Backbone runtime benchmark (issue 5 "Speed"): per-module milliseconds per frame of
# `dynref run --method orb --trace off` on one core at 640x480 with 1000 ORB features, on
# synthetic sequences generated here (nothing downloaded). Prints a Markdown table (median and
# mean per module, keyframes, local BA calls, ATE, RPE over 1 frame) and writes it to $OUT/backbone_runtime.md.
#
#   bash scripts/bench-backbone.sh [FRAMES] [PRESET ...]
#   defaults: 300 frames, presets static_xyz walking_xyz; output under out/bench
#   (override with DYNREF_BENCH_OUT). Real TUM sequences: DYNREF_BENCH_SEQUENCES="path1 path2"
#   benchmarks those folders instead of synthetic presets.
#
# Timings are thread CPU time (see run.json "timing_clock"), so other processes on the machine
# change them little; they are not results and are never compared in tests.
set -euo pipefail
cd "$(dirname "$0")/.."
FRAMES=${1:-300}
shift || true
PRESETS=("$@")
[ ${#PRESETS[@]} -eq 0 ] && PRESETS=(static_xyz walking_xyz)
OUT=${DYNREF_BENCH_OUT:-out/bench}
DYNREF=${DYNREF:-build/dynref}
[ -x "$DYNREF" ] || bash scripts/build.sh
mkdir -p "$OUT"

SEQS=()
if [ -n "${DYNREF_BENCH_SEQUENCES:-}" ]; then
  read -r -a SEQS <<< "$DYNREF_BENCH_SEQUENCES"
else
  for p in "${PRESETS[@]}"; do
    seq="$OUT/seq/$p-$FRAMES"
    [ -f "$seq/groundtruth.txt" ] || "$DYNREF" synth --preset "$p" --frames "$FRAMES" --seed 1 --out "$seq"
    SEQS+=("$seq")
  done
fi

RUNS=()
for seq in "${SEQS[@]}"; do
  run="$OUT/run/$(basename "$seq")"
  "$DYNREF" run --method orb --sequence "$seq" --out "$run" --trace off --no-progress
  if [ -f "$seq/groundtruth.txt" ]; then
    "$DYNREF" eval --gt "$seq/groundtruth.txt" --est "$run/trajectory.txt" --delta 1 --delta-unit f --json "$run/eval.json" > /dev/null
  fi
  RUNS+=("$run")
done

python3 - "$OUT/backbone_runtime.md" "$("$DYNREF" version)" \
  "${RUNS[@]}" <<'EOF'
import json, os, sys
out, version, runs = sys.argv[1], sys.argv[2], sys.argv[3:]
modules = ["load", "extraction", "tracking", "local_mapping", "ba", "slam", "total"]
lines = ["# dynref backbone runtime (`--method orb --trace off`, one core, 640x480, 1000 features)", "",
         f"Built by `{version}`. Milliseconds per frame, thread CPU time: median / mean over all",
         "frames. `slam` = everything after image decoding (extraction + tracking + local mapping + BA,",
         "ORB-SLAM2's TrackRGBD span with local mapping run sequentially); `total` = load + slam.",
         "Local mapping and BA run only on keyframes, so their medians are 0 when fewer than half",
         "of the frames are keyframes; the mean is the amortised cost.", "",
         "| sequence | frames | keyframes | local BA calls | " + " | ".join(modules) + " | ATE rmse [m] | RPE 1 frame [m / deg] |",
         "|---|---:|---:|---:|" + "---:|" * len(modules) + "---:|---:|"]
for run in runs:
    j = json.load(open(os.path.join(run, "run.json")))
    t = j["timing"]
    cells = ["%.1f / %.1f" % (t[m]["median_ms_per_frame"], t[m]["mean_ms_per_frame"]) for m in modules]
    ate = rpe = "-"
    ev = os.path.join(run, "eval.json")
    if os.path.exists(ev):
        e = json.load(open(ev))
        ate = "%.4f" % e["ate"]["stats"]["rmse"]
        rpe = "%.4f / %.3f" % (e["rpe"]["translational_m"]["rmse"], e["rpe"]["rotational_deg"]["rmse"])
    lines.append("| %s | %d | %d | %d | %s | %s | %s |" % (os.path.basename(run), j["frames_processed"],
                 j["keyframes"], j["local_ba_calls"], " | ".join(cells), ate, rpe))
text = "\n".join(lines) + "\n"
tmp = out + ".tmp"
open(tmp, "w").write(text)
os.replace(tmp, out)
print(text, end="")
EOF
