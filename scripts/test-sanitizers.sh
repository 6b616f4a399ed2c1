#!/usr/bin/env bash
# Builds the test suite with AddressSanitizer + UndefinedBehaviorSanitizer in build-asan/ and runs
# the unit tests and goldens under it (issue 20). Called by .ci/run after scripts/test.sh
# (the build's cost was cut two ways, each measured and explained below: UBSan's two costliest
# checks off, test files at -O0).
# Only the unit tests and the goldens are registered
# (DYNREF_TEST_SPEC="~[cli]~[e2e]~[slow],[golden]"): the tests that run build/dynref carry [cli]
# (scripts/cli-test-tags.py keeps that true), whole-method runs and whole-sequence syntheses inside
# a test process [e2e], long ones [slow]; they exercise the code paths the unit tests and goldens
# already cover and run in the normal build.
set -euo pipefail
cd "$(dirname "$0")/.."
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# -O1 without debug info: the sanitizers need no -O2, and debug info doubles the compile time (CI
# budget); set DYNREF_ASAN_DEBUG=1 for line numbers in reports.
opt="-O1 -g0"
# UBSan without its `alignment` and `null` checks: those two double the compile time of every file
# (measured on ref/geometry/fundamental.cpp: 42.7 s with, 19.8 s without; plain -O2 16.1 s). A null
# dereference still stops the run (ASan's SEGV report with its stack); misaligned access needs a
# typed cast of a byte buffer, which ref/ never does (bytes are copied with memcpy).
SAN="-fsanitize=address,undefined -fno-sanitize=alignment,null"
[ "${DYNREF_ASAN_DEBUG:-0}" = 1 ] && opt="-O1 -g"
# The test files themselves at -O0 (DYNREF_TEST_COMPILE_OPTIONS, tests/CMakeLists.txt): under
# -fsanitize a Catch2 test file compiles 2.2x slower at -O1 than at -O0, and the code the
# sanitizers are here for (ref/) keeps -O1. The test files keep ASan but not UBSan (the undefined
# behaviour hunted is ref/'s: tests/optim's unity file 17.7 CPU-s with both, 14.4 with ASan only).
# The report writers and the command line (dynref_reproduce, the dynref executable) are built
# without sanitizers (ref/CMakeLists.txt DYNREF_UNSANITIZED_TARGETS): the unit tests and goldens
# run little of them (the [cli] tests that do run in the normal build), and instrumented they were
# a quarter of this build's compile time (reproduce's larger unity file 45.7 CPU-s, 22.2 without).
# Both measured at stop 46 on this machine. Ninja on a fresh folder (scripts/build.sh says why).
gen=()
[ -f build-asan/CMakeCache.txt ] || ! command -v ninja > /dev/null || gen=(-G Ninja)
# --target dynref_tests: the test programs, the fuzz driver and build-asan/dynref (the goldens run
# its `diff` and `trace verify`), not the benchmarks.
cmake -S . -B build-asan "${gen[@]}" -DCMAKE_BUILD_TYPE=None -DDYNREF_TEST_COMPILE_OPTIONS="-O0 -fno-sanitize=undefined" \
  -DDYNREF_UNSANITIZED_TARGETS="dynref_reproduce;dynref" \
  -DDYNREF_TEST_SPEC="~[cli]~[e2e]~[slow],[golden]" -DCMAKE_UNITY_BUILD=ON \
  -DCMAKE_CXX_FLAGS="$opt $SAN -fno-omit-frame-pointer -fno-sanitize-recover=undefined" \
  -DCMAKE_EXE_LINKER_FLAGS="$SAN" > build-asan.configure.log 2>&1 || { cat build-asan.configure.log; exit 1; }
cmake --build build-asan -j "$(nproc)" --target dynref_tests
cd build-asan
# -LE cli: the add_test entries that run dynref (the config fuzzer smoke) carry the CTest label cli.
ctest --output-on-failure -j "$(nproc)" -LE cli
