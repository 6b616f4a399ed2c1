#!/usr/bin/env bash
# Installs dependencies, builds, and runs the tests with CTest (the README's test command).
#   bash scripts/test.sh          every test but those tagged [slow] (CTest label slow): what CI runs
#   bash scripts/test.sh --all    every test, [slow] ones too (paper-table and workflow runs,
#                                 ablation-config verifications, the 30-frame viewer run)
set -euo pipefail
cd "$(dirname "$0")/.."
select=(-LE slow)
if [ "${1:-}" = --all ]; then select=(); elif [ $# -gt 0 ]; then echo "usage: scripts/test.sh [--all]" >&2; exit 2; fi
bash scripts/install-deps.sh --tests
bash scripts/build.sh
cd build
ctest --output-on-failure -j "$(nproc)" "${select[@]}"
