#!/usr/bin/env bash
# Configures and builds dynref into build/ (Release, -O2, -ffp-contract=off). Executable: build/dynref.
#   bash scripts/build.sh            everything (executable, tests, benchmarks)
#   bash scripts/build.sh dynref     only the executable (the main job)
set -euo pipefail
cd "$(dirname "$0")/.."
# Ninja on a fresh folder: it compiles a room's files while the rooms below it are still being
# archived (Make waits for each library), which keeps both cores busy on the long room chain.
# An existing folder keeps the generator it was made with.
gen=()
[ -f build/CMakeCache.txt ] || ! command -v ninja > /dev/null || gen=(-G Ninja)
# Unity build: a room's .cpp files compiled 8 at a time as one unit, so Eigen, OpenCV, Ceres and
# Catch2 headers are parsed once per unit instead of once per file (CI budget; measured in the
# commit that made it). Names in anonymous namespaces are unique per room for this (CONTRIBUTING).
# Test code (not ref/) at -O1: a unity test file compiles in 15.4 CPU-s instead of 20.9 at -O2
# (tests/optim, measured), and the code under test keeps -O2 (CI budget). -O0 is slower to compile.
cmake -S . -B build "${gen[@]}" -DCMAKE_BUILD_TYPE=Release -DCMAKE_UNITY_BUILD=ON \
  -DDYNREF_TEST_COMPILE_OPTIONS=-O1 > build.configure.log 2>&1 || { cat build.configure.log; exit 1; }
if [ $# -gt 0 ]; then
  cmake --build build -j "$(nproc)" --target "$@"
else
  cmake --build build -j "$(nproc)"
fi
