#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-2.0-or-later
#
# Planar mechanisms (four-bar, slider-crank, Whitworth, 3RRR): rhs time and operation
# count of mbsc's complement and multipliers formulations, side by side with the peers
# of issue 3 -- sympy.physics.mechanics generated code (bench/sympy_planar.py) and MuJoCo
# (bench/mujoco/*.xml, written by bench/mujoco_planar.py) -- all timed in one driver
# process per mechanism (bench/planar_driver.cpp), in the same run:
#   bash bench/run_planar.sh        (from the repository root; ~2 min on 2 cores)
# Writes bench/results/planar.md (and prints it). Scratch in bench/work/planar (ignored).
#
# The peers are for comparison only, not dependencies of mbsc: /usr/bin/python3 with
# sympy (Debian python3-sympy) and MuJoCo (Debian libmujoco-dev). When one is missing
# the script installs it with apt-get if it runs as root, else it leaves that peer's
# columns "n/a" and says so. SYMPY_TIMEOUT (default 300 s) bounds sympy's derivation and
# code generation per mechanism; NO_PEERS=1 measures mbsc alone; MBSC_BIN=path measures
# that mbsc binary instead of building one in build-bench/; RESULT (default
# bench/results/planar.md) names the result file.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$ROOT"
BUILD=build-bench
WORK=bench/work/planar
FLAGS="-std=c++17 -O2 -march=x86-64"
PY=/usr/bin/python3
SYMPY_TIMEOUT=${SYMPY_TIMEOUT:-300}
log() { echo "[run_planar $(date +%T)] $*" >&2; }

# --- peers (bench-only) ------------------------------------------------------------------
apt_install() {  # package...; true when installed
  [ "$(id -u)" -eq 0 ] || return 1
  log "installing $* (bench-only peer, not a dependency of mbsc)"
  DEBIAN_FRONTEND=noninteractive apt-get install -y "$@" >/dev/null 2>&1 ||
    { apt-get update >/dev/null 2>&1 && DEBIAN_FRONTEND=noninteractive apt-get install -y "$@" >/dev/null 2>&1; }
}
HAVE_SYMPY=""
HAVE_MUJOCO=""
if [ -z "${NO_PEERS:-}" ]; then
  if $PY -c 'import sympy' 2>/dev/null || { apt_install python3-sympy && $PY -c 'import sympy' 2>/dev/null; }; then
    HAVE_SYMPY=1
  else
    log "no sympy for $PY (apt-get install python3-sympy): the sympy columns are n/a"
  fi
  if [ -f /usr/include/mujoco/mujoco.h ] || { apt_install libmujoco-dev libqhull-dev && [ -f /usr/include/mujoco/mujoco.h ]; }; then
    HAVE_MUJOCO=1
  else
    log "no MuJoCo (apt-get install libmujoco-dev): the MuJoCo columns are n/a"
  fi
fi

MBSC=${MBSC_BIN:-$BUILD/mbsc}   # MBSC_BIN=path: measure that binary, nothing built
if [ -z "${MBSC_BIN:-}" ]; then
  log "building mbsc (Release) in $BUILD"
  cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DMBSC_BUILD_TESTS=OFF -DMBSC_BUILD_APPS=OFF >/dev/null
  cmake --build "$BUILD" -j2 --target mbsc >/dev/null
fi
rm -rf "$WORK" && mkdir -p "$WORK" bench/results
out=${RESULT:-bench/results/planar.md}
speed=$WORK/speed.md
acc=$WORK/accuracy.md
{
  echo "| model | dof | complement ops | complement ns | multipliers ops | multipliers ns | complement --state minimal ops | minimal ns | sympy ops | sympy ns | MuJoCo ns | MuJoCo / complement | sympy / complement |"
  echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
} > "$speed"
{
  echo "| model | multipliers vs complement | minimal vs complement | sympy vs complement | same at the start state | MuJoCo qacc vs complement, median / max | same at rest, median / max | near-hard: moving / at rest | MuJoCo loop error at the states (m) | MuJoCo loop error, 1 s of mj_step (m) | sympy derive + codegen (s) |"
  echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
} > "$acc"
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { if (a == "" || b == "") print "n/a"; else printf "%.2f", a / b }'; }
pair() { if [ -n "$1" ]; then echo "$1 / $2"; else echo "n/a"; fi; }
or_na() { if [ -n "$1" ]; then echo "$1"; else echo "n/a"; fi; }

run() {  # model, guesses, drivers, MuJoCo joint map, MuJoCo inputs[, sympy variant]
  local m=$1 guess=$2 drivers=$3 mjmap=$4 mjin=$5 sv=${6:-$1} label=$1
  if [ "$sv" != "$m" ]; then label="$m (sympy: $sv)"; fi
  log "$m: mbsc generate (complement, multipliers)"
  "$MBSC" generate "models/$m.mbs" -o "$WORK" >/dev/null
  "$MBSC" generate "models/$m.mbs" -o "$WORK" --name "${m}_mult" --formulation multipliers >/dev/null
  "$MBSC" generate "models/$m.mbs" -o "$WORK" --name "${m}_min" --state minimal >/dev/null
  local oc om on dof
  oc=$(sed -n 's|^//   rhs: .*total \([0-9]*\)$|\1|p' "$WORK/$m/$m.cpp")
  om=$(sed -n 's|^//   rhs: .*total \([0-9]*\)$|\1|p' "$WORK/${m}_mult/${m}_mult.cpp")
  on=$(sed -n 's|^//   rhs: .*total \([0-9]*\)$|\1|p' "$WORK/${m}_min/${m}_min.cpp")
  dof=$(sed -n 's|^inline constexpr int kNdof = \([0-9]*\);|\1|p' "$WORK/$m/$m.hpp")
  local defs=() objs=() libs=() sops="" sgen="" sstatus=""
  if [ -n "$HAVE_SYMPY" ]; then
    log "$m: sympy derive + codegen (timeout $SYMPY_TIMEOUT s)"
    set +e
    timeout "$SYMPY_TIMEOUT" $PY bench/sympy_planar.py "$sv" "$WORK/sympy" > "$WORK/sympy_$sv.log" 2>&1
    local rc=$?
    set -e
    if [ $rc -eq 0 ]; then
      local o conv
      read -r o conv sgen < <($PY -c '
import json, sys
d = json.load(open(sys.argv[1]))
print(d["speeds"], d["ops_mbsc_conv"], round(d["derive_s"] + d["codegen_s"], 2))' "$WORK/sympy/sympy_$sv.json")
      # + the driver's LU solve of the o x o system, mbsc's formula o^3/3 + o^2
      sops=$((conv + $(awk -v n="$o" 'BEGIN { printf "%d", n * n * n / 3.0 + n * n + 0.5 }')))
      g++ $FLAGS -x c++ -c "$WORK/sympy/sympy_$sv.c" -o "$WORK/sympy_$sv.o"
      defs+=(-DWITH_SYMPY -DSYMPY_NQ="$o" -DSYMPY_NAME="$sv")
      objs+=("$WORK/sympy_$sv.o")
    elif [ $rc -eq 124 ]; then
      sstatus="did not finish in $SYMPY_TIMEOUT s"
      sgen="> $SYMPY_TIMEOUT"
    else
      sstatus="failed (rc $rc, $WORK/sympy_$sv.log)"
    fi
    [ -n "$sstatus" ] && log "$m: sympy $sstatus"
  fi
  if [ -n "$HAVE_MUJOCO" ]; then
    defs+=(-DWITH_MUJOCO -DMJ_XML="\"bench/mujoco/$m.xml\"" -DMJ_MAP="$mjmap" -DMJ_INPUTS="$mjin")
    libs+=(-lmujoco)
  fi
  log "$m: driver"
  g++ $FLAGS -I include -I "$WORK" -DMODEL="$m" -DGUESS="$guess" -DDRIVERS="$drivers" -DWITH_MINIMAL "${defs[@]}" \
    bench/planar_driver.cpp "$WORK/$m/$m.cpp" "$WORK/${m}_mult/${m}_mult.cpp" "$WORK/${m}_min/${m}_min.cpp" "${objs[@]}" \
    "${libs[@]}" -o "$WORK/driver_$sv"
  "$WORK/driver_$sv" > "$WORK/$sv.txt"
  val() { sed -n "s/^$1=//p" "$WORK/$sv.txt"; }
  local c mu mn s mj
  c=$(val complement_ns); mu=$(val multipliers_ns); mn=$(val minimal_ns); s=$(val sympy_ns); mj=$(val mujoco_ns)
  local sns; sns=$(or_na "$s"); [ -n "$sstatus" ] && sns=$sstatus
  echo "| $label | $dof | $oc | $c | $om | $mu | $on | $mn | $(or_na "$sops") | $sns | $(or_na "$mj") | $(ratio "$mj" "$c") | $(ratio "$s" "$c") |" >> "$speed"
  echo "| $label | $(val max_rel_diff) | $(val minimal_rel_diff) | $(or_na "$(val sympy_rel_diff)") | $(or_na "$(val sympy_rel_diff_start)") | $(pair "$(val mujoco_rel_diff_median)" "$(val mujoco_rel_diff)") | $(pair "$(val mujoco_rel_diff_rest_median)" "$(val mujoco_rel_diff_rest)") | $(pair "$(val mujoco_hard_rel_diff)" "$(val mujoco_hard_rel_diff_rest)") | $(or_na "$(val mujoco_eq_states)") | $(or_na "$(val mujoco_eq_1s)") | $(or_na "$sgen") |" >> "$acc"
}
FOUR_BAR=('{"crank.theta", 1.2}, {"coupler.theta", 0.4}, {"rocker.theta", 1.9}, {"crank.w", 2.0}' '"crank.theta", "crank.w"'
  '{"crank", "crank.theta", ""}, {"coupler", "coupler.theta", "crank.theta"}, {"rocker", "rocker.theta", ""}'
  '{"crank", "tau0"}')
run four_bar "${FOUR_BAR[@]}"
run slider_crank '{"crank.theta", 0.7}, {"rod.theta", -0.1}, {"slider.x", 0.4}, {"crank.w", 5.0}' '"crank.theta", "crank.w"' \
  '{"crank", "crank.theta", ""}, {"slider", "slider.x", ""}, {"rod", "rod.theta", ""}' \
  '{"crank", "tau"}, {"slider", "F_load"}'
run whitworth '{"crank.theta", 0.785398}, {"crank.w", 1.5708}, {"slider.x", 0.7}, {"slider.y", 0.8}, {"rocker.theta", 1.3}, {"rocker.x", 0.1}, {"rocker.y", 0.3}, {"rod.theta", 3.4}, {"rod.x", 0.5}, {"rod.y", 0.7}, {"crank.y", 0.3}' '"crank.theta", "crank.w"' \
  '{"slider", "slider.x", ""}, {"rod", "rod.theta", ""}, {"crank", "crank.theta", ""}, {"rocker", "rocker.theta", "crank.theta"}, {"slot", "@slot", ""}' \
  '{"crank", "u1"}'
run three_rrr '{"HA.proximal.theta", 2.0}, {"HA.proximal.x", 3.0}, {"HB.proximal.theta", 3.8}, {"HB.proximal.x", -1.5}, {"HB.proximal.y", 2.598}, {"HC.proximal.theta", 6.0}, {"HC.proximal.x", -1.5}, {"HC.proximal.y", -2.598}, {"HA.distal.theta", 1.0}, {"HB.distal.theta", 3.1}, {"HC.distal.theta", 5.2}, {"platform.u", -1.5708}, {"platform.v", 0.7854}' '"platform.x", "platform.y", "platform.theta", "platform.u", "platform.v", "platform.w"' \
  '{"HA_proximal", "HA.proximal.theta", ""}, {"HA_distal", "HA.distal.theta", "HA.proximal.theta"}, {"platform", "platform.theta", "HA.distal.theta"}, {"HB_proximal", "HB.proximal.theta", ""}, {"HB_distal", "HB.distal.theta", "HB.proximal.theta"}, {"HC_proximal", "HC.proximal.theta", ""}, {"HC_distal", "HC.distal.theta", "HC.proximal.theta"}' \
  '{"HA_proximal", "u1"}, {"HB_proximal", "u2"}, {"HC_proximal", "u3"}'
# The four-bar again, sympy in mbsc's absolute coordinates (x, y, theta of every bar):
# the coordinates, not only the formulation, set sympy's cost.
if [ -n "$HAVE_SYMPY" ]; then run four_bar "${FOUR_BAR[@]}" four_bar_abs; fi
{
  echo "Time per rhs call (ns, median of 5 alternating loops of >= 0.3 s over 50 states) and operation count:"
  echo
  cat "$speed"
  echo
  echo "Agreement (speed rates; per state max |a - b| / max |a|, a = complement; the max over the 50 states unless marked) and MuJoCo's loop-closure error (max |efc_pos| of its connect rows):"
  echo
  cat "$acc"
  echo
  echo "$(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) cores, $(lscpu | sed -n 's/Model name: *//p'), g++ $FLAGS," \
    "load average $(cut -d' ' -f1-3 /proc/loadavg) at the end"
  if [ -n "$HAVE_SYMPY" ]; then echo "sympy $($PY -c 'import sympy; print(sympy.__version__)')"; fi
  if [ -n "$HAVE_MUJOCO" ]; then echo "MuJoCo $(dpkg-query -W -f='${Version}' libmujoco-dev 2>/dev/null) (mj_version $(sed -n 's/^mujoco_version=//p' "$WORK/four_bar.txt")), default options: timestep $(sed -n 's/^mujoco_timestep=//p' "$WORK/four_bar.txt") s, Euler, Newton solver, soft equality constraints"; fi
} > "$out"
cat "$out"
