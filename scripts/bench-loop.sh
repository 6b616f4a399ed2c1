#!/usr/bin/env bash
# Issue 34 measurements (reports/loop_closing.md): orb on the loop presets with and without loop
# closing, and MGD on the walking analogues with relocalisation recent | bow. One thread each.
# Usage: bash scripts/bench-loop.sh [WORK_DIR]   (env: SEEDS="1 2 3", LOOP_FRAMES=720, WALK_FRAMES=300,
#        PARTS="loop mgd", LOOP_PRESETS="loop_static loop_walking")
set -euo pipefail
cd "$(dirname "$0")/.."
WORK=${1:-out/bench-loop}
DYNREF=${DYNREF:-build/dynref}
SEEDS=${SEEDS:-"1 2 3"}
LOOP_FRAMES=${LOOP_FRAMES:-720}
WALK_FRAMES=${WALK_FRAMES:-300}
PARTS=${PARTS:-"loop mgd"}
LOOP_PRESETS=${LOOP_PRESETS:-"loop_static loop_walking"}
mkdir -p "$WORK/seq" "$WORK/runs"
seq_of() {  # preset seed frames -> folder (synthesised once, with yolo-like detections)
  local d="$WORK/seq/$1-$3-s$2"
  [ -f "$d/groundtruth.txt" ] || "$DYNREF" synth --preset "$1" --seed "$2" --frames "$3" --detections yolo-like --out "$d" > /dev/null
  echo "$d"
}
ate() { "$DYNREF" eval --gt "$1/groundtruth.txt" --est "$2/trajectory.txt" 2>/dev/null | awk '$1 == "ate" {print $3, $4; exit}'; }
# Frames where a loop closed (trace COUNT loop closed) and loop closing's cost (run.json loop_closing).
loop_info() {
  local closed cost
  closed=$("$DYNREF" trace dump "$1" --stage loop --entity closed 2>/dev/null | awk -F, 'NR > 1 {printf "%s ", $1}')
  cost=$(python3 -c 'import json, sys; j = json.load(open(sys.argv[1])).get("loop_closing")
print("" if j is None else "kf %d loops %d detect %.3f ms/frame %.2f ms/kf correct %.1f ms/loop globalBA %.1f ms/loop total %.3f ms/frame" % (
    j["keyframes_processed"], j["loops_closed"], j["detect_ms_per_frame"], j["detect_ms_per_keyframe"],
    j["correct_ms_per_loop"], j["global_ba_ms_per_loop"], j["total_ms_per_frame"]))' "$1/run.json" 2>/dev/null)
  echo "closed at: ${closed:--} $cost"
}
if [[ " $PARTS " == *" loop "* ]]; then
  # orb on both presets; on loop_walking also mgd (the method issue 34 names) with yolo-like detections.
  for preset in $LOOP_PRESETS; do
    methods=orb
    [ "$preset" = loop_walking ] && methods="orb mgd"
    for s in $SEEDS; do
      seq=$(seq_of "$preset" "$s" "$LOOP_FRAMES")
      for m in $methods; do
        det=()
        [ "$m" = orb ] || det=(--detections "$seq/detections/yolo-like")
        for lc in false true; do
          run="$WORK/runs/$m-$preset-s$s-loop_$lc"
          [ -f "$run/run.json" ] || "$DYNREF" run --method "$m" --sequence "$seq" --out "$run" --trace frames --no-progress \
            "${det[@]}" --set backbone.loop_closing=$lc > /dev/null || true
          echo "$m $preset s$s loop_closing=$lc $(ate "$seq" "$run") $(loop_info "$run")"
        done
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
