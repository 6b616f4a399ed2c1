#!/usr/bin/env bash
# The main job on the embedded default (README command 1): installs dependencies, builds
# build/dynref, and evaluates the bundled real trajectory pair (TUM fr2_desk, ORB-SLAM estimate)
# exactly as TUM's evaluate_ate.py / evaluate_rpe.py would.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
OUT=${DYNREF_DEMO_OUT:-out/demo}
mkdir -p "$OUT"
build/dynref eval --gt datasets/real/trajectories/fr2_desk_groundtruth.txt \
  --est datasets/real/trajectories/fr2_desk_ORB.txt --json "$OUT/eval_fr2_desk.json"
echo "demo: results in $OUT"
