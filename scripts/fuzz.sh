#!/usr/bin/env bash
# Mutation-fuzzes every input reader (tests/fuzz, issue 20) with a fixed budget and writes the
# table to reports/fuzz.md. Not run by CI (CTest runs 3000 executions per target).
#   scripts/fuzz.sh [EXECUTIONS_PER_TARGET=1000000] [SEED=1]
# Uses build/ (scripts/build.sh) or the folder in $DYNREF_BUILD (e.g. build-asan for ASan+UBSan);
# $DYNREF_FUZZ_BIN names a ready driver binary instead (nothing is built; e.g. a copy, so that a
# rebuild during the ~25 min run cannot swap it).
set -euo pipefail
cd "$(dirname "$0")/.."
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
} > reports/fuzz.md.tmp
mv reports/fuzz.md.tmp reports/fuzz.md
cat reports/fuzz.md
rm -rf "$table"
[ "$status" -eq 0 ] && rm -rf "$work" || echo "inputs kept in $work" >&2
exit "$status"
