#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-2.0-or-later
# mbsc's accelerations of the real robots against DART's (docs/benchmarks.md, "Robots
# from URDF"): each robot is imported, generated with --state minimal and compiled with
# bench/urdf/dart_check.cpp, which compares the two at 100 random states and torques.
# Both read a copy without meshes, <mimic> and <dynamics> (bench/urdf/strip_for_peer.py
# says why; mbsc's mimic rows and damping are checked by tests/numeric/urdf_import_test.cpp
# against an independent recursion instead).
#
# Usage: bash bench/urdf/run_dart_check.sh [ROBOTS_DIR]   (default ../shared/robots)
# Needs: libdart-dev libdart-utils-urdf-dev (Debian), a built mbsc in build/.
set -euo pipefail
cd "$(dirname "$0")/../.."
robots=${1:-../shared/robots}
[ -d "$robots" ] || { echo "no robots folder at $robots"; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
status=0
for spec in "ur5_robot fixed" "panda fixed" "solo12 floating" "talos_full_v2 floating"; do
  set -- $spec
  name=$1 base=$2
  /usr/bin/python3 bench/urdf/strip_for_peer.py "$robots/$name.urdf" "$work/$name.urdf"
  flags=()
  [ "$base" = floating ] && flags=(--floating-base)
  ./build/mbsc import "$work/$name.urdf" -o "$work/$name.mbs" "${flags[@]}" 2>/dev/null
  /usr/bin/time -f "$name: mbsc generate %e s, %M KiB" \
    ./build/mbsc generate "$work/$name.mbs" -o "$work/gen" --state minimal --outputs rhs --name "$name" --force --quiet
  g++ -O2 -std=c++17 -w -I"$work/gen" -I/usr/include/eigen3 -DMBSC_MODEL_HEADER="\"$name/$name.hpp\"" -DMBSC_NS="$name" \
    bench/urdf/dart_check.cpp "$work/gen/$name/$name.cpp" -o "$work/check_$name" \
    -ldart-utils-urdf -ldart-utils -ldart -lurdfdom_model -lboost_system
  "$work/check_$name" "$work/$name.urdf" "$base" 100 2>/dev/null || status=1
done
exit $status
