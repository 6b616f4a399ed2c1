#!/usr/bin/env bash
# Issue 34 measurements (reports/loop_closing.md): orb on the loop presets with and without loop
# closing, and MGD on the walking analogues with relocalisation recent | bow. One thread each.
# Usage: bash scripts/bench-loop.sh [WORK_DIR]   (env: SEEDS="1 2 3", LOOP_FRAMES=720, WALK_FRAMES=300,
#        PARTS="loop mgd")
set -euo pipefail
cd "$(dirname "$0")/.."
WORK=${1:-out/bench-loop}
DYNREF=${DYNREF:-build/dynref}
SEEDS=${SEEDS:-"1 2 3"}
LOOP_FRAMES=${LOOP_FRAMES:-720}
WALK_FRAMES=${WALK_FRAMES:-300}
PARTS=${PARTS:-"loop mgd"}
mkdir -p "$WORK/seq" "$WORK/runs"
seq_of() {  # preset seed frames -> folder (synthesised once, with yolo-like detections)
  local d="$WORK/seq/$1-$3-s$2"
  [ -f "$d/groundtruth.txt" ] || "$DYNREF" synth --preset "$1" --seed "$2" --frames "$3" --detections yolo-like --out "$d" > /dev/null
  echo "$d"
}
ate() { "$DYNREF" eval --gt "$1/groundtruth.txt" --est "$2/trajectory.txt" 2>/dev/null | awk '$1 == "ate" {print $3, $4; exit}'; }
if [[ " $PARTS " == *" loop "* ]]; then
  for preset in loop_static loop_walking; do
    for s in $SEEDS; do
      seq=$(seq_of "$preset" "$s" "$LOOP_FRAMES")
      for lc in false true; do
        run="$WORK/runs/$preset-s$s-loop_$lc"
        [ -f "$run/run.json" ] || "$DYNREF" run --method orb --sequence "$seq" --out "$run" --trace frames --no-progress \
          --set backbone.loop_closing=$lc > /dev/null || true
        echo "$preset s$s loop_closing=$lc $(ate "$seq" "$run")"
      done
    done
  done
fi
if [[ " $PARTS " == *" mgd "* ]]; then
  for preset in walking_xyz walking_static walking_rpy walking_halfsphere; do
    for s in $SEEDS; do
      seq=$(seq_of "$preset" "$s" "$WALK_FRAMES")
      for rl in recent bow; do
        run="$WORK/runs/mgd-$preset-s$s-reloc_$rl"
        [ -f "$run/run.json" ] || "$DYNREF" run --method mgd --sequence "$seq" --out "$run" --trace frames --no-progress \
          --detections "$seq/detections/yolo-like" --set backbone.relocalisation=$rl > /dev/null || true
        echo "mgd $preset s$s relocalisation=$rl $(ate "$seq" "$run")"
      done
    done
  done
fi
