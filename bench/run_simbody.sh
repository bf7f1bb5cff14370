#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-2.0-or-later
#
# Simbody, the peer of the speed-versus-error benchmark (`mbsc bench`, docs/benchmarks.md):
# builds bench/simbody (Debian libsimbody-dev; installed with apt-get when missing and
# running as root) and integrates every shipped closed-loop model, rebuilt with
# Simbody's API, from the initial state of bench/simbody/initial_states.txt to T_END
# with Simbody's integrators at accuracies 1e-3 ... 1e-10, one process per run:
#   bash bench/run_simbody.sh [MODEL ...]     (repository root; ~15 min on 2 cores)
# Writes bench/results/simbody_<model>.csv (columns: bench/simbody/simbody_bench.cpp),
# bench/results/simbody_env.txt (machine, versions, date) and, for runs Simbody could
# not finish, one line each in bench/results/simbody_failures.txt.
#   env: T_END (default 5 s), TOLS, METHODS (adaptive, every tolerance), TIGHT_TOLS for
#        TIGHT_METHODS (the explicit Runge-Kutta pairs also at 1e-11, 1e-12, so that
#        their final-state error reaches 1e-9), LOW_ORDER and LOW_TOLS (low-order
#        methods, the loose tolerances only), APPEND=1 (add the runs to the existing
#        CSVs instead of replacing them), TIMEOUT per run
#        (default 60 s), JOBS (models run side by side, default 1), SB_BUILD
#        (default build-simbody). rk3 and verlet are left out by default: at the tight
#        tolerances they take minutes per run (verlet does not finish the four-bar at
#        1e-5 in 300 s) and add no point left of the curves of the others.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$ROOT"
SB=${SB_BUILD:-build-simbody}
T_END=${T_END:-5}
TOLS=${TOLS-"1e-3 1e-4 1e-5 1e-6 1e-7 1e-8 1e-9 1e-10"}
METHODS=${METHODS-"rkmerson rkfeldberg cpodes_bdf"}
TIGHT_TOLS=${TIGHT_TOLS-"1e-11 1e-12"}
TIGHT_METHODS=${TIGHT_METHODS-"rkmerson rkfeldberg"}
LOW_ORDER=${LOW_ORDER-"semieuler2"}
LOW_TOLS=${LOW_TOLS-"1e-3 1e-4 1e-5"}
APPEND=${APPEND:-}
TIMEOUT=${TIMEOUT:-60}
JOBS=${JOBS:-1}
MODELS=("$@")
[ ${#MODELS[@]} -gt 0 ] || MODELS=(four_bar four_bar_toggle slider_crank five_bar whitworth three_rrr parallelogram_chain)
log() { echo "[run_simbody $(date +%T)] $*" >&2; }

if [ ! -f /usr/lib/x86_64-linux-gnu/cmake/simbody/SimbodyConfig.cmake ] && ! dpkg -s libsimbody-dev >/dev/null 2>&1; then
  [ "$(id -u)" -eq 0 ] || { log "needs libsimbody-dev (apt-get install libsimbody-dev)"; exit 1; }
  log "installing libsimbody-dev (bench-only peer, not a dependency of mbsc)"
  DEBIAN_FRONTEND=noninteractive apt-get install -y libsimbody-dev >/dev/null
fi
log "building bench/simbody in $SB"
cmake -S bench/simbody -B "$SB" -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build "$SB" -j2 --target simbody_bench > /dev/null

mkdir -p bench/results
{
  echo "date: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
  echo "machine: nproc $(nproc), $(lscpu | sed -n 's/^Model name: *//p'), $(free -g | awk '/^Mem:/ {print $2}') GiB, Linux $(uname -r)"
  echo "compiler: $(g++ --version | head -1)"
  echo "simbody: $(dpkg-query -W -f '${Package} ${Version}' libsimbody-dev 2>/dev/null || echo unknown)"
  echo "load at start: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "T_END=$T_END TOLS=$TOLS METHODS=$METHODS TIGHT_TOLS=$TIGHT_TOLS TIGHT_METHODS=$TIGHT_METHODS"
  echo "LOW_ORDER=$LOW_ORDER LOW_TOLS=$LOW_TOLS JOBS=$JOBS APPEND=$APPEND"
} > "$SB/env.txt"
if [ -n "$APPEND" ]; then { echo; cat "$SB/env.txt"; } >> bench/results/simbody_env.txt; else cp "$SB/env.txt" bench/results/simbody_env.txt; fi

one() {  # model tol method first
  local out rc err="$SB/err_$1.txt"
  set +e
  if [ "$4" = 1 ]; then
    out=$(timeout "$TIMEOUT" "$SB/simbody_bench" "$1" "$2" "$T_END" "$3" --header 2> "$err")
  else
    out=$(timeout "$TIMEOUT" "$SB/simbody_bench" "$1" "$2" "$T_END" "$3" 2> "$err")
  fi
  rc=$?
  set -e
  if [ $rc -eq 0 ]; then
    echo "$out"
  else
    local why
    why=$(grep -m1 -o 'Integrator step failed at time [0-9.e+-]*' "$err" || true)
    [ -n "$why" ] || why=$(grep -m1 'Error detected by' "$err" | sed 's/^ *//' || true)
    [ $rc -eq 124 ] && why="no result within $TIMEOUT s"
    [ -n "$why" ] || why=$(grep -v '^ *$' "$err" | tail -1)
    echo "$1 $3 tol $2: failed (exit $rc): $why" >> "$SB/fail_$1.txt"
    log "$1 $3 tol $2: failed ($why)"
  fi
}

model_runs() {  # model: every method and tolerance into bench/results/simbody_<model>.csv
  local m=$1 csv=bench/results/simbody_$1.csv tmp first=1 line tols meth tol
  log "$m -> $csv"
  tmp=$(mktemp)
  if [ -n "$APPEND" ] && [ -s "$csv" ]; then cp "$csv" "$tmp"; first=0; fi
  : > "$SB/fail_$m.txt"
  for meth in $METHODS $LOW_ORDER; do
    tols=$TOLS
    case " $TIGHT_METHODS " in *" $meth "*) tols="$TOLS $TIGHT_TOLS" ;; esac
    case " $LOW_ORDER " in *" $meth "*) tols=$LOW_TOLS ;; esac
    for tol in $tols; do
      line=$(one "$m" "$tol" "$meth" "$first")
      if [ -n "$line" ]; then
        if [ "$first" = 1 ]; then first=0; fi
        echo "$line" >> "$tmp"
      fi
    done
  done
  mv "$tmp" "$csv"
  chmod 644 "$csv"
  log "$m done"
}

running=0
for m in "${MODELS[@]}"; do
  model_runs "$m" &
  running=$((running + 1))
  if [ "$running" -ge "$JOBS" ]; then wait -n; running=$((running - 1)); fi
done
wait
[ -n "$APPEND" ] || : > bench/results/simbody_failures.txt
for m in "${MODELS[@]}"; do cat "$SB/fail_$m.txt"; done >> bench/results/simbody_failures.txt
echo "load at end: $(cut -d' ' -f1-3 /proc/loadavg); finished $(date -u +%H:%M:%SZ)" >> bench/results/simbody_env.txt
log "done: bench/results/simbody_*.csv"
