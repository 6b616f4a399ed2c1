#!/usr/bin/env bash
# Lines and planes in the backbone (issue 13): ATE of `orb` vs `mgd-nd` on synthetic static
# sequences and the low-texture control, line / plane residuals per frame, and CPU ms per frame
# of line detection (FLD + LBD), plane segmentation (AHC), tracking (pose optimisation with the
# structure residuals) and local BA. Several seeds; trace level frames (counts only).
#
#   bash scripts/bench-structure.sh [SEEDS]        (default "1 2 3"; DYNREF_BENCH_OUT, default out/bench)
#   FRAMES=600 PRESETS="static_xyz static_rpy static_halfsphere static_lowtexture" VARIANTS=... DYNREF=...
#
# Variants: orb (ORB-SLAM2 defaults: depth read at the keypoint's pixel, start on > 500 keypoints
# with depth), orb-edge50 (orb with mgd-nd's two point settings: backbone depth_edge_rel=0.05, no
# depth for keypoints on depth steps, and min_init_points=50), mgd-nd (configs/mgd_nd.yaml, which
# sets those two), mgd-nd-orb2 (mgd-nd with ORB-SLAM2's point settings: depth_edge_rel=0,
# min_init_points=500), mgd-nd-nopar (e_par off, backbone line_parallel_term=false).
# Writes $OUT/structure_bench.md. Timings are this machine's CPU and never tested.
set -euo pipefail
cd "$(dirname "$0")/.."
SEEDS=(${1:-1 2 3})
FRAMES=${FRAMES:-600}
PRESETS=(${PRESETS:-static_xyz static_rpy static_halfsphere static_lowtexture})
VARIANTS=(${VARIANTS:-orb orb-edge50 mgd-nd mgd-nd-orb2 mgd-nd-nopar})
OUT=${DYNREF_BENCH_OUT:-out/bench}
DYNREF=${DYNREF:-build/dynref}
[ -x "$DYNREF" ] || bash scripts/build.sh
mkdir -p "$OUT"
rows=""
for preset in "${PRESETS[@]}"; do
  for seed in "${SEEDS[@]}"; do
    seq="$OUT/seq/$preset-$FRAMES-s$seed"
    [ -f "$seq/groundtruth.txt" ] || "$DYNREF" synth --preset "$preset" --frames "$FRAMES" --seed "$seed" --out "$seq" > /dev/null
    for variant in "${VARIANTS[@]}"; do
      method=$variant; sets=()
      case "$variant" in
        orb-edge50) method=orb; sets=(--set backbone.depth_edge_rel=0.05 --set backbone.min_init_points=50) ;;
        mgd-nd-orb2) method=mgd-nd; sets=(--set backbone.depth_edge_rel=0 --set backbone.min_init_points=500) ;;
        mgd-nd-nopar) method=mgd-nd; sets=(--set backbone.line_parallel_term=false) ;;
      esac
      run="$OUT/runs/$preset-$FRAMES-s$seed-$variant"
      echo "bench-structure: $preset seed $seed $variant" >&2
      "$DYNREF" run --method "$method" --sequence "$seq" --out "$run" --trace frames --no-progress "${sets[@]}" > /dev/null || true
      ate=$("$DYNREF" eval --est "$run/trajectory.txt" --gt "$seq/groundtruth.txt" 2>/dev/null | awk '/ate \[m\]/ {print $4}' || true)
      rows+=$(python3 - "$run" "$preset" "$seed" "$variant" "${ate:-nan}" "$DYNREF" <<'PY'
import json, subprocess, sys
run, preset, seed, variant, ate, dynref = sys.argv[1:]
j = json.load(open(run + "/run.json"))
t = j["timing"]
ms = lambda k: t[k]["mean_ms_per_frame"] if k in t else float("nan")
counts = {}
dump = subprocess.run([dynref, "trace", "dump", run + "/trace.dtr"], capture_output=True, text=True).stdout
for line in dump.splitlines():
    f = line.split(",")
    if len(f) > 7 and f[1] == "count" and f[2] == "structure.final":
        counts.setdefault(f[4], []).append(int(f[7]))
mean = lambda k: sum(counts[k]) / len(counts[k]) if counts.get(k) else 0.0
ate_cm = float(ate) * 100
print(f"| {preset} | {seed} | {variant} | {j['frames_tracked']}/{j['frames_processed']} | {ate_cm:.2f} | "
      f"{mean('line_residuals'):.0f} | {mean('plane_residuals'):.1f} | {j.get('map_lines', 0)} | {j.get('map_planes', 0)} | "
      f"{ms('lines'):.1f} | {ms('planes'):.1f} | {ms('tracking'):.1f} | {ms('ba'):.1f} | {ms('slam'):.1f} |")
PY
)$'\n'
    done
  done
done
table="| sequence | seed | variant | tracked | ATE cm | line residuals / frame | plane residuals / frame | map lines | map planes | lines ms | planes ms | tracking ms | local BA ms | slam ms |
|---|---|---|---|---|---|---|---|---|---|---|---|---|---|
$rows"
printf '%s' "$table" | tee "$OUT/structure_bench.md"
