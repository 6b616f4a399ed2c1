#!/usr/bin/env bash
# Trace cost (issue 32): CPU of `dynref run --trace full` against `--trace off` for every method on
# one synthetic sequence, the bytes per frame of the full trace, and what `dynref trace verify`
# costs and says. CPU = user + sys of the whole process (children's rusage), so it includes
# building the records, encoding, checksums and writing. Ratios are measured in one run, side
# by side, which is what holds on a noisy machine. Writes reports/trace_overhead.md.
#
#   bash scripts/bench-trace.sh [PRESET] [FRAMES]      (default walking_xyz 300)
#   METHODS="orb mgd ..." SEED=1 DYNREF=build/dynref DYNREF_BENCH_OUT=out/bench REPORT=reports/trace_overhead.md
set -euo pipefail
cd "$(dirname "$0")/.."
PRESET=${1:-walking_xyz}
FRAMES=${2:-300}
SEED=${SEED:-1}
METHODS=(${METHODS:-orb mgd-nd mgd sgdo blur epi epi_ALL semantic})
OUT=${DYNREF_BENCH_OUT:-out/bench}
DYNREF=${DYNREF:-build/dynref}
REPORT=${REPORT:-reports/trace_overhead.md}
[ -x "$DYNREF" ] || bash scripts/build.sh
seq="$OUT/seq/$PRESET-$FRAMES-s$SEED"
[ -f "$seq/groundtruth.txt" ] || "$DYNREF" synth --preset "$PRESET" --frames "$FRAMES" --seed "$SEED" \
  --detections yolo-like --out "$seq" > /dev/null
# cpu_seconds CMD...: runs CMD, prints its user+sys CPU seconds (stdout of CMD discarded).
cpu_seconds() {
  python3 -c '
import resource, subprocess, sys
r = subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL)
u = resource.getrusage(resource.RUSAGE_CHILDREN)
print(f"{u.ru_utime + u.ru_stime:.3f} {r.returncode}")' "$@"
}
rows=()
for m in "${METHODS[@]}"; do
  declare -A cpu=()
  for level in off full; do
    run="$OUT/runs/trace-$PRESET-$m-$level"
    read -r c rc < <(cpu_seconds "$DYNREF" run --sequence "$seq" --out "$run" --method "$m" \
      --detections "$seq/detections/yolo-like" --trace "$level" --no-progress)
    [ "$rc" = 0 ] || { echo "bench-trace: $m --trace $level failed (exit $rc)" >&2; exit 1; }
    cpu[$level]=$c
    echo "bench-trace: $m --trace $level: ${c} s CPU" >&2
  done
  full="$OUT/runs/trace-$PRESET-$m-full"
  cmp -s "$full/trajectory.txt" "$OUT/runs/trace-$PRESET-$m-off/trajectory.txt" && same=identical || same=DIFFERS
  bytes=$(stat -c %s "$full/trace.dtr")
  read -r vc vrc < <(cpu_seconds "$DYNREF" trace verify "$full")
  total=$("$DYNREF" trace verify "$full" | awk -F, '$1=="total"{print $2" verified, "$3" mismatched, "$4" unverifiable"}' || true)
  rows+=("$(python3 -c '
import sys
m, off, full, bytes_, frames, same, vc, vrc, total = sys.argv[1:]
off, full, bytes_, frames = float(off), float(full), int(bytes_), int(frames)
print(f"| {m} | {1000*off/frames:.1f} | {1000*full/frames:.1f} | {full/off:.2f} | {bytes_/frames/1024:.0f} | "
      f"{bytes_/2**20:.1f} | {same} | {vc} | {total} (exit {vrc}) |")' "$m" "${cpu[off]}" "${cpu[full]}" "$bytes" "$FRAMES" "$same" "$vc" "$vrc" "$total")")
done
commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)
git diff --quiet HEAD 2>/dev/null || commit="$commit+dirty"
tmp="$REPORT.tmp.$$"
{
  echo "# Trace cost: --trace full against --trace off (issue 32)"
  echo
  echo "Made by \`bash scripts/bench-trace.sh $PRESET $FRAMES\` at commit $commit on $(nproc) cores"
  echo "($(date -u +%Y-%m-%d)), sequence \`$PRESET\` seed $SEED, $FRAMES frames, yolo-like detections, one thread."
  echo "CPU is user + sys of the whole \`dynref run\` process (loading, every stage, the trace writer)"
  echo "per frame; the ratio is full / off measured in the same script run. The target is <= 1.3x."
  echo "\`verify\` is the CPU of \`dynref trace verify\` on the full trace and its verdict."
  echo
  echo "| method | off CPU ms/frame | full CPU ms/frame | full / off | KiB / frame | trace MiB | trajectory off vs full | verify CPU s | verify |"
  echo "|---|---|---|---|---|---|---|---|---|"
  for r in "${rows[@]}"; do echo "$r"; done
} > "$tmp"
mv "$tmp" "$REPORT"
cat "$REPORT"
