#!/usr/bin/env bash
# reports/mgd_order.md (issue 38, defect 1): MGD's probability update before the local-map search
# (after_local_map_search: false, dynref before issue 38) and after it (the paper's order, the
# default) on the four walking analogues, seeds 1-3: tracked frames and the lost ones, ATE, the
# share of updated features with a computable P_pro and the share inheriting from a map point
# (trace COUNT records of mgd.probability). One run at a time, --trace frames.
#
#   bash scripts/bench-mgd-order.sh [WORK=out/bench-mgd-order]   (env: FRAMES=300, SEEDS="1 2 3", DYNREF)
set -euo pipefail
cd "$(dirname "$0")/.."
DYNREF=${DYNREF:-build/dynref}
WORK=${1:-out/bench-mgd-order}
FRAMES=${FRAMES:-300}
SEEDS=${SEEDS:-"1 2 3"}
mkdir -p "$WORK"
"$DYNREF" version
# lost frames (0-based index in rgb.txt) as ranges, P_pro and map-point shares from the trace counts
row() {  # seq before_run after_run
  python3 - "$@" "$DYNREF" <<'PY'
import subprocess, sys
seq, runs, dynref = sys.argv[1], sys.argv[2:4], sys.argv[4]
stamps = [round(float(l.split()[0]), 4) for l in open(seq + "/rgb.txt") if l.strip() and not l.startswith("#")]
def lost(run):
    have = {round(float(l.split()[0]), 4) for l in open(run + "/trajectory.txt") if l.strip() and not l.startswith("#")}
    idx = [i for i, s in enumerate(stamps) if s not in have]
    ranges, start = [], None
    for j, i in enumerate(idx):
        if start is None: start = i
        if j + 1 == len(idx) or idx[j + 1] != i + 1:
            ranges.append(str(start) if start == i else "%d-%d" % (start, i)); start = None
    return len(stamps) - len(idx), ", ".join(ranges)
def shares(run):
    out = subprocess.run([dynref, "trace", "dump", run, "--stage", "mgd.probability"], capture_output=True, text=True, check=True).stdout
    n = {}
    for line in out.splitlines()[1:]:
        f = line.split(",")
        if f[1] == "count": n[f[4]] = n.get(f[4], 0) + int(float(f[7]))
    upd = n.get("inherit_prev_frame", 0) + n.get("inherit_map_point", 0) + n.get("inherit_init", 0)
    return 100.0 * n.get("P_pro_computable", 0) / upd, 100.0 * n.get("inherit_map_point", 0) / upd
def ate(run):
    out = subprocess.run([dynref, "eval", "--gt", seq + "/groundtruth.txt", "--est", run + "/trajectory.txt"], capture_output=True, text=True).stdout
    for l in out.splitlines():
        f = l.split()
        if f[:3] == ["ate", "[m]", "rmse"]: return float(f[3]) * 1000
    return float("nan")
cells = []
for r in runs:
    t, l = lost(r)
    cells.append("%d (%s)" % (t, l) if l else "%d" % t)
a = [ate(r) for r in runs]
s = [shares(r) for r in runs]
print(" | ".join(cells + ["%.2f" % a[0], "%.2f" % a[1], "%.1f %%" % s[0][0], "%.1f %%" % s[1][0], "%.1f %%" % s[0][1], "%.1f %%" % s[1][1]]) + " |")
PY
}
echo "| sequence | seed | tracked, before (lost) | tracked, after (lost) | ATE before mm | ATE after mm | P_pro before | P_pro after | from map point before | after |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
for preset in walking_halfsphere walking_rpy walking_static walking_xyz; do
  for s in $SEEDS; do
    seq="$WORK/seq/$preset-s$s"
    [ -f "$seq/groundtruth.txt" ] || "$DYNREF" synth --preset "$preset" --frames "$FRAMES" --seed "$s" --detections yolo-like --out "$seq" > /dev/null
    for order in false true; do
      run="$WORK/runs/$preset-s$s-after_$order"
      [ -f "$run/run.json" ] || "$DYNREF" run --method mgd --sequence "$seq" --detections "$seq/detections/yolo-like" --out "$run" \
        --trace frames --no-progress --set mgd.probability.after_local_map_search=$order > /dev/null
    done
    echo "| $preset | $s | $(row "$seq" "$WORK/runs/$preset-s$s-after_false" "$WORK/runs/$preset-s$s-after_true")"
  done
done
