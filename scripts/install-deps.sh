#!/usr/bin/env bash
# Installs the Debian (bookworm) packages dynref needs. Run as root.
#   bash scripts/install-deps.sh          build and run (the main job, scripts/demo.sh)
#   bash scripts/install-deps.sh --tests  + what only the tests need (scripts/test.sh, CI)
# Idempotent: packages already present are skipped, so a warm machine pays nothing.
set -euo pipefail
PACKAGES=(
  build-essential cmake git pkg-config
  ninja-build                # faster parallel builds on few cores (scripts/build.sh)
  libeigen3-dev              # linear algebra, SE(3)
  libopencv-dev libopencv-contrib-dev  # images, ORB/FAST, LK, DNN (OpenCV 4.6)
  zlib1g-dev                 # dynref view: zlib literal (tests, size comparison; ref/view/packed.cpp)
  liblzma-dev                # dynref view: LZMA-compressed data files (ref/view/lzma_pack.cpp)
  libdeflate-dev             # the sequences' PNG frames decoded ~2-3x faster than zlib (ref/io/png_decode.h)
  libpng-dev libjpeg-dev     # png.h / jpeglib.h: the executable keeps the codecs' messages (ref/cli/main.cpp)
  libceres-dev               # pose-only optimisation and local BA
  libopenimageio-dev         # off-screen overlays, montages, plots
  catch2                     # tests (v2.13, catch2/catch.hpp); CMake configures the test tree too
  libyaml-cpp-dev            # method configs with per-parameter sources
  nlohmann-json3-dev         # run.json / eval --json
  libcli11-dev               # subcommands, --help, unknown flags are errors
  libnanoflann-dev           # k-d tree for SOR / radius queries in dense maps
  liboctomap-dev             # semantic octrees written as real .ot/.bt (seed 002; octovis, octomap_server)
)
# Only the tests (and users who scale out) need these: the main job installs none of them
# (snakemake alone pulls ~300 packages).
if [ "${1:-}" = "--tests" ]; then
  PACKAGES+=(
    snakemake                # workflow/Snakefile: the paper-table matrix on many cores or a Slurm cluster (issue 19)
    darknet                  # ships real test photos with people (person.jpg, kite.jpg)
    python3                  # tests: second, independent trace writer (ref/trace/dtr_from_jsonl.py)
    chromium                 # tests: the dynref view site loaded in headless Chromium (issue 36)
  )
fi
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}"
