#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-2.0-or-later
#
# The Whipple bicycle (models/whipple_bicycle.mbs): mbsc's generation time, the rhs
# operation count (the generated file's banner) and time per rhs call of the complement,
# multipliers, --state minimal and --solver sparse / dense builds, a variant with Euler
# angles, and the same bicycle in joint coordinates (models/whipple_bicycle_joints.mbs,
# full and --state minimal), side by side in ONE
# driver process (bench/bicycle_driver.cpp) with sympy.physics.mechanics deriving the same
# bicycle with KanesMethod in PyDy's layout (bench/sympy_bicycle.py), its C code compiled
# the same way; callgrind's instructions per call when valgrind is there.
#   bash bench/run_bicycle.sh      (from the repository root; ~3 min on 2 cores, sympy ~80 s)
# Writes bench/results/bicycle.md (and prints it). Scratch in bench/work/bicycle (ignored).
#
# The peers are for comparison only, not dependencies of mbsc: /usr/bin/python3 with sympy
# (Debian python3-sympy) and valgrind; as root the script installs what is missing with
# apt-get, else it leaves those columns "n/a". SYMPY_TIMEOUT (default 600 s) bounds
# sympy's derivation and code generation; NO_PEERS=1 measures mbsc alone; MBSC_BUILD=DIR
# uses the mbsc of an existing Release build folder (only its `mbsc` target is built).
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$ROOT"
BUILD=${MBSC_BUILD:-build-bench}
WORK=bench/work/bicycle
FLAGS="-std=c++17 -O2 -march=x86-64"
PY=/usr/bin/python3
SYMPY_TIMEOUT=${SYMPY_TIMEOUT:-600}
M=whipple_bicycle
log() { echo "[run_bicycle $(date +%T)] $*" >&2; }

apt_install() {  # package...; true when installed
  [ "$(id -u)" -eq 0 ] || return 1
  log "installing $* (bench-only peer, not a dependency of mbsc)"
  DEBIAN_FRONTEND=noninteractive apt-get install -y "$@" >/dev/null 2>&1 ||
    { apt-get update >/dev/null 2>&1 && DEBIAN_FRONTEND=noninteractive apt-get install -y "$@" >/dev/null 2>&1; }
}
HAVE_SYMPY=""
HAVE_VALGRIND=""
if [ -z "${NO_PEERS:-}" ]; then
  if $PY -c 'import sympy' 2>/dev/null || { apt_install python3-sympy && $PY -c 'import sympy' 2>/dev/null; }; then
    HAVE_SYMPY=1
  else
    log "no sympy for $PY (apt-get install python3-sympy): the sympy columns are n/a"
  fi
  if command -v valgrind >/dev/null || { apt_install valgrind && command -v valgrind >/dev/null; }; then
    HAVE_VALGRIND=1
  else
    log "no valgrind: the instruction counts are n/a"
  fi
fi

log "building mbsc (Release) in $BUILD"
[ -n "${MBSC_BUILD:-}" ] || cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DMBSC_BUILD_TESTS=OFF -DMBSC_BUILD_APPS=OFF >/dev/null
cmake --build "$BUILD" -j2 --target mbsc >/dev/null
rm -rf "$WORK" && mkdir -p "$WORK" bench/results

# --- mbsc: generation (wall time of the default build, best of 3) -----------------------
gen_s=""
for _ in 1 2 3; do
  s=$(date +%s.%N)
  "$BUILD/mbsc" generate "models/$M.mbs" -o "$WORK" --quiet
  e=$(date +%s.%N)
  gen_s=$(awk -v a="$s" -v b="$e" -v best="$gen_s" 'BEGIN { d = b - a; if (best == "" || d < best) best = d; printf "%.2f", best }')
done
log "mbsc generate: $gen_s s"
"$BUILD/mbsc" generate "models/$M.mbs" -o "$WORK" --quiet --name ${M}_mult --formulation multipliers
"$BUILD/mbsc" generate "models/$M.mbs" -o "$WORK" --quiet --name ${M}_min --state minimal
"$BUILD/mbsc" generate "models/$M.mbs" -o "$WORK" --quiet --name ${M}_sparse --solver sparse
"$BUILD/mbsc" generate "models/$M.mbs" -o "$WORK" --quiet --name ${M}_dense --solver dense
# Where the time goes: the same bicycle with Euler angles (zxy: yaw, lean, pitch; singular
# only with a body's y axis vertical, a bicycle lying flat) instead of quaternions.
sed "s/^  mass m\([RBHF]\)\$/  mass m\1\n  attitude euler zxy body/; /^initial.*e0 = 1/d" "models/$M.mbs" > "$WORK/${M}_euler.mbs"
"$BUILD/mbsc" generate "$WORK/${M}_euler.mbs" -o "$WORK" --quiet --name ${M}_euler
# The same bicycle in joint coordinates (the shipped models/whipple_bicycle_joints.mbs).
"$BUILD/mbsc" generate "models/${M}_joints.mbs" -o "$WORK" --quiet
"$BUILD/mbsc" generate "models/${M}_joints.mbs" -o "$WORK" --quiet --name ${M}_joints_min --state minimal
ops() { sed -n 's|^//   rhs: .*total \([0-9]*\)$|\1|p' "$WORK/$1/$1.cpp"; }
"$BUILD/mbsc" print "models/$M.mbs" --stats > "$WORK/stats.txt" 2>&1 || true

# --- sympy: derive + codegen ---------------------------------------------------------------
defs=() objs=() s_status="" s_derive="" s_codegen="" s_ops=""
if [ -n "$HAVE_SYMPY" ]; then
  log "sympy derive + codegen (timeout $SYMPY_TIMEOUT s)"
  set +e
  timeout "$SYMPY_TIMEOUT" $PY bench/sympy_bicycle.py "$WORK/sympy" > "$WORK/sympy.log" 2>&1
  rc=$?
  set -e
  if [ $rc -eq 0 ]; then
    read -r s_derive s_codegen conv < <($PY -c '
import json, sys
d = json.load(open(sys.argv[1]))
print(d["derive_s"], d["codegen_s"], d["ops_mbsc_conv"])' "$WORK/sympy/sympy_bicycle.json")
    s_ops=$((conv + 6 * 6 * 6 / 3 + 6 * 6))  # + the driver's 6 x 6 LU solve, mbsc's formula n^3/3 + n^2
    gcc -O2 -march=x86-64 -c "$WORK/sympy/sympy_bicycle.c" -o "$WORK/sympy_bicycle.o"
    defs+=(-DWITH_SYMPY)
    objs+=("$WORK/sympy_bicycle.o")
    # The same code in quadruple precision (GCC's __float128 and libquadmath), for the
    # accuracy column only.
    sed 's/#include <math.h>/#include <quadmath.h>/; s/\bdouble\b/__float128/g; s/\bsin(/sinq(/g; s/\bcos(/cosq(/g;
         s/\bpow(/powq(/g; s/\bsqrt(/sqrtq(/g; s/sympy_bicycle_/sympy_bicycle_q_/g' \
      "$WORK/sympy/sympy_bicycle.c" > "$WORK/sympy_bicycle_q.c"
    if gcc -O1 -c "$WORK/sympy_bicycle_q.c" -o "$WORK/sympy_bicycle_q.o" 2> "$WORK/sympy_q.log"; then
      defs+=(-DWITH_SYMPY_QUAD)
      objs+=("$WORK/sympy_bicycle_q.o" -lquadmath)
    fi
  elif [ $rc -eq 124 ]; then
    s_status="did not finish in $SYMPY_TIMEOUT s"
  else
    s_status="failed (rc $rc, $WORK/sympy.log)"
  fi
  [ -n "$s_status" ] && log "sympy $s_status"
fi

# --- the driver ------------------------------------------------------------------------------
log "driver"
srcs=()
for v in "$M" ${M}_mult ${M}_min ${M}_sparse ${M}_dense ${M}_euler ${M}_joints ${M}_joints_min; do srcs+=("$WORK/$v/$v.cpp"); done
g++ $FLAGS -I include -I "$WORK" -DWITH_EULER -DWITH_JOINTS "${defs[@]}" bench/bicycle_driver.cpp "${srcs[@]}" "${objs[@]}" -o "$WORK/driver"
"$WORK/driver" > "$WORK/driver.txt"
val() { sed -n "s/^$1=//p" "$WORK/driver.txt"; }
instr() {  # callgrind's instructions per rhs call of tool $1
  [ -n "$HAVE_VALGRIND" ] || { echo "n/a"; return; }
  valgrind --tool=callgrind --toggle-collect='*count_calls*' --callgrind-out-file="$WORK/callgrind.$1" \
    "$WORK/driver" count "$1" > "$WORK/count_$1.txt" 2> "$WORK/callgrind_$1.log" || { echo "failed"; return; }
  local total calls
  total=$(sed -n 's/.*Collected : \([0-9]*\).*/\1/p' "$WORK/callgrind_$1.log")
  calls=$(sed -n 's/^count_calls=//p' "$WORK/count_$1.txt")
  awk -v a="$total" -v b="$calls" 'BEGIN { if (b > 0 && a > 0) printf "%.0f", a / b; else print "n/a" }'
}

out=bench/results/bicycle.md
{
  echo "mbsc generate models/$M.mbs: $gen_s s (wall, best of 3, all functions)"
  echo
  echo "| build | state size | rhs ops | ns per rhs call (median) | min | instructions per call (callgrind) | agreement with the complement |"
  echo "|---|---:|---:|---:|---:|---:|---:|"
  row() {  # tag, generated name, state size
    local agree="(reference)"
    [ "$1" != complement ] && agree=$(val "$1_rel_diff")
    echo "| $1 | $3 | $(ops "$2") | $(val "$1_ns") | $(val "$1_ns_min") | $(instr "$1") | $agree |"
  }
  row complement "$M" "$(sed -n 's/^inline constexpr int kNx = \([0-9]*\);/\1/p' "$WORK/$M/$M.hpp")"
  row multipliers ${M}_mult "$(sed -n 's/^inline constexpr int kNx = \([0-9]*\);/\1/p' "$WORK/${M}_mult/${M}_mult.hpp")"
  row minimal ${M}_min "$(sed -n 's/^inline constexpr int kNx = \([0-9]*\);/\1/p' "$WORK/${M}_min/${M}_min.hpp")"
  row sparse ${M}_sparse "$(sed -n 's/^inline constexpr int kNx = \([0-9]*\);/\1/p' "$WORK/${M}_sparse/${M}_sparse.hpp")"
  row euler ${M}_euler "$(sed -n 's/^inline constexpr int kNx = \([0-9]*\);/\1/p' "$WORK/${M}_euler/${M}_euler.hpp")"
  row joints ${M}_joints "$(sed -n 's/^inline constexpr int kNx = \([0-9]*\);/\1/p' "$WORK/${M}_joints/${M}_joints.hpp")"
  row joints_min ${M}_joints_min "$(sed -n 's/^inline constexpr int kNx = \([0-9]*\);/\1/p' "$WORK/${M}_joints_min/${M}_joints_min.hpp")"
  row dense ${M}_dense "$(sed -n 's/^inline constexpr int kNx = \([0-9]*\);/\1/p' "$WORK/${M}_dense/${M}_dense.hpp")"
  if [ -n "$HAVE_SYMPY" ]; then
    if [ -z "$s_status" ]; then
      echo "| sympy KanesMethod (+ 6 x 6 LU) | 10 | $s_ops | $(val sympy_ns) | $(val sympy_ns_min) | $(instr sympy) | $(val sympy_rel_diff) (independent accelerations) |"
    else
      echo "| sympy KanesMethod | 10 | n/a | $s_status | | | |"
    fi
  fi
  echo
  if [ -n "$HAVE_SYMPY" ] && [ -z "$s_status" ]; then
    echo "sympy $($PY -c 'import sympy; print(sympy.__version__)'): derivation $s_derive s, code generation (cse + C) $s_codegen s;" \
      "at the running state (yaw, lean, steer, pitch) = ($(val sympy_state)) its (lean, rear wheel, steer) accelerations" \
      "$(val sympy_acc) against mbsc's $(val mbsc_acc); the same sympy code in quadruple precision:" \
      "$(val sympy_quad_acc) (relative difference to mbsc $(val sympy_quad_rel_diff)); finite exactly upright: $(val sympy_upright_ok)"
    echo
  fi
  echo "$(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) cores, $(lscpu | sed -n 's/Model name: *//p'), g++ $FLAGS," \
    "load average $(cut -d' ' -f1-3 /proc/loadavg) at the end"
  [ -n "$HAVE_VALGRIND" ] && echo "$(valgrind --version) (callgrind, instructions of 1000 rhs calls after 100 warm-up calls)"
  echo
  echo "mbsc print --stats:"
  echo
  echo '```'
  cat "$WORK/stats.txt"
  echo '```'
} > "$out"
cat "$out"
