#!/usr/bin/env bash
# Installs every Debian (bookworm) package dynref needs to build, test and run. Run as root.
# Idempotent: packages already present are skipped, so a warm machine pays nothing.
set -euo pipefail
PACKAGES=(
  build-essential cmake git pkg-config
  libeigen3-dev              # linear algebra, SE(3)
  libopencv-dev libopencv-contrib-dev  # images, ORB/FAST, LK, DNN (OpenCV 4.6)
  libceres-dev               # pose-only optimisation and local BA
  libopenimageio-dev         # off-screen overlays, montages, plots
  catch2                     # tests (v2.13, catch2/catch.hpp)
  snakemake                  # workflow/Snakefile: the paper-table matrix on many cores or a Slurm cluster (issue 19)
  libyaml-cpp-dev            # method configs with per-parameter sources
  nlohmann-json3-dev         # run.json / eval --json
  libcli11-dev               # subcommands, --help, unknown flags are errors
  libnanoflann-dev           # k-d tree for SOR / radius queries in dense maps
  liboctomap-dev             # semantic octrees written as real .ot/.bt (seed 002; octovis, octomap_server)
  darknet                    # ships real test photos with people (person.jpg, kite.jpg)
  python3                    # tests: second, independent trace writer (ref/trace/dtr_from_jsonl.py)
)
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
