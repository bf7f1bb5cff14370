#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-2.0-or-later
#
# Planar mechanisms (four-bar, slider-crank, Whitworth, 3RRR): rhs time and operation
# count of the complement and the multipliers formulation of each, measured in one run.
#   bash bench/run_planar.sh        (from the repository root; ~1 min on 2 cores)
# Writes bench/results/planar.md (and prints it). Scratch in bench/work/planar (ignored).
# Not yet here: the sympy.physics.mechanics and MuJoCo peers of issue 3.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$ROOT"
BUILD=build-bench
WORK=bench/work/planar
FLAGS="-std=c++17 -O2 -march=x86-64"
cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DMBSC_BUILD_TESTS=OFF -DMBSC_BUILD_APPS=OFF >/dev/null
cmake --build "$BUILD" -j2 --target mbsc >/dev/null
rm -rf "$WORK" && mkdir -p "$WORK" bench/results
out=bench/results/planar.md
{
  echo "| model | dof | complement ops | multipliers ops | complement ns | multipliers ns | multipliers / complement | max rel. diff |"
  echo "|---|---:|---:|---:|---:|---:|---:|---:|"
} > "$out"
run() {  # model, guesses, drivers
  local m=$1 guess=$2 drivers=$3
  "$BUILD/mbsc" generate "models/$m.mbs" -o "$WORK" >/dev/null
  "$BUILD/mbsc" generate "models/$m.mbs" -o "$WORK" --name "${m}_mult" --formulation multipliers >/dev/null
  local oc om dof
  oc=$(sed -n 's|^//   rhs: .*total \([0-9]*\)$|\1|p' "$WORK/$m/$m.cpp")
  om=$(sed -n 's|^//   rhs: .*total \([0-9]*\)$|\1|p' "$WORK/${m}_mult/${m}_mult.cpp")
  dof=$(sed -n 's|^inline constexpr int kNdof = \([0-9]*\);|\1|p' "$WORK/$m/$m.hpp")
  g++ $FLAGS -I include -I "$WORK" -DMODEL="$m" -DGUESS="$guess" -DDRIVERS="$drivers" bench/planar_driver.cpp \
    "$WORK/$m/$m.cpp" "$WORK/${m}_mult/${m}_mult.cpp" -o "$WORK/driver_$m"
  "$WORK/driver_$m" > "$WORK/$m.txt"
  local c mu d
  c=$(sed -n 's/^complement_ns=//p' "$WORK/$m.txt")
  mu=$(sed -n 's/^multipliers_ns=//p' "$WORK/$m.txt")
  d=$(sed -n 's/^max_rel_diff=//p' "$WORK/$m.txt")
  echo "| $m | $dof | $oc | $om | $c | $mu | $(awk -v a="$mu" -v b="$c" 'BEGIN { printf "%.2f", a / b }') | $d |" >> "$out"
}
run four_bar '{"crank.theta", 1.2}, {"coupler.theta", 0.4}, {"rocker.theta", 1.9}, {"crank.w", 2.0}' '"crank.theta", "crank.w"'
run slider_crank '{"crank.theta", 0.7}, {"rod.theta", -0.1}, {"slider.x", 0.4}, {"crank.w", 5.0}' '"crank.theta", "crank.w"'
run whitworth '{"crank.theta", 0.785398}, {"crank.w", 1.5708}, {"slider.x", 0.7}, {"slider.y", 0.8}, {"rocker.theta", 1.3}, {"rocker.x", 0.1}, {"rocker.y", 0.3}, {"rod.theta", 3.4}, {"rod.x", 0.5}, {"rod.y", 0.7}, {"crank.y", 0.3}' '"crank.theta", "crank.w"'
run three_rrr '{"HA.proximal.theta", 2.0}, {"HA.proximal.x", 3.0}, {"HB.proximal.theta", 3.8}, {"HB.proximal.x", -1.5}, {"HB.proximal.y", 2.598}, {"HC.proximal.theta", 6.0}, {"HC.proximal.x", -1.5}, {"HC.proximal.y", -2.598}, {"HA.distal.theta", 1.0}, {"HB.distal.theta", 3.1}, {"HC.distal.theta", 5.2}, {"platform.u", -1.5708}, {"platform.v", 0.7854}' '"platform.x", "platform.y", "platform.theta", "platform.u", "platform.v", "platform.w"'
{
  echo
  echo "$(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) cores, $(lscpu | sed -n 's/Model name: *//p'), g++ $FLAGS"
} >> "$out"
cat "$out"
