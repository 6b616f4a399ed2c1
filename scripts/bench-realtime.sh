#!/usr/bin/env bash
# Real time on one core (issues 18, 35): `dynref run --trace off` of every config a reproduce table
# uses (and orb, the yardstick) on synthetic sequences with yolo-like detections: per-module ms
# per frame (thread CPU time from run.json: mean, p50, p95), each method stage's mean, slam ms as a
# ratio to orb on the same sequence in the same bench run (ratios hold on a shared, noisy machine),
# then one LONG-frame run per method for the head / tail means (first / last 100 frames) and the
# peak RSS (GNU time). Writes a Markdown report. Numbers, never a timed test.
#
#   bash scripts/bench-realtime.sh [REPORT]     (default reports/realtime_bench.md)
#   FRAMES=600 LONG=900 SEEDS="1 2 3" PRESETS="walking_xyz walking_halfsphere"
#   METHODS="orb sgdo ..." (default: every configs/*.yaml named in ref/reproduce, orb first)
#   DYNREF=build/dynref DYNREF_BENCH_OUT=out/bench
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${DYNREF_BENCH_OUT:-out/bench}
REPORT=${1:-reports/realtime_bench.md}
FRAMES=${FRAMES:-600}
LONG=${LONG:-900}
SEEDS=(${SEEDS:-1 2 3})
PRESETS=(${PRESETS:-walking_xyz walking_halfsphere})
DYNREF=${DYNREF:-build/dynref}
table_configs() {  # configs/<name>.yaml whose name a reproduce table quotes
  for f in configs/*.yaml; do
    local m; m=$(basename "$f" .yaml)
    [ "$m" = orb ] || ! grep -q "\"$m\"" ref/reproduce/*.cpp || echo "$m"
  done
}
METHODS=(orb $(echo "${METHODS:-$(table_configs)}" | tr ' ' '\n' | grep -vx orb || true))
[ -x "$DYNREF" ] || bash scripts/build.sh
command -v /usr/bin/time > /dev/null || { echo "bench-realtime: needs GNU time (apt-get install time)" >&2; exit 2; }
mkdir -p "$OUT/runs"

sequence() {  # preset frames seed -> folder
  local seq="$OUT/seq/$1-$2-s$3"
  [ -f "$seq/groundtruth.txt" ] || "$DYNREF" synth --preset "$1" --frames "$2" --seed "$3" --detections yolo-like \
    --out "$seq" > /dev/null
  echo "$seq"
}

ROWS=()
run() {  # kind preset frames seed method
  local seq out
  seq=$(sequence "$2" "$3" "$4")
  out="$OUT/runs/realtime-$2-$3-s$4-$5"
  echo "bench-realtime: $5 on $2 seed $4 ($3 frames)" >&2
  /usr/bin/time -v -o "$out.time" "$DYNREF" run --sequence "$seq" --out "$out" --method "$5" \
    --detections "$seq/detections/yolo-like" --trace off --no-progress > /dev/null
  "$DYNREF" eval --gt "$seq/groundtruth.txt" --est "$out/trajectory.txt" --json "$out/eval.json" > /dev/null
  ROWS+=("$1|$2|$3|$4|$5|$out")
}

for p in "${PRESETS[@]}"; do
  for s in "${SEEDS[@]}"; do
    for m in "${METHODS[@]}"; do run table "$p" "$FRAMES" "$s" "$m"; done
  done
done
if [ "$LONG" -gt 0 ]; then
  for m in "${METHODS[@]}"; do run long walking_xyz "$LONG" "${SEEDS[0]}" "$m"; done
fi

python3 scripts/realtime_report.py "$REPORT" "$("$DYNREF" version)" "$(nproc)" "$(uptime)" "${ROWS[@]}"
