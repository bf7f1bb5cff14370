#!/usr/bin/env bash
# Growth of check/generate cost with model size (issue 11, "generation in O(N log N)"):
# CPU time (user + system) and peak resident memory of `mbsc check` and `mbsc generate`
# for three families, then bench/fit_front_end_scaling.py fits the exponent of each
# and exits 1, loudly, when one grows faster than N^1.3 (MBSC_SCALING_LIMIT overrides).
#   free particles (particle2d, gravity)            N = 100 .. 1000
#   planar N-link chain of bench/chain_model.py     N = 16 .. 128, --state minimal
#   models/parallelogram_chain.mbs --freeze N=...   N = 10 .. 150 (not 80 or 120: at those
#     lengths the random probe point makes the given independent set look singular, a
#     failure of the rank test that predates this script)
# Writes bench/results/front_end_scaling.csv (family,n,command,cpu_s,rss_kib,exit).
# MBSC: the binary to measure (default build/mbsc, built here when missing).
set -uo pipefail
cd "$(dirname "$0")/.."
mbsc=${MBSC:-build/mbsc}
if [ ! -x "$mbsc" ]; then
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null && cmake --build build -j"$(nproc)" --target mbsc >/dev/null
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
out=${OUT:-bench/results/front_end_scaling.csv}
budget=${BUDGET:-120}
echo "family,n,command,cpu_s,rss_kib,exit" > "$out"
measure() {  # family n command model [extra mbsc arguments]
  local family=$1 n=$2 cmd=$3 model=$4; shift 4
  local args=("$cmd" "$model" "$@" --budget "$budget" -q)
  [ "$cmd" = generate ] && args+=(-o "$tmp/out" --force)
  local rc=0
  /usr/bin/time -f "%U %S %M" -o "$tmp/time" "$mbsc" "${args[@]}" >/dev/null 2>"$tmp/err" || rc=$?
  rm -rf "$tmp/out"
  read -r user sys rss < <(tail -1 "$tmp/time")
  local cpu; cpu=$(awk -v u="$user" -v s="$sys" 'BEGIN { printf "%.3f", u + s }')
  echo "$family,$n,$cmd,$cpu,$rss,$rc" | tee -a "$out"
}
for n in ${FREE_N-100 200 400 700 1000}; do
  printf 'model free%s\nparameter m = 1, g = 9.81\ngravity (0, -g)\nfor i = 1 to %s { body b[i] : particle2d { mass m } }\n' \
    "$n" "$n" > "$tmp/free$n.mbs"
  measure free_particles "$n" check "$tmp/free$n.mbs"
  measure free_particles "$n" generate "$tmp/free$n.mbs"
done
for n in ${CHAIN_N-16 32 64 128}; do
  /usr/bin/python3 bench/chain_model.py "$n" "$tmp/chain$n.mbs"
  measure chain "$n" check "$tmp/chain$n.mbs"
  measure chain "$n" generate "$tmp/chain$n.mbs" --state minimal
done
for n in ${PARALLELOGRAM_N-10 20 40 70 100 150}; do
  measure parallelogram_chain "$n" check models/parallelogram_chain.mbs --freeze "N=$n"
  measure parallelogram_chain "$n" generate models/parallelogram_chain.mbs --freeze "N=$n"
done
/usr/bin/python3 bench/fit_front_end_scaling.py "$out"
