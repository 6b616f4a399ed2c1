#!/usr/bin/env bash
# reports/real_people.md's measurements (issue 39), one command: NanoDet on the 10 real TUM
# walking_halfsphere frames against the 20 hand-drawn person boxes (no temporal help, gaps 1 and
# 2), the default detect folder, blur and mgd on it (paper thresholds calibrated and raw), and
# NanoDet against the synthetic people of walking_halfsphere (30 frames, seeds 1-3, gaps 0 and 2).
# Prints the tools' own outputs; the report's tables are read off them.
#
#   bash scripts/bench-real-people.sh [OUT=out/real-people]
#   DATA=../shared/data/tum_fr3_walking_halfsphere_10rgb DYNREF=build/dynref
# The real frames come without depth: each gets the constant 2 m depth PNG of
# datasets/real/tum_fr3_walking_halfsphere_3frames (as the report says).
set -euo pipefail
cd "$(dirname "$0")/.."
DATA=${DATA:-../shared/data/tum_fr3_walking_halfsphere_10rgb}
DYNREF=${DYNREF:-build/dynref}
OUT=${1:-out/real-people}
B=datasets/real/tum_fr3_walking_halfsphere_10rgb_person_boxes.txt
[ -f "$DATA/rgb.txt" ] || { echo "bench-real-people: $DATA/rgb.txt: no such file (set DATA)" >&2; exit 2; }
rm -rf "$OUT" && mkdir -p "$OUT/seq/depth"
cp -r "$DATA/rgb" "$DATA/rgb.txt" "$OUT/seq/"
depth=$(ls datasets/real/tum_fr3_walking_halfsphere_3frames/depth/*.png | head -1)
{
  echo "# depth maps"
  echo "# constant 2.0 m stand-in (16-bit, 10000 at 5000 units/m): no depth came with these frames"
  echo "# timestamp filename"
  awk '!/^#/ {print $1}' "$DATA/rgb.txt" | while read -r t; do
    cp "$depth" "$OUT/seq/depth/$t.png"
    echo "$t depth/$t.png"
  done
} > "$OUT/seq/depth.txt"
"$DYNREF" version
section() { printf '\n===== %s\n' "$*"; }
for gap in 0 1 2; do
  section "real frames: nanodet --no-masks --conf 0.05 --temporal-gap $gap, against the hand boxes"
  "$DYNREF" detect --source nanodet --no-masks --conf 0.05 --temporal-gap "$gap" --sequence "$OUT/seq" \
    --camera tum_fr3 --out "$OUT/det_gap$gap" > /dev/null
  "$DYNREF" info "$OUT/det_gap$gap" --boxes "$B"
done
section "real frames: the default detect folder (nanodet, score floor 0.3, selfie masks)"
"$DYNREF" detect --source nanodet --sequence "$OUT/seq" --camera tum_fr3 --out "$OUT/det_default" > /dev/null
"$DYNREF" info "$OUT/det_default" --boxes "$B"
for run in "blur" "blur blur.mask.threshold_scale=raw" "mgd" "mgd mgd.probability.threshold_scale=raw"; do
  set -- $run
  section "real frames: --method $1 ${2:+--set $2}"
  "$DYNREF" run --method "$1" ${2:+--set "$2"} --sequence "$OUT/seq" --camera tum_fr3 --detections "$OUT/det_default" \
    --out "$OUT/run_$1${2:+_raw}" --no-progress 2>&1 | grep -E "mask|boxes|warning" || true
done
for seed in 1 2 3; do
  s="$OUT/synth$seed"
  "$DYNREF" synth --preset walking_halfsphere --frames 30 --seed "$seed" --detections yolo-like --out "$s/seq" > /dev/null
  (echo "# dynref hand boxes 1"; for f in "$s"/seq/gt/*.txt; do
     awk -v st="$(basename "$f" .txt)" '!/^#/ && $3=="person" {print st, "person", "gt"$1, $5, $6, $7, $8}' "$f"
   done) > "$s/boxes.txt"
  for gap in 0 2; do
    section "synthetic walking_halfsphere seed $seed: nanodet --no-masks --conf 0.05 --temporal-gap $gap"
    "$DYNREF" detect --source nanodet --no-masks --conf 0.05 --temporal-gap "$gap" --sequence "$s/seq" \
      --out "$s/det_gap$gap" > /dev/null
    "$DYNREF" info "$s/det_gap$gap" --boxes "$s/boxes.txt"
  done
  section "synthetic walking_halfsphere seed $seed: yolo-like"
  "$DYNREF" info "$s/seq/detections/yolo-like" --boxes "$s/boxes.txt"
done
