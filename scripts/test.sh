#!/usr/bin/env bash
# Installs dependencies, builds, and runs every test with CTest (the README's test command).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh --tests
bash scripts/build.sh
cd build
ctest --output-on-failure -j "$(nproc)"
