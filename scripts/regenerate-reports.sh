#!/usr/bin/env bash
# Every paper-table report of `dynref reproduce --list`, regenerated at one commit by the workflow
# (`snakemake all`, workflow/Snakefile: headline tables at the papers' lengths over seeds 1-5,
# ablations at 300 frames over seeds 1-3), then reports/README.md naming that commit, the matrix
# and the total CPU and wall time (over snakemake and every job it ran, kept by scripts/cpu_heartbeat.py), and the claims
# ledger reports/CLAIMS.md from the new reports. Issue 38.
#
#   bash scripts/regenerate-reports.sh              # -j 2, work folder dynref-work/tables
#   JOBS=8 WORK=/scratch/tables bash scripts/regenerate-reports.sh
#   SNAKEMAKE_ARGS="--profile workflow/profiles/slurm" bash ...   (CPU time is then the cluster's, not counted)
#
# Refuses a tree with uncommitted changes (a report must name a commit that holds its code); the
# work folder is kept, so a run stopped half way resumes where it stopped (snakemake's own rule).
# Across machine sessions (the whole regeneration outlasts one): scripts/regen-checkpoint.py save
# --stop before the session ends, and restore into an empty work folder at the same commit in the
# next one (workflow/README.md).
set -euo pipefail
cd "$(dirname "$0")/.."
JOBS=${JOBS:-2}
WORK=${WORK:-dynref-work/tables}
DYNREF=${DYNREF:-build/dynref}
if [ -n "$(git status --porcelain --untracked-files=no)" ]; then
  echo "regenerate-reports: the tree has uncommitted changes; commit first (a report names its commit)" >&2
  exit 2
fi
command -v snakemake > /dev/null || { echo "regenerate-reports: needs snakemake (bash scripts/install-deps.sh --tests)" >&2; exit 2; }
bash scripts/build.sh dynref
commit=$(git rev-parse --short=12 HEAD)
built=$("$DYNREF" version | grep -o '[0-9a-f]\{12\}[+a-z]*' | head -1)
[ "$built" = "$commit" ] || { echo "regenerate-reports: $DYNREF is $built, the tree is $commit" >&2; exit 2; }
mkdir -p "$WORK"
# One line per invocation (a regeneration stopped half way is resumed by running this again at the
# same commit; the README sums the lines): start, commit, jobs, wall s, user s, sys s, and
# "complete" or "stopped". scripts/cpu_heartbeat.py keeps an invocation's time in $beat every 30 s
# (its process tree from /proc), so one that is killed (a machine session ending) leaves its time,
# short of at most 30 s: the next invocation appends it as "stopped".
log="$WORK/regenerate-time.log"
beat="$WORK/regenerate-time.running"
if [ -f "$beat" ]; then cat "$beat" >> "$log" && rm -f "$beat"; fi
if [ -f "$log" ] && ! awk -v c="$commit" '$2 != c { exit 1 }' "$log"; then
  echo "regenerate-reports: $log holds a run at another commit; remove it (or use another WORK)" >&2
  exit 2
fi
start=$(date -u +%Y-%m-%dT%H:%MZ)
# The reports are written into $WORK/reports first (so a checkpoint carries them to the next
# session) and copied into reports/ when every one is written. --forcerun on every report
# (reproduce --list's third column) not yet written by this regeneration: each is rewritten at this
# commit, even when its runs are all current, and only once.
made="$WORK/reports"
mkdir -p "$made"
reports=""
for r in $("$DYNREF" reproduce --list | tail -n +2 | cut -f3); do
  [ -f "$made/$(basename "$r")" ] || reports="$reports $made/$(basename "$r")"
done
status=0
# The heartbeat's pid in $WORK/regenerate.pid: scripts/regen-checkpoint.py save --stop ends the
# regeneration through it (SIGTERM, passed on to snakemake) before a machine session ends.
python3 scripts/cpu_heartbeat.py --out "$beat" --prefix "$start $commit $JOBS" -- \
  snakemake -s workflow/Snakefile -j "$JOBS" --rerun-incomplete ${SNAKEMAKE_ARGS:-} \
  ${reports:+--forcerun $reports} \
  --config dynref="$DYNREF" work="$WORK" reports="$made" &
heartbeat=$!
echo "$heartbeat" > "$WORK/regenerate.pid"
wait "$heartbeat" || status=$?
rm -f "$WORK/regenerate.pid"
cat "$beat" >> "$log" && rm -f "$beat"
[ "$status" = 0 ] || { echo "regenerate-reports: snakemake failed ($status); its time is in $log" >&2; exit "$status"; }
cp -p "$made"/* reports/
# The claims ledger reads the reports just written (reports/CLAIMS.md, issue 38 item 5).
"$DYNREF" reproduce claims --out reports/CLAIMS.md --reports reports
python3 scripts/reports_readme.py --time-log "$log" --config workflow/config.yaml --out reports/README.md
echo "regenerate-reports: reports/README.md written (commit $commit)"
