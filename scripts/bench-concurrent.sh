#!/usr/bin/env bash
# --variant concurrent against the oracle (issue 18): one oracle run and RUNS concurrent runs of
# METHOD on a synthetic seed-1 sequence with full traces, each concurrent run diffed against the
# oracle (`dynref diff --summary`) and evaluated against the ground truth. Writes a Markdown report.
#
#   bash scripts/bench-concurrent.sh [REPORT]   (default out/bench/concurrent_diff.md)
#   PRESET=walking_xyz FRAMES=300 METHOD=sgdo RUNS=2 DYNREF=build/dynref DYNREF_BENCH_OUT=out/bench
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${DYNREF_BENCH_OUT:-out/bench}
REPORT=${1:-$OUT/concurrent_diff.md}
PRESET=${PRESET:-walking_xyz}
FRAMES=${FRAMES:-300}
METHOD=${METHOD:-sgdo}
RUNS=${RUNS:-2}
DYNREF=${DYNREF:-build/dynref}
[ -x "$DYNREF" ] || bash scripts/build.sh
seq="$OUT/seq/$PRESET-$FRAMES-s1"
[ -f "$seq/groundtruth.txt" ] || "$DYNREF" synth --preset "$PRESET" --frames "$FRAMES" --seed 1 --detections yolo-like \
  --out "$seq" > /dev/null
run() {  # variant name
  local r="$OUT/runs/concurrent-$PRESET-$FRAMES-$METHOD-$2"
  echo "bench-concurrent: $1 ($2)" >&2
  "$DYNREF" run --sequence "$seq" --out "$r" --method "$METHOD" --detections "$seq/detections/yolo-like" \
    --trace full --variant "$1" --no-progress > /dev/null
  "$DYNREF" eval --gt "$seq/groundtruth.txt" --est "$r/trajectory.txt" --json "$r/eval.json" > /dev/null
  echo "$r"
}
oracle=$(run oracle oracle)
{
  echo "# --variant concurrent against the oracle (issue 18)"
  echo
  echo "Written by \`scripts/bench-concurrent.sh\` with $("$DYNREF" version): \`dynref run --method $METHOD --trace full\` on"
  echo "synthetic $PRESET ($FRAMES frames, seed 1, yolo-like detections), the oracle once and $RUNS concurrent runs;"
  echo "each concurrent run diffed against the oracle with \`dynref diff ORACLE RUN --summary\`."
  echo
  python3 - "$oracle" <<'PY'
import json, sys
r = sys.argv[1]
j, e = json.load(open(r + "/run.json")), json.load(open(r + "/eval.json"))
print(f"Oracle: {j['frames_tracked']}/{j['frames_processed']} frames tracked, {j['keyframes_created']} keyframes, "
      f"ATE RMSE {e['ate']['stats']['rmse']:.4f} m, slam {j['timing']['slam']['mean_ms_per_frame']:.1f} ms/frame (thread CPU).")
PY
  for i in $(seq 1 "$RUNS"); do
    c=$(run concurrent "concurrent$i")
    echo
    echo "## Concurrent run $i"
    echo
    python3 - "$c" <<'PY'
import json, sys
r = sys.argv[1]
j, e = json.load(open(r + "/run.json")), json.load(open(r + "/eval.json"))
m = j["timing"]["mapping_thread_per_keyframe"]
print(f"{j['frames_tracked']}/{j['frames_processed']} frames tracked, {j['keyframes_created']} keyframes, "
      f"ATE RMSE {e['ate']['stats']['rmse']:.4f} m, slam {j['timing']['slam']['mean_ms_per_frame']:.1f} ms/frame (wall), "
      f"mapping thread {m['mean_ms_per_frame']:.1f} ms per keyframe.")
PY
    echo
    echo '```'
    # Optimiser calls (localba#17, track.pose#2) summed per kind; per-field error rows of poses,
    # inputs and residual vectors left out (the summary covers them).
    "$DYNREF" diff "$oracle" "$c" --summary --max-report 3 | python3 -c '
import re, sys
calls, out = {}, []
for line in sys.stdin:
    m = re.match(r"  ([\w.]+)#\d+,(\d+),(\d+),(\d+),(\d+),(\d+)$", line)
    if m:
        if m.group(1) not in calls:
            calls[m.group(1)] = [0] * 5
            out.append(("calls", m.group(1)))
        calls[m.group(1)] = [a + int(b) for a, b in zip(calls[m.group(1)], m.groups()[1:])]
    elif not re.match(r"  (T_wc|in\.|start|end)", line):
        out.append(("line", line))
for kind, v in out:
    print("  " + v + "#*," + ",".join(map(str, calls[v])) if kind == "calls" else v, end="" if kind == "line" else "\n")
' || true
    echo '```'
  done
} > "$REPORT.tmp"
mv "$REPORT.tmp" "$REPORT"
cat "$REPORT"
