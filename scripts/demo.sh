#!/usr/bin/env bash
# The main job on the embedded default (README command 1). Installs what building and running
# need (not the test-only packages), builds build/dynref, then:
#   1. evaluates the bundled real trajectory pair (TUM fr2_desk, ORB-SLAM estimate) exactly as
#      TUM's evaluate_ate.py / evaluate_rpe.py do;
#   2. `dynref overview`: synthesizes a dynamic sequence (walking_xyz, seed 1, yolo-like masks),
#      runs orb and every method (sgdo, mgd, mgd-nd, blur, epi, semantic), evaluates them against
#      the ground truth and writes one page: ATE/RPE, tracked frames, ms/frame per module,
#      rejection precision/recall, map files, trajectories, the same frame's overlay per method;
#   3. `dynref view`: the run viewer of the mgd and sgdo runs (open out/demo/view/index.html in a
#      browser: frame slider, click a feature to see its probability history).
# Everything lands in out/demo/ (override with DYNREF_DEMO_OUT, frames with DYNREF_DEMO_FRAMES).
set -euo pipefail
cd "$(dirname "$0")/.."
start=$SECONDS
bash scripts/install-deps.sh
echo "demo: dependencies after $((SECONDS - start)) s" >&2
bash scripts/build.sh dynref
echo "demo: build after $((SECONDS - start)) s" >&2
OUT=${DYNREF_DEMO_OUT:-out/demo}
FRAMES=${DYNREF_DEMO_FRAMES:-150}
mkdir -p "$OUT"
run_start=$SECONDS
build/dynref eval --gt datasets/real/trajectories/fr2_desk_groundtruth.txt \
  --est datasets/real/trajectories/fr2_desk_ORB.txt --json "$OUT/eval_fr2_desk.json"
build/dynref overview --preset walking_xyz --frames "$FRAMES" --seed 1 --work "$OUT/work" \
  --out "$OUT/overview.md" --viewer view/index.html
# --threads 2: LZMA is most of dynref view's time; the site is the same for any thread count.
build/dynref view "$OUT/work/seed1/runs/mgd" "$OUT/work/seed1/runs/sgdo" --out "$OUT/view" --threads 2
echo "demo: overview $OUT/overview.md, viewer $OUT/view/index.html ($((SECONDS - run_start)) s after the build)"
