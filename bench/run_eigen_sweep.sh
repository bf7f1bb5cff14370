#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-2.0-or-later
#
# Timing of the eigenvalue sweep of `mbsc eig` (bench/eigen_sweep_driver.cpp):
#   bash bench/run_eigen_sweep.sh [BUILD]     (from anywhere; BUILD defaults to build)
# Needs a Release build of mbsc_core in BUILD (cmake --build BUILD --target mbsc_core).
# Prints a markdown table; scratch in bench/work/eigen_sweep (ignored).
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$ROOT"
BUILD=${1:-build}
WORK=bench/work/eigen_sweep
mkdir -p "$WORK"
[ -f "$BUILD/libmbsc_core.a" ] || { echo "no $BUILD/libmbsc_core.a: build mbsc_core first" >&2; exit 1; }
${CXX:-g++} -std=c++17 -O2 -DNDEBUG -Iinclude -I/usr/include/eigen3 bench/eigen_sweep_driver.cpp \
  "$BUILD/libmbsc_core.a" -lfmt -o "$WORK/eigen_sweep_driver"
"$WORK/eigen_sweep_driver"
