#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-2.0-or-later
#
# The four-bar linkage (models/four_bar.mbs): mbsc's complement rhs (full state and
# --state minimal) against SD/FAST's generated code for the same mechanism (a tree of
# three pins plus a loop pin joint, bench/sdfast_four_bar.py) in its Order(N) and Kane
# formulations, in one driver process (bench/sdfast_four_bar_driver.cpp):
#
#   SDFAST_SRC=/path/to/sdfast bash bench/run_sdfast_planar.sh   (repository root; ~1 min)
#
# SDFAST_SRC: a checkout of SD/FAST's open source release (Apache-2.0), built here with
# CMake into build-sdfast/ (never part of mbsc); without it the script says so and exits
# 0. Per tool: callgrind instructions per rhs call (100 calls after 100 warm-up calls,
# the primary metric), ns per call (median of 5 loops), and the accuracy: the angular
# accelerations of the three bars against the complement's at 100 random assembled
# states; a difference above ACC_LIMIT (default 1e-10) fails the run.
# Writes bench/results/sdfast_four_bar.md (also printed); scratch in bench/work/sdfast_planar.
# Only the four-bar: SD/FAST's loop joints express the other planar mechanisms too, but
# their SD/FAST models are not written yet.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$ROOT"
SDFAST_SRC=${SDFAST_SRC:-}
ACC_LIMIT=${ACC_LIMIT:-1e-10}
BUILD=build-bench
SDFAST_BUILD=build-sdfast
WORK=bench/work/sdfast_planar
FLAGS="-std=c++17 -O2 -march=x86-64"
CFLAGS_SDFAST="-O2 -march=x86-64 -w"
PY=/usr/bin/python3
OUT=bench/results/sdfast_four_bar.md
log() { echo "[run_sdfast_planar $(date +%T)] $*" >&2; }

if [ -z "$SDFAST_SRC" ]; then
  log "SDFAST_SRC not set: nothing to compare (set it to a checkout of SD/FAST's open source release)"
  exit 0
fi
[ -f "$SDFAST_SRC/CMakeLists.txt" ] && [ -d "$SDFAST_SRC/sdfast_main" ] ||
  { echo "run_sdfast_planar: SDFAST_SRC=$SDFAST_SRC is not an SD/FAST checkout" >&2; exit 1; }
if ! command -v valgrind >/dev/null; then
  log "installing valgrind (Debian package 'valgrind')"
  apt-get install -y valgrind >/dev/null 2>&1 || { apt-get update >/dev/null && apt-get install -y valgrind >/dev/null; }
fi

log "building mbsc (Release) in $BUILD and SD/FAST in $SDFAST_BUILD"
cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DMBSC_BUILD_TESTS=OFF -DMBSC_BUILD_APPS=OFF >/dev/null
cmake --build "$BUILD" -j2 --target mbsc >/dev/null
cmake -S "$SDFAST_SRC" -B "$SDFAST_BUILD" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$SDFAST_BUILD" -j2 >/dev/null
SDFAST=$(cd "$SDFAST_BUILD" && pwd)/sdfast

rm -rf "$WORK" && mkdir -p "$WORK/gen" "$WORK/sdfast" bench/results
log "generate: mbsc (complement, full and minimal state), SD/FAST (Order(N) and Kane)"
"$BUILD/mbsc" generate models/four_bar.mbs -o "$WORK/gen" >/dev/null
"$BUILD/mbsc" generate models/four_bar.mbs -o "$WORK/gen" --name four_bar_min --state minimal >/dev/null
$PY bench/sdfast_four_bar.py "$WORK/sdfast/four_bar.sd"
(cd "$WORK/sdfast" && "$SDFAST" -n -p sdn -l c -g dl four_bar.sd sdn_four_bar >/dev/null &&
  "$SDFAST" -k -p sdk -l c -g dl four_bar.sd sdk_four_bar >/dev/null)

log "compile"
objs=()
for f in four_bar four_bar_min; do
  g++ $FLAGS -c "$WORK/gen/$f/$f.cpp" -o "$WORK/$f.o"
  objs+=("$WORK/$f.o")
done
for f in sdn_four_bar_dyn sdnlib sdk_four_bar_dyn sdklib; do
  gcc $CFLAGS_SDFAST -c "$WORK/sdfast/$f.c" -o "$WORK/$f.o"
  objs+=("$WORK/$f.o")
done
g++ $FLAGS -I "$WORK/gen" bench/sdfast_four_bar_driver.cpp "${objs[@]}" -o "$WORK/driver"

log "driver (check at 100 states, then timing)"
"$WORK/driver" > "$WORK/driver.txt"
val() { sed -n "s/^$1=//p" "$WORK/driver.txt"; }
log "callgrind"
declare -A ir
for t in complement minimal sdn sdk; do
  valgrind --tool=callgrind --toggle-collect='*count_calls*' --callgrind-out-file="$WORK/callgrind.$t" \
    "$WORK/driver" count "$t" >"$WORK/count_$t.txt" 2>"$WORK/callgrind_$t.log"
  total=$(sed -n 's/.*Collected : \([0-9]*\).*/\1/p' "$WORK/callgrind_$t.log")
  calls=$(sed -n 's/^count_calls=//p' "$WORK/count_$t.txt")
  ir[$t]=$(awk -v a="$total" -v b="$calls" 'BEGIN { printf "%.0f", a / b }')
done

{
  echo "Four-bar linkage (models/four_bar.mbs), $(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) cores,"
  echo "$(lscpu | sed -n 's/Model name: *//p'), load $(cut -d' ' -f1 /proc/loadavg); g++ $FLAGS; gcc $CFLAGS_SDFAST;"
  echo "SD/FAST $(git -C "$SDFAST_SRC" log -1 --format='commit %h (%cs)' 2>/dev/null || echo '(not a git checkout)');"
  echo "assembled states' position residual $(val assembly_residual)."
  echo
  echo "| tool | instructions / rhs call | ns / rhs call | rel. diff vs mbsc complement | instructions / mbsc complement |"
  echo "|---|---:|---:|---:|---:|"
  echo "| mbsc complement (full state) | ${ir[complement]} | $(val complement_ns) | (reference) | 1 |"
  echo "| mbsc complement --state minimal | ${ir[minimal]} | $(val minimal_ns) | $(val minimal_rel_diff) (crank) | $(awk -v a="${ir[minimal]}" -v b="${ir[complement]}" 'BEGIN { printf "%.3g", a / b }') |"
  echo "| SD/FAST Order(N) | ${ir[sdn]} | $(val sdn_ns) | $(val sdn_rel_diff) | $(awk -v a="${ir[sdn]}" -v b="${ir[complement]}" 'BEGIN { printf "%.3g", a / b }') |"
  echo "| SD/FAST Kane | ${ir[sdk]} | $(val sdk_ns) | $(val sdk_rel_diff) | $(awk -v a="${ir[sdk]}" -v b="${ir[complement]}" 'BEGIN { printf "%.3g", a / b }') |"
} > "$OUT"
cat "$OUT"
for k in sdn_rel_diff sdk_rel_diff minimal_rel_diff; do
  awk -v v="$(val $k)" -v l="$ACC_LIMIT" 'BEGIN { exit !(v + 0 <= l + 0) }' ||
    { echo "run_sdfast_planar: FAILED: $k = $(val $k) > $ACC_LIMIT" >&2; exit 1; }
done
log "done: $OUT"
