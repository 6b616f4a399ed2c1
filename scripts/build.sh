#!/usr/bin/env bash
# Configures and builds dynref into build/ (Release, -O2, -ffp-contract=off). Executable: build/dynref.
#   bash scripts/build.sh            everything (executable, tests, benchmarks)
#   bash scripts/build.sh dynref     only the executable (the main job)
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release > build.configure.log 2>&1 || { cat build.configure.log; exit 1; }
if [ $# -gt 0 ]; then
  cmake --build build -j "$(nproc)" --target "$@"
else
  cmake --build build -j "$(nproc)"
fi
