#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-2.0-or-later
#
# Issue 13's benchmark: linearization and 1000-point eigenvalue sweeps of the ring-disc
# (models/ring_disc.mbs, thesis Ex 4.2 / 4.7) and the Whipple bicycle in joint coordinates
# (models/whipple_bicycle_joints.mbs), mbsc's generated linear_parts with
# include/mbsc/runtime/linear_model.hpp (bench/linearize_driver.cpp) against
# sympy.physics.mechanics' KanesMethod.linearize on the same models
# (bench/sympy_linearize.py), in ONE run; callgrind's instructions per linear_model call
# when valgrind is there.
#   bash bench/run_linearize.sh     (from the repository root; mbsc ~2 min on 2 cores; sympy's
#   bicycle linearization is long: docs/benchmarks.md "Issue 13")
# Writes bench/results/linearize.md (and prints it). Scratch in bench/work/linearize (ignored).
#
# The peers are for comparison only, not dependencies of mbsc: /usr/bin/python3 with sympy
# and numpy (Debian python3-sympy, python3-numpy) and valgrind; as root the script installs
# what is missing with apt-get, else those columns are "n/a". SYMPY_TIMEOUT (default
# 1200 s) bounds the sympy script; SYMPY_NUMERIC_DATA=1 derives sympy's bicycle with its
# data as numbers (a smaller symbolic linearization); NO_PEERS=1 measures mbsc alone; MBSC_BUILD=DIR uses the mbsc of an existing Release build
# folder (only its `mbsc` target is built).
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$ROOT"
BUILD=${MBSC_BUILD:-build-bench}
WORK=bench/work/linearize
FLAGS="-std=c++17 -O2 -march=x86-64"
PY=/usr/bin/python3
SYMPY_TIMEOUT=${SYMPY_TIMEOUT:-1200}
log() { echo "[run_linearize $(date +%T)] $*" >&2; }

apt_install() {  # package...; true when installed
  [ "$(id -u)" -eq 0 ] || return 1
  log "installing $* (bench-only peer, not a dependency of mbsc)"
  DEBIAN_FRONTEND=noninteractive apt-get install -y "$@" >/dev/null 2>&1 ||
    { apt-get update >/dev/null 2>&1 && DEBIAN_FRONTEND=noninteractive apt-get install -y "$@" >/dev/null 2>&1; }
}
HAVE_SYMPY="" HAVE_VALGRIND=""
if [ -n "${NO_PEERS:-}" ]; then
  log "NO_PEERS: mbsc alone"
elif (cd /tmp && $PY -c 'import sympy, numpy') 2>/dev/null || { apt_install python3-sympy python3-numpy && (cd /tmp && $PY -c 'import sympy, numpy') 2>/dev/null; }; then
  HAVE_SYMPY=1
else
  log "no sympy + numpy for $PY: the sympy columns are n/a"
fi
if [ -n "${NO_PEERS:-}" ]; then
  :
elif command -v valgrind >/dev/null || { apt_install valgrind && command -v valgrind >/dev/null; }; then
  HAVE_VALGRIND=1
else
  log "no valgrind: the instruction counts are n/a"
fi
EIGEN=""
for d in /usr/include/eigen3 /usr/local/include/eigen3; do [ -f "$d/Eigen/Dense" ] && EIGEN=$d && break; done
[ -n "$EIGEN" ] || { log "Eigen 3 not found (the driver's eigenvalues)"; exit 1; }

log "building mbsc (Release) in $BUILD"
[ -n "${MBSC_BUILD:-}" ] || cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DMBSC_BUILD_TESTS=OFF -DMBSC_BUILD_APPS=OFF >/dev/null
cmake --build "$BUILD" -j2 --target mbsc >/dev/null
rm -rf "$WORK" && mkdir -p "$WORK" bench/results

# --- mbsc: generation with linear_parts (wall time, best of 3) ------------------------------
declare -A gen_s
for M in ring_disc whipple_bicycle_joints; do
  best=""
  for _ in 1 2 3; do
    s=$(date +%s.%N)
    "$BUILD/mbsc" generate "models/$M.mbs" -o "$WORK" --quiet --linear-parts
    e=$(date +%s.%N)
    best=$(awk -v a="$s" -v b="$e" -v best="$best" 'BEGIN { d = b - a; if (best == "" || d < best) best = d; printf "%.2f", best }')
  done
  gen_s[$M]=$best
  log "mbsc generate --linear-parts $M: $best s"
done

# --- the driver ---------------------------------------------------------------------------
log "driver"
declare -A cc_s
for M in ring_disc whipple_bicycle_joints; do  # the generated code's compile time (wall)
  s=$(date +%s.%N)
  g++ $FLAGS -I include -c "$WORK/$M/$M.cpp" -o "$WORK/$M.o"
  e=$(date +%s.%N)
  cc_s[$M]=$(awk -v a="$s" -v b="$e" 'BEGIN { printf "%.1f", b - a }')
done
g++ $FLAGS -I include -I "$WORK" -I "$EIGEN" bench/linearize_driver.cpp "$WORK/ring_disc.o" "$WORK/whipple_bicycle_joints.o" -o "$WORK/driver"
"$WORK/driver" sweep-out "$WORK/mbsc_sweep.txt" > "$WORK/driver.txt"
val() { sed -n "s/^$1=//p" "$WORK/driver.txt"; }
instr() {  # callgrind's instructions per linear_model call ($1: ring or bike)
  [ -n "$HAVE_VALGRIND" ] || { echo "n/a"; return; }
  valgrind --tool=callgrind --toggle-collect='count_calls' --callgrind-out-file="$WORK/callgrind.$1" \
    "$WORK/driver" count "$1" > "$WORK/count_$1.txt" 2> "$WORK/callgrind_$1.log" || { echo "failed"; return; }
  local total calls
  total=$(sed -n 's/.*Collected : \([0-9]*\).*/\1/p' "$WORK/callgrind_$1.log")
  calls=$(sed -n 's/^count_calls=//p' "$WORK/count_$1.txt")
  awk -v a="$total" -v b="$calls" 'BEGIN { if (b > 0 && a > 0) printf "%.0f", a / b; else print "n/a" }'
}
log "callgrind"
ring_instr=$(instr ring)
bike_instr=$(instr bike)

# --- sympy ------------------------------------------------------------------------------------
s_status=""
if [ -n "$HAVE_SYMPY" ]; then
  log "sympy linearize (timeout $SYMPY_TIMEOUT s)"
  set +e
  timeout "$SYMPY_TIMEOUT" $PY bench/sympy_linearize.py "$WORK/sympy" 1000 ${SYMPY_NUMERIC_DATA:+--numeric-data} > "$WORK/sympy.log" 2>&1
  rc=$?
  set -e
  [ $rc -eq 124 ] && s_status="did not finish in $SYMPY_TIMEOUT s"
  [ $rc -ne 0 ] && [ $rc -ne 124 ] && s_status="failed (rc $rc, $WORK/sympy.log)"
  [ -n "$s_status" ] && log "sympy $s_status"
else
  s_status="n/a (not run)"
fi

# --- the table ----------------------------------------------------------------------------------
# Agreement of the sweeps: the ring-disc's omega point by point; the bicycle's eigenvalues
# as sets (each eigenvalue of one to the nearest of the other, both ways: mbsc's minimal
# state carries 4 more zero eigenvalues, the ignorable coordinates sympy's layout drops).
compare() {
  (cd "$WORK" && $PY - <<'EOF'
import json
def read(path):
    ring, bike = {}, {}
    for line in open(path):
        f = line.split()
        if f[0] == "ring": ring[int(f[1])] = float(f[2])
        else: bike[int(f[1])] = [complex(float(f[i]), float(f[i + 1])) for i in range(2, len(f), 2)]
    return ring, bike
mr, mb = read("mbsc_sweep.txt")
sr, sb = read("sympy/sympy_sweep.txt")
ring = max(abs(mr[k] - sr[k]) / abs(sr[k]) for k in sr)
def hd(a, b): return max(min(abs(x - y) for y in b) for x in a)
worst, at = 0.0, 0
for k in sb:
    d = max(hd(mb[k], sb[k]), hd(sb[k], mb[k])) / max(1.0, max(abs(z) for z in sb[k]))
    if d > worst: worst, at = d, k
s = json.load(open("sympy/sympy_linearize.json"))
paper = [complex(-0.775341882195845, 4.464867713788234), complex(-0.775341882195845, -4.464867713788234),
         complex(-0.322866429004087, 0), complex(-14.0783896927982, 0)]
e5 = [complex(a, b) for a, b in s["bike"]["eigenvalues"]]
print(json.dumps({"ring_rel": ring, "bike_rel": worst, "bike_at_v": 10.0 * at / 999,
                  "sympy_bike_err_paper": max(min(abs(z - p) for z in e5) for p in paper),
                  "sympy_ring_err_thesis": abs(s["ring"]["omega"] - 2.63296508333)}))
EOF
  )
}
cmp_json=$(compare 2>/dev/null || echo '{}')
sj() {  # a value of sympy's json: $1 model, $2 key
  [ -f "$WORK/sympy/sympy_linearize.json" ] || { echo "n/a"; return; }
  $PY -c 'import json, sys; print(json.load(open(sys.argv[1])).get(sys.argv[2], {}).get(sys.argv[3], "n/a"))' "$WORK/sympy/sympy_linearize.json" "$1" "$2"
}
cj() { $PY -c 'import json, sys; d = json.loads(sys.argv[1]); print("%.2g" % d[sys.argv[2]] if sys.argv[2] in d else "n/a")' "$cmp_json" "$1"; }
fmt_s() { awk -v x="$1" 'BEGIN { if (x == "n/a" || x == "") print "n/a"; else printf "%.3g", x }'; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { if (a == "n/a" || b == "n/a" || a == "" || b == "" || a + 0 == 0) print "n/a"; else printf "%.0f", b / a }'; }

out=bench/results/linearize.md
{
  echo "| model | mbsc: one linear_model call (median / min) | instructions per call (callgrind) | mbsc: 1000-point sweep (median / min) | sympy: derive (KanesMethod) | sympy: linearize (symbolic M, A) | sympy: op_point substituted + P^T M^-1 A | sympy: sweep set-up (msubs + lambdify) | sympy: 1000-point sweep | sweep ratio sympy / mbsc | agreement |"
  echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"
  rs=$(sj ring sweep_s); bs=$(sj bike sweep_s)
  echo "| ring-disc (14 full, $(val ring_m) minimal) | $(val ring_linear_model_ns) / $(val ring_linear_model_ns_min) ns | $ring_instr | $(val ring_sweep_ms) / $(val ring_sweep_ms_min) ms | $(fmt_s "$(sj ring derive_s)") s | $(fmt_s "$(sj ring linearize_s)") s | $(fmt_s "$(sj ring op_point_s)") s | $(fmt_s "$(sj ring sweep_setup_s)") s | $(fmt_s "$rs") s | $(ratio "$(val ring_sweep_ms)" "$(awk -v x="$rs" 'BEGIN { print (x == "n/a") ? x : x * 1000 }')") | omega $(val ring_omega): $(val ring_omega_err_thesis) from the thesis' 2.63296508333, $(val ring_omega_err_closed) from the closed form; sweep: largest relative difference to the closed form $(val ring_sweep_rel_err_closed), to sympy $(cj ring_rel); sympy's omega $(cj sympy_ring_err_thesis) from the thesis; central differences of rhs $(val ring_fd_rel_diff) |"
  echo "| bicycle, joint coordinates (45 full, $(val bike_m) minimal) | $(val bike_linear_model_ns) / $(val bike_linear_model_ns_min) ns | $bike_instr | $(val bike_sweep_ms) / $(val bike_sweep_ms_min) ms | $(fmt_s "$(sj bike derive_s)") s | $(fmt_s "$(sj bike linearize_s)") s | $(fmt_s "$(sj bike op_point_s)") s | $(fmt_s "$(sj bike sweep_setup_s)") s | $(fmt_s "$bs") s | $(ratio "$(val bike_sweep_ms)" "$(awk -v x="$bs" 'BEGIN { print (x == "n/a") ? x : x * 1000 }')") | 5 m/s: weave, capsize, castering $(val bike_err_paper) from Meijaard et al. Table 2 (sympy $(cj sympy_bike_err_paper)); sweep: largest difference to sympy's eigenvalues $(cj bike_rel) (relative to the largest, at v = $(cj bike_at_v) m/s); central differences of rhs $(val bike_fd_rel_diff) |"
  echo
  [ -n "$s_status" ] && { echo "sympy: $s_status"; echo; }
  [ "$(sj bike numeric_data)" = True ] && { echo "sympy's bicycle derived with Table 1's data as numbers (SYMPY_NUMERIC_DATA=1); the ring-disc's data symbolic."; echo; }
  echo "mbsc generate --linear-parts (wall, best of 3): ring_disc ${gen_s[ring_disc]} s, whipple_bicycle_joints ${gen_s[whipple_bicycle_joints]} s;" \
    "g++ $FLAGS of the generated code (wall, once): ${cc_s[ring_disc]} s and ${cc_s[whipple_bicycle_joints]} s."
  echo "mbsc's bicycle eigenvalues at 5 m/s (minimal state keeping lean, steer and their rates): $(val bike_eigs)"
  echo
  echo "$(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) cores, $(lscpu | sed -n 's/Model name: *//p'), g++ $FLAGS," \
    "load average $(cut -d' ' -f1-3 /proc/loadavg) at the end"
  [ -n "$HAVE_SYMPY" ] && echo "sympy $(cd /tmp && $PY -c 'import sympy; print(sympy.__version__)'), numpy $(cd /tmp && $PY -c 'import numpy; print(numpy.__version__)'), $($PY --version 2>&1)"
  [ -n "$HAVE_VALGRIND" ] && echo "$(valgrind --version) (callgrind, instructions of 100 linear_model calls after 20 warm-up calls)"
} > "$out"
cat "$out"
