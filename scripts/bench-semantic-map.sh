#!/usr/bin/env bash
# Semantic mapping (seed 002) growth benchmark (issue 16): does the cost of mapping stay flat per
# keyframe as a sequence grows? Runs `dynref run --method semantic --trace frames` on synthetic
# walking_xyz of each length given (default 300 and 900 frames) and prints, per length:
# keyframes, CPU ms per keyframe of the map module (run.json timing_stages: keyframe clouds and
# map updates) and of all local mapping (run.json timing: + local BA, whose cost follows the
# covisible map, not the sequence length), peak resident memory and its growth per keyframe, raw map points
# per keyframe, and the wall time of the whole run including the end-of-run registration, SOR,
# voxel grid, octree and grid. Writes the table to $OUT/semantic_map_growth.md.
#
#   bash scripts/bench-semantic-map.sh [FRAMES ...]      (DYNREF_BENCH_OUT, default out/bench)
#
# Memory: the keyframe clouds are kept until the end of the run (they are registered with the
# FINAL keyframe poses, spec 002 step 8), so memory grows linearly with keyframes by design; flat
# means a constant increment per keyframe. Timings are not results and are never tested.
set -euo pipefail
cd "$(dirname "$0")/.."
LENGTHS=("$@")
[ ${#LENGTHS[@]} -eq 0 ] && LENGTHS=(300 900)
OUT=${DYNREF_BENCH_OUT:-out/bench}
DYNREF=${DYNREF:-build/dynref}
[ -x "$DYNREF" ] || bash scripts/build.sh
[ -x /usr/bin/time ] || { echo "bench-semantic-map: needs /usr/bin/time (apt-get install time)" >&2; exit 2; }
mkdir -p "$OUT"
rows=""
for n in "${LENGTHS[@]}"; do
  seq="$OUT/seq/walking_xyz-$n"
  [ -f "$seq/groundtruth.txt" ] || "$DYNREF" synth --preset walking_xyz --frames "$n" --seed 1 \
      --detections yolo-like --out "$seq" > /dev/null
  run="$OUT/semantic-$n"
  echo "bench-semantic-map: $n frames" >&2
  /usr/bin/time -f "%M %e" -o "$OUT/time-$n.txt" "$DYNREF" run --method semantic --sequence "$seq" \
      --out "$run" --detections "$seq/detections/yolo-like" --trace frames --no-progress > /dev/null
  read -r rss_kb wall_s < "$OUT/time-$n.txt"
  rows+=$(python3 - "$run/run.json" "$rss_kb" "$wall_s" "$n" <<'PY'
import json, re, sys
run, rss_kb, wall, n = json.load(open(sys.argv[1])), float(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4])
kept = run["keyframes"]
kf = run["keyframes_created"]  # the map module ran once per inserted keyframe, culled ones included
frames = run["frames_processed"]
lm = run["timing"]["local_mapping"]["mean_ms_per_frame"] * frames / kf
mm = run["timing_stages"]["semantic.map"] * frames / kf
raw = next(o for o in run["outputs"] if o["path"].endswith("_raw.pcd"))
pts = int(re.search(r"(\d+) points", raw["what"]).group(1))
print(f"| {n} | {kf} | {kept} | {mm:.1f} | {lm:.1f} | {rss_kb/1024:.0f} | {rss_kb/1024/kept:.2f} | {pts/kept:.0f} | {wall:.0f} |")
PY
)$'\n'
done
table="| frames | keyframes inserted | keyframes kept | semantic.map ms / inserted keyframe | local mapping ms / inserted keyframe | peak RSS MB | RSS MB / kept keyframe | raw points / kept keyframe | wall s |
|---|---|---|---|---|---|---|---|---|
$rows"
printf '%s' "$table" | tee "$OUT/semantic_map_growth.md"
