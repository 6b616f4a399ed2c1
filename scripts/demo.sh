#!/usr/bin/env bash
# The main job on the embedded default (README command 1). Installs dependencies, builds
# build/dynref, then:
#   1. evaluates the bundled real trajectory pair (TUM fr2_desk, ORB-SLAM estimate) exactly as
#      TUM's evaluate_ate.py / evaluate_rpe.py do;
#   2. synthesizes a dynamic sequence (walking_xyz, seed 1, yolo-like masks), runs the orb
#      backbone and SGDO-SLAM with every ablation, evaluates ATE and rejected-feature precision/
#      recall against ground truth, renders an overlay montage, and writes the Markdown report.
# Everything lands in out/demo/ (override with DYNREF_DEMO_OUT, frames with DYNREF_DEMO_FRAMES).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
OUT=${DYNREF_DEMO_OUT:-out/demo}
FRAMES=${DYNREF_DEMO_FRAMES:-150}
mkdir -p "$OUT"
build/dynref eval --gt datasets/real/trajectories/fr2_desk_groundtruth.txt \
  --est datasets/real/trajectories/fr2_desk_ORB.txt --json "$OUT/eval_fr2_desk.json"
build/dynref reproduce sgdo-table6 --sequences walking_xyz --frames "$FRAMES" --seeds 1 \
  --detections yolo-like --sensitivity none --work "$OUT/work" --out "$OUT/report.md"
echo "demo: report $OUT/report.md, overlays and runs under $OUT/work"
