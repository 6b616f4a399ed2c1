#!/usr/bin/env bash
# Effect of the virtual mapping clock (issue 18, ref/mapping/mapping_clock.h): every method and
# preset run with backbone.mapping_clock true (default) and false (local mapping idle at every
# frame, the earlier behaviour), over seeds. Prints a Markdown table (ATE RMSE, keyframes,
# SLAM ms/frame mean = thread CPU time without image loading) and writes it to
# reports/mapping_clock.md.
#   scripts/bench-mapping-clock.sh [-f FRAMES] [-s "1 2"] [-p "walking_xyz static_xyz"]
#                                  [-m "orb sgdo_nodense"] [-j JOBS] [-w WORKDIR]
set -euo pipefail
cd "$(dirname "$0")/.."
FRAMES=200; SEEDS="1 2"; PRESETS="walking_xyz static_xyz"; METHODS="orb sgdo_nodense"; JOBS=2
WORK=out/mapping_clock; OUT=reports/mapping_clock.md
while getopts "f:s:p:m:j:w:" opt; do
  case $opt in f) FRAMES=$OPTARG;; s) SEEDS=$OPTARG;; p) PRESETS=$OPTARG;; m) METHODS=$OPTARG;;
    j) JOBS=$OPTARG;; w) WORK=$OPTARG;; *) exit 2;; esac
done
DYNREF=${DYNREF:-build/dynref}
[ -x "$DYNREF" ] || { echo "bench-mapping-clock: $DYNREF not built (bash scripts/build.sh)" >&2; exit 2; }
mkdir -p "$WORK/configs"
for m in $METHODS; do  # the same config with the clock switched off
  sed 's/^backbone:$/backbone:\n  mapping_clock: {value: false, source: "bench: local mapping idle at every frame"}/' \
    "configs/$m.yaml" > "$WORK/configs/${m}_noclock.yaml"
  grep -q "mapping_clock: {value: false" "$WORK/configs/${m}_noclock.yaml" || { echo "no backbone: map in configs/$m.yaml" >&2; exit 2; }
  cp "configs/$m.yaml" "$WORK/configs/$m.yaml"
done
jobs_file=$(mktemp)
for p in $PRESETS; do for s in $SEEDS; do
  seq="$WORK/seq/${p}_s${s}_f${FRAMES}"
  [ -f "$seq/groundtruth.txt" ] || "$DYNREF" synth --preset "$p" --frames "$FRAMES" --seed "$s" \
      --detections yolo-like --out "$seq" > /dev/null
  for m in $METHODS; do for v in "$m" "${m}_noclock"; do
    run="$WORK/runs/${p}_s${s}_f${FRAMES}/$v"
    method=$(sed -n 's/^method: *//p' "configs/$m.yaml")
    [ -f "$run/run.json" ] || echo "$DYNREF run --method $method --config $WORK/configs/$v.yaml --sequence $seq --out $run --detections $seq/detections/yolo-like --trace off --no-progress" >> "$jobs_file"
  done; done
done; done
echo "bench-mapping-clock: $(wc -l < "$jobs_file") runs to do ($JOBS at a time)" >&2
xargs -P "$JOBS" -I{} sh -c '{} > /dev/null 2>&1 || echo "bench-mapping-clock: failed: {}" >&2' < "$jobs_file"
rm -f "$jobs_file"
python3 - "$WORK" "$FRAMES" "$SEEDS" "$PRESETS" "$METHODS" "$DYNREF" > "$OUT.tmp" <<'PY'
import json, subprocess, sys
work, frames, seeds, presets, methods, dynref = sys.argv[1], sys.argv[2], sys.argv[3].split(), sys.argv[4].split(), sys.argv[5].split(), sys.argv[6]
def ate(seq, run):
    out = subprocess.run([dynref, "eval", "--gt", f"{seq}/groundtruth.txt", "--est", f"{run}/trajectory.txt"],
                         capture_output=True, text=True).stdout
    for line in out.splitlines():
        if line.strip().startswith("ate [m]"):
            return float(line.split()[3])
    return float("nan")
print("# Virtual mapping clock: effect on keyframes, ATE and time\n")
print(f"`scripts/bench-mapping-clock.sh -f {frames} -s \"{' '.join(seeds)}\" -p \"{' '.join(presets)}\" -m \"{' '.join(methods)}\"`.")
print("clock = backbone `mapping_clock: true` (default since issue 18); idle = `false` (before).")
print("SLAM ms/frame = mean thread CPU time per frame without image loading (run.json `timing.slam`).\n")
print("| preset | seed | method | KF idle | KF clock | ATE idle (m) | ATE clock (m) | tracked idle | tracked clock | SLAM ms idle | SLAM ms clock | local BA ms idle | local BA ms clock |")
print("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
for p in presets:
    for s in seeds:
        seq = f"{work}/seq/{p}_s{s}_f{frames}"
        for m in methods:
            cells = {}
            for tag, v in (("idle", m + "_noclock"), ("clock", m)):
                run = f"{work}/runs/{p}_s{s}_f{frames}/{v}"
                r = json.load(open(f"{run}/run.json"))
                t = r["timing"]
                cells[tag] = (r["keyframes"], ate(seq, run), f"{r['frames_tracked']}/{r['frames_processed']}",
                              t["slam"]["mean_ms_per_frame"], t["ba"]["mean_ms_per_frame"])
            i, c = cells["idle"], cells["clock"]
            print(f"| {p} | {s} | {m} | {i[0]} | {c[0]} | {i[1]:.4f} | {c[1]:.4f} | {i[2]} | {c[2]} | {i[3]:.1f} | {c[3]:.1f} | {i[4]:.1f} | {c[4]:.1f} |")
PY
mv "$OUT.tmp" "$OUT"
cat "$OUT"
