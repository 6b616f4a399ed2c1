#!/usr/bin/env bash
# Rebuilds models/vocab/dynref_orb_k10_l4.txt, the default vocabulary embedded in dynref
# (ref/place/README.md). Deterministic: the same dynref build writes the same bytes.
# Usage: bash models/vocab/make_default.sh [WORK_DIR]   (from the repository root, after a build)
set -euo pipefail
DYNREF=${DYNREF:-build/dynref}
WORK=${1:-/tmp/dynref-vocab}
mkdir -p "$WORK"
SEQS=()
for preset in walking_xyz walking_halfsphere sitting_rpy crowd static_xyz static_lowtexture; do
  for seed in 1 2; do
    out="$WORK/${preset}_s${seed}"
    [ -f "$out/rgb.txt" ] || "$DYNREF" synth --preset "$preset" --seed "$seed" --frames 60 --out "$out"
    SEQS+=(--sequence "$out")
  done
done
"$DYNREF" vocab train "${SEQS[@]}" --sequence datasets/real/tum_fr1_desk_9frames \
  --k 10 --levels 4 --seed 1 --every 2 --features 1000 --out models/vocab/dynref_orb_k10_l4.txt
