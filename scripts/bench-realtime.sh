#!/usr/bin/env bash
# Real time on one core (issue 18): `dynref run --trace off` of orb and sgdo (dense map on) on
# synthetic seed-1 sequences, per-module ms per frame (thread CPU time, run.json), the dense map's
# stage time, the means over the first and last 100 frames, and the peak memory (GNU time).
# Writes a Markdown report. Numbers, never a timed test.
#
#   bash scripts/bench-realtime.sh [REPORT]     (default out/bench/realtime_bench.md)
#   FRAMES="600" LONG=900 PRESETS="walking_xyz walking_halfsphere static_xyz" METHODS="orb sgdo"
#   DYNREF=build/dynref DYNREF_BENCH_OUT=out/bench
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${DYNREF_BENCH_OUT:-out/bench}
REPORT=${1:-$OUT/realtime_bench.md}
FRAMES=${FRAMES:-600}
LONG=${LONG:-900}
PRESETS=(${PRESETS:-walking_xyz walking_halfsphere static_xyz})
METHODS=(${METHODS:-orb sgdo})
DYNREF=${DYNREF:-build/dynref}
[ -x "$DYNREF" ] || bash scripts/build.sh
command -v /usr/bin/time > /dev/null || { echo "bench-realtime: needs GNU time (apt-get install time)" >&2; exit 2; }
mkdir -p "$OUT/runs"

sequence() {  # preset frames -> folder
  local seq="$OUT/seq/$1-$2-s1"
  [ -f "$seq/groundtruth.txt" ] || "$DYNREF" synth --preset "$1" --frames "$2" --seed 1 --detections yolo-like \
    --out "$seq" > /dev/null
  echo "$seq"
}

ROWS=()
run() {  # preset frames method
  local seq run
  seq=$(sequence "$1" "$2")
  run="$OUT/runs/realtime-$1-$2-$3"
  echo "bench-realtime: $3 on $1 ($2 frames)" >&2
  /usr/bin/time -v -o "$run.time" "$DYNREF" run --sequence "$seq" --out "$run" --method "$3" \
    --detections "$seq/detections/yolo-like" --trace off --no-progress > /dev/null
  "$DYNREF" eval --gt "$seq/groundtruth.txt" --est "$run/trajectory.txt" --json "$run/eval.json" > /dev/null
  ROWS+=("$1|$2|$3|$run")
}

for p in "${PRESETS[@]}"; do
  for m in "${METHODS[@]}"; do
    case "$p" in static_*) [ "$m" = orb ] || continue ;; esac  # static control: the backbone only
    run "$p" "$FRAMES" "$m"
  done
done
[ "$LONG" -gt 0 ] && for m in "${METHODS[@]}"; do run walking_xyz "$LONG" "$m"; done

python3 - "$REPORT" "$("$DYNREF" version)" "${ROWS[@]}" <<'PY'
import json, os, re, sys
report, version, rows = sys.argv[1], sys.argv[2], sys.argv[3:]
lines = [
    "# Real time on one core (issue 18)", "",
    f"Written by `scripts/bench-realtime.sh` with {version}. `dynref run --trace off`, one thread, "
    "640x480, synthetic seed 1, yolo-like detections. ms = thread CPU ms per frame (run.json `timing`; "
    "`slam` = everything but image loading). `dense` = the `sgdo.densemap` stage (part of local mapping). "
    "head / tail = mean slam ms over the first / last 100 frames. Peak RSS from GNU time. ATE RMSE over the "
    "tracked frames (SE(3) alignment).", "",
    "| preset | frames | method | slam ms | tracking | local mapping | ba | dense | head | tail | tail/head | keyframes | dense map points | peak RSS GiB | ATE m | tracked |",
    "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
]
for row in rows:
    preset, frames, method, run = row.split("|")
    j = json.load(open(os.path.join(run, "run.json")))
    t = j["timing"]
    ms = lambda k, f="mean_ms_per_frame": t[k][f]
    dense = j.get("timing_stages", {}).get("sgdo.densemap")
    rss = float(re.search(r"Maximum resident set size \(kbytes\): (\d+)", open(run + ".time").read()).group(1)) / 2**20
    points = "-"
    ply = os.path.join(run, "dense_map.ply")
    if os.path.exists(ply):
        head = open(ply, "rb").read(400).decode("latin1")
        points = re.search(r"element vertex (\d+)", head).group(1)
    ev = json.load(open(os.path.join(run, "eval.json")))
    ate = ev["ate"]["stats"]["rmse"]
    lines.append(
        f"| {preset} | {frames} | {method} | {ms('slam'):.1f} | {ms('tracking'):.1f} | {ms('local_mapping'):.1f} | "
        f"{ms('ba'):.1f} | {'-' if dense is None else f'{dense:.1f}'} | {ms('slam', 'head_mean_ms_per_frame'):.1f} | "
        f"{ms('slam', 'tail_mean_ms_per_frame'):.1f} | {ms('slam', 'tail_mean_ms_per_frame') / ms('slam', 'head_mean_ms_per_frame'):.2f} | "
        f"{j['keyframes_created']} | {points} | {rss:.2f} | {ate:.4f} | {j['frames_tracked']}/{j['frames_processed']} |")
os.makedirs(os.path.dirname(os.path.abspath(report)), exist_ok=True)
tmp = report + ".tmp"
open(tmp, "w").write("\n".join(lines) + "\n")
os.replace(tmp, report)
print("\n".join(lines))
PY
