#!/usr/bin/env bash
# ATE of several methods over synthetic presets and seeds (a result must hold over seeds, not one).
# Usage: scripts/seeds-matrix.sh [-f FRAMES] [-s "1 2 3"] [-p "walking_xyz walking_rpy"]
#                                [-m "orb sgdo_nodense mgd"] [-j JOBS] [-o REPORT.md] [-w WORKDIR]
# Runs are reused when their run.json exists (delete WORKDIR to start over); the report lists per
# preset and seed the ATE RMSE (m, SE(3)-aligned, tracked frames only), tracked/total frames and
# the cut vs orb, then mean +- std per preset and method. Deterministic: same arguments, same table.
set -euo pipefail
cd "$(dirname "$0")/.."
FRAMES=300; SEEDS="1 2 3"; PRESETS="walking_xyz walking_rpy walking_halfsphere walking_static"
METHODS="orb sgdo_nodense mgd"; JOBS=2; OUT=out/seeds/report.md; WORK=out/seeds/work
while getopts "f:s:p:m:j:o:w:" opt; do
  case $opt in f) FRAMES=$OPTARG;; s) SEEDS=$OPTARG;; p) PRESETS=$OPTARG;; m) METHODS=$OPTARG;;
    j) JOBS=$OPTARG;; o) OUT=$OPTARG;; w) WORK=$OPTARG;; *) exit 2;; esac
done
DYNREF=${DYNREF:-build/dynref}
[ -x "$DYNREF" ] || { echo "seeds-matrix: $DYNREF not built (bash scripts/build.sh)" >&2; exit 2; }
mkdir -p "$WORK" "$(dirname "$OUT")"
jobs_file=$(mktemp)
for p in $PRESETS; do for s in $SEEDS; do
  seq="$WORK/seq/${p}_s${s}_f${FRAMES}"
  [ -f "$seq/groundtruth.txt" ] || "$DYNREF" synth --preset "$p" --frames "$FRAMES" --seed "$s" \
      --detections yolo-like --out "$seq" > /dev/null
  for m in $METHODS; do
    run="$WORK/runs/${p}_s${s}_f${FRAMES}/$m"
    method=$(sed -n 's/^method: *//p' "configs/$m.yaml")
    [ -f "$run/run.json" ] || echo "$DYNREF run --method $method --config configs/$m.yaml --sequence $seq --out $run --detections $seq/detections/yolo-like --trace off --no-progress" >> "$jobs_file"
  done
done; done
n=$(wc -l < "$jobs_file")
echo "seeds-matrix: $n runs to do ($JOBS at a time)" >&2
xargs -P "$JOBS" -I{} sh -c '{} > /dev/null 2>&1 || echo "seeds-matrix: failed: {}" >&2' < "$jobs_file"
rm -f "$jobs_file"
python3 - "$WORK" "$FRAMES" "$SEEDS" "$PRESETS" "$METHODS" "$DYNREF" > "$OUT.tmp" <<'PY'
import json, math, subprocess, sys
work, frames, seeds, presets, methods, dynref = sys.argv[1], sys.argv[2], sys.argv[3].split(), sys.argv[4].split(), sys.argv[5].split(), sys.argv[6]
def ate(seq, run):
    out = subprocess.run([dynref, "eval", "--gt", f"{seq}/groundtruth.txt", "--est", f"{run}/trajectory.txt"],
                         capture_output=True, text=True).stdout
    for line in out.splitlines():
        if line.strip().startswith("ate [m]"):
            return float(line.split()[3])
    return float("nan")
print(f"# ATE over seeds: synthetic presets, {frames} frames, yolo-like masks\n")
print(f"Written by `scripts/seeds-matrix.sh -f {frames} -s \"{' '.join(seeds)}\" -p \"{' '.join(presets)}\" -m \"{' '.join(methods)}\"`. ATE RMSE in metres (SE(3) alignment, TUM evaluate_ate.py semantics) over the tracked frames; `tracked` = frames with a pose; cut = 1 - ATE/ATE(orb).\n")
print("| preset | seed | " + " | ".join(f"{m} ATE (tracked)" for m in methods) + " | " + " | ".join(f"{m} cut" for m in methods if m != "orb") + " |")
print("|---|---|" + "---|" * (2 * len(methods) - 1))
summary = {}
for p in presets:
    for s in seeds:
        seq = f"{work}/seq/{p}_s{s}_f{frames}"
        row, vals = [], {}
        for m in methods:
            run = f"{work}/runs/{p}_s{s}_f{frames}/{m}"
            try:
                j = json.load(open(f"{run}/run.json"))
                a = ate(seq, run); vals[m] = a
                row.append(f"{a:.4f} ({j['frames_tracked']}/{j['frames_processed']})")
                summary.setdefault((p, m), []).append((a, j["frames_tracked"] / max(1, j["frames_processed"])))
            except Exception:
                row.append("failed"); vals[m] = float("nan")
        cuts = [f"{100 * (1 - vals[m] / vals['orb']):.1f} %" if "orb" in vals and vals["orb"] > 0 else "-" for m in methods if m != "orb"]
        print(f"| {p} | {s} | " + " | ".join(row) + " | " + " | ".join(cuts) + " |")
print("\n## Mean +- std over seeds\n\n| preset | " + " | ".join(methods) + " |\n|---|" + "---|" * len(methods))
for p in presets:
    cells = []
    for m in methods:
        v = [a for a, _ in summary.get((p, m), []) if not math.isnan(a)]
        t = [t for _, t in summary.get((p, m), [])]
        if not v: cells.append("-"); continue
        mu = sum(v) / len(v); sd = math.sqrt(sum((x - mu) ** 2 for x in v) / (len(v) - 1)) if len(v) > 1 else 0.0
        cells.append(f"{mu:.4f} +- {sd:.4f} (tracked {100 * sum(t) / len(t):.0f} %)")
    print(f"| {p} | " + " | ".join(cells) + " |")
PY
mv "$OUT.tmp" "$OUT"
echo "seeds-matrix: wrote $OUT" >&2
