#!/usr/bin/env bash
# Mutation-fuzzes every input reader (tests/fuzz, issue 20) with a fixed budget and writes the
# table to reports/fuzz.md. Not run by CI (CTest runs 3000 executions per target).
#   scripts/fuzz.sh [EXECUTIONS_PER_TARGET=1000000] [SEED=1]
# Uses build/ (scripts/build.sh) or the folder in $DYNREF_BUILD (e.g. build-asan for ASan+UBSan);
# $DYNREF_FUZZ_BIN names a ready driver binary instead (nothing is built; e.g. a copy, so that a
# rebuild during the ~25 min run cannot swap it).
#
#   scripts/fuzz.sh configs [JOBS=2] [ROTATE=1] [BUDGET_S=0 (none)] [WIDTHS=160,320,640]
# The config-mutation target (issue 37, scripts/fuzz_configs.py): every parameter of every
# configs/*.yaml mutated (inf, -inf, nan, 1e308, -1, 0, 1.5x, 1e-308, text, lists, ...), each
# mutant run on a shared 2-frame synthetic sequence (the smallest of WIDTHS on which the unmutated
# config runs complete) with a 30 s limit; exit 0 with complete outputs or
# exit 2 naming file, line and key, else a finding. Writes the "Config mutation" section of
# reports/fuzz.md (the input-reader section above it is kept).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${1:-}" = "configs" ]; then
  jobs="${2:-2}"
  rotate="${3:-1}"
  budget="${4:-0}"
  widths="${5:-160,320,640}"
  build="${DYNREF_BUILD:-build}"
  bin="${DYNREF_BIN:-$build/dynref}"
  [ -n "${DYNREF_BIN:-}" ] || cmake --build "$build" --target dynref -j "$(nproc)" > /dev/null
  work="$(mktemp -d "$( [ -d /dev/shm ] && echo /dev/shm || echo /tmp )/dynref_fuzz_configs.XXXXXX")"
  table="$(mktemp)"
  status=0
  load_start="$(cut -d' ' -f1-3 /proc/loadavg)"
  python3 scripts/fuzz_configs.py --dynref "$bin" --work "$work" --jobs "$jobs" --rotate "$rotate" \
    --budget "$budget" --widths "$widths" --timeout 30 --table "$table" 2> "$work/stderr.log" || status=$?
  touch reports/fuzz.md
  {
    sed '/^## Config mutation/,$d' reports/fuzz.md
    echo "## Config mutation"
    echo
    dirty=""
    [ -z "$(git status --porcelain --untracked-files=no)" ] || dirty=" (dirty tree)"
    echo "\`scripts/fuzz.sh configs $jobs $rotate $budget $widths\` on $(date -u '+%Y-%m-%d %H:%M UTC'), commit $(git rev-parse --short HEAD)$dirty,"
    echo "binary \`$bin\`, $(nproc) cores (shared), load average at start $load_start, at end $(cut -d' ' -f1-3 /proc/loadavg)."
    echo "Each mutant changes one value of one configs/*.yaml line and runs \`dynref run --trace off\` on one"
    echo "shared 2-frame walking_xyz synthetic sequence (\`dynref synth --width W\`, ideal detections), W the smallest"
    echo "of $widths on which the unmutated config runs complete (column width)."
    echo "accepted = exit 0 with run.json complete and trajectory.txt; refused = exit 2 naming the mutated"
    echo "file, its line and the key (stage.key); not-initialised = exit 2 after a run that found too few points on"
    echo "the tiny sequence (a valid value; the run fails, publishes nothing); every other column is a finding."
    echo
    cat "$table"
    echo
    echo "Exit status of the driver: $status (0 = no finding)."
  } > reports/fuzz.md.tmp
  mv reports/fuzz.md.tmp reports/fuzz.md
  sed -n '/^## Config mutation/,$p' reports/fuzz.md
  rm -f "$table"
  [ "$status" -eq 0 ] && rm -rf "$work" || echo "mutants and logs kept in $work" >&2
  exit "$status"
fi
execs="${1:-1000000}"
seed="${2:-1}"
build="${DYNREF_BUILD:-build}"
fuzz_bin="${DYNREF_FUZZ_BIN:-$build/tests/fuzz/dynref_fuzz}"
[ -n "${DYNREF_FUZZ_BIN:-}" ] || cmake --build "$build" --target dynref_fuzz -j "$(nproc)" > /dev/null
work="$(mktemp -d "$( [ -d /dev/shm ] && echo /dev/shm || echo /tmp )/dynref_fuzz.XXXXXX")"
table="$(mktemp)"
status=0
"$fuzz_bin" all --execs "$execs" --seed "$seed" --work "$work" \
  > "$table" 2> "$work/stderr.log" || status=$?
{
  echo "# Fuzzing the input readers"
  echo
  echo "\`scripts/fuzz.sh $execs $seed\` on $(date -u +%Y-%m-%d), commit $(git rev-parse --short HEAD),"
  echo "binary \`$fuzz_bin\`, $(nproc) cores. Driver: \`tests/fuzz\` (deterministic blind mutation of"
  echo "valid seed files, one file per execution; not coverage guided). \"rejected\" = a clean"
  echo "InputError naming the file; \"unclear\" = any other exception (a finding); a crash stops the"
  echo "run and is named below (a finding)."
  echo
  cat "$table"
  echo
  echo "Exit status of the driver: $status (0 = no finding)."
  if grep -q "unclear x\|CRASH" "$work/stderr.log"; then
    echo
    echo "Findings:"
    echo '```'
    grep "unclear x\|CRASH" "$work/stderr.log"
    echo '```'
  fi
  # The config-mutation section (scripts/fuzz.sh configs) stays.
  [ -f reports/fuzz.md ] && { echo; sed -n '/^## Config mutation/,$p' reports/fuzz.md; }
} > reports/fuzz.md.tmp
mv reports/fuzz.md.tmp reports/fuzz.md
cat reports/fuzz.md
rm -rf "$table"
[ "$status" -eq 0 ] && rm -rf "$work" || echo "inputs kept in $work" >&2
exit "$status"
