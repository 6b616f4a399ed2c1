#!/usr/bin/env bash
# --threads N (issue 18): per-module ms per frame of `dynref run` with 1 and N threads on a
# synthetic sequence, trace off, and the check that the trajectories are byte-identical.
# Timings: thread CPU ms with 1 thread, wall-clock ms with N > 1 (run.json timing_clock; on an
# otherwise idle machine a single-threaded run's CPU and wall time agree). Never a timed test.
#
#   bash scripts/bench-threads.sh [PRESET] [FRAMES] [THREADS]   (default walking_xyz 300 2)
#   METHODS="orb mgd sgdo blur epi semantic" SEED=1 DYNREF=build/dynref DYNREF_BENCH_OUT=out/bench
set -euo pipefail
cd "$(dirname "$0")/.."
PRESET=${1:-walking_xyz}
FRAMES=${2:-300}
N=${3:-2}
SEED=${SEED:-1}
METHODS=(${METHODS:-orb mgd sgdo blur epi semantic})
OUT=${DYNREF_BENCH_OUT:-out/bench}
DYNREF=${DYNREF:-build/dynref}
[ -x "$DYNREF" ] || bash scripts/build.sh
seq="$OUT/seq/$PRESET-$FRAMES-s$SEED"
[ -f "$seq/groundtruth.txt" ] || "$DYNREF" synth --preset "$PRESET" --frames "$FRAMES" --seed "$SEED" \
  --detections yolo-like --out "$seq" > /dev/null
echo "| method | threads | extraction ms | tracking ms | local mapping ms | slam ms | method stages ms | wall s (whole run) | trajectory |"
echo "|---|---|---|---|---|---|---|---|---|"
for m in "${METHODS[@]}"; do
  for t in 1 "$N"; do
    run="$OUT/runs/threads-$PRESET-$m-$t"
    start=$(date +%s.%N)
    "$DYNREF" run --sequence "$seq" --out "$run" --method "$m" --detections "$seq/detections/yolo-like" \
      --trace off --threads "$t" --no-progress > /dev/null
    end=$(date +%s.%N)
    same="-"
    [ "$t" != 1 ] && { cmp -s "$run/trajectory.txt" "$OUT/runs/threads-$PRESET-$m-1/trajectory.txt" && same="identical" || same="DIFFERS"; }
    [ "$t" != 1 ] && [ -f "$run/dense_map.ply" ] && { cmp -s "$run/dense_map.ply" "$OUT/runs/threads-$PRESET-$m-1/dense_map.ply" && same="$same, dense map identical" || same="$same, dense map DIFFERS"; }
    python3 - "$run/run.json" "$m" "$t" "$start" "$end" "$same" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
t = j["timing"]
ms = lambda k: t[k]["mean_ms_per_frame"]
wall = float(sys.argv[5]) - float(sys.argv[4])
stages = ", ".join(f"{k} {v:.2f}" for k, v in sorted(j.get("timing_stages", {}).items())) or "-"
print(f"| {sys.argv[2]} | {sys.argv[3]} | {ms('extraction'):.2f} | {ms('tracking'):.2f} | {ms('local_mapping'):.2f} | "
      f"{ms('slam'):.2f} | {stages} | {wall:.1f} | {sys.argv[6]} |")
PY
  done
done
