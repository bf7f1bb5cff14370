#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-2.0-or-later
#
# The spatial N-link chain of issue 25 (bench/spatial_chain_model.py): generation, compile
# and rhs cost of mbsc's default choice (`--solver auto`: the tree recursion from seven
# links on) and of the dense Cholesky of the reduced equations (`--solver dense`, up to
# DENSE_MAX_N links), `--state minimal --outputs rhs`:
#
#   bash bench/run_spatial_chain.sh   (from the repository root; ~5 min on 2 cores)
#
# Environment: NS (default "1 2 4 8 12 16 24 32 48 64"), DENSE_MAX_N (default 12; 4 with
# BALL=1 or QUAT=1), MBSC_BIN (default build/mbsc), BALL=1 for the chain of spherical joints with
# zyx angles (bench/spatial_chain_model.py --ball; results in ball_chain.md), QUAT=1 for the
# same joints with a quaternion each (--quat; quat_chain.md), LOOP=1 for the
# revolute chain with its tip held on a ground plane (--loop: a loop closed on the tree;
# results in loop_chain.md; DENSE_MAX_N default 16). Per N and solver: rhs operations (the generated header),
# generation CPU time and peak memory (GNU time), g++ -O2 time and peak memory,
# instructions per rhs call (callgrind over bench/rhs_count_driver.cpp's 20 states), and
# the agreement of the auto and dense rhs at 100 random states
# (bench/spatial_chain_driver.cpp; an agreement above 1e-10 fails the run after the table).
# Pinocchio and RBDL were measured outside this repository (docs/benchmarks.md says how);
# nothing here builds them. Writes bench/results/spatial_chain.md (also printed) and
# spatial_chain_env.txt; scratch in bench/work/spatial_chain/ (with BALL=1: ball_chain.md,
# ball_chain_env.txt, bench/work/ball_chain/; with QUAT=1 and LOOP=1 the same with quat_chain
# and loop_chain).
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$ROOT"
NS=${NS:-"1 2 4 8 12 16 24 32 48 64"}
BALL=${BALL:-0}
QUAT=${QUAT:-0}
LOOP=${LOOP:-0}
if [ "$QUAT" = 1 ]; then KIND=quat_chain MODEL_FLAG=--quat DENSE_DEFAULT=4
elif [ "$BALL" = 1 ]; then KIND=ball_chain MODEL_FLAG=--ball DENSE_DEFAULT=4
elif [ "$LOOP" = 1 ]; then KIND=loop_chain MODEL_FLAG=--loop DENSE_DEFAULT=16
else KIND=spatial_chain MODEL_FLAG= DENSE_DEFAULT=12
fi
DENSE_MAX_N=${DENSE_MAX_N:-$DENSE_DEFAULT}
MBSC=${MBSC_BIN:-build/mbsc}
WORK=bench/work/$KIND
rm -rf "$WORK"; mkdir -p "$WORK" bench/results
for tool in valgrind /usr/bin/time g++; do command -v "$tool" >/dev/null || { echo "needs $tool" >&2; exit 2; }; done
{ date -u; uname -srm; nproc; g++ --version | head -1; "$MBSC" --version 2>/dev/null || true; } >"bench/results/${KIND}_env.txt"

measure() {  # N solver -> one table row
  local n=$1 solver=$2 name="chain${1}_$2" d="$WORK/$1_$2"
  mkdir -p "$d"
  /usr/bin/python3 bench/spatial_chain_model.py $MODEL_FLAG "$n" "$d/model.mbs"
  /usr/bin/time -f "%U %M" -o "$d/gen.time" "$MBSC" generate "$d/model.mbs" -o "$d" --name "$name" -q \
    --state minimal --outputs rhs --solver "$solver"
  local ops tree gen_s gen_kb cc_s cc_kb total calls
  ops=$(sed -n 's|^//   rhs: .*total \([0-9]*\)$|\1|p' "$d/$name/$name.cpp")
  tree=$(grep -c "tree recursion" "$d/$name/$name.cpp" || true)
  read -r gen_s gen_kb <"$d/gen.time"
  /usr/bin/time -f "%e %M" -o "$d/cc.time" g++ -std=c++17 -O2 -march=x86-64 -I include -I "$d" -DMODEL="$name" \
    -DHEADER="\"$name/$name.hpp\"" bench/rhs_count_driver.cpp "$d/$name/$name.cpp" -o "$d/count"
  read -r cc_s cc_kb <"$d/cc.time"
  valgrind --tool=callgrind --toggle-collect='*count_calls*' --callgrind-out-file="$d/cg.out" "$d/count" \
    >"$d/count.txt" 2>"$d/cg.log"
  total=$(sed -n 's/.*Collected : \([0-9]*\).*/\1/p' "$d/cg.log")
  calls=$(sed -n 's/^count_calls=//p' "$d/count.txt")
  # A call that fails (a singular solve) returns early: its count would not be the rhs's.
  [ "$(sed -n 's/^failed=//p' "$d/count.txt")" = 0 ] || { echo "N = $n $solver: rhs calls failed" >&2; exit 1; }
  printf '| %s | %s | %s | %s | %.0f | %.2f s, %.0f MiB | %.1f s, %.0f MiB |' "$n" "$solver" \
    "$([ "$tree" -gt 0 ] && echo "tree recursion" || echo "dense Cholesky")" "$ops" \
    "$(awk -v a="$total" -v b="$calls" 'BEGIN { print a / b }')" "$gen_s" "$(awk -v k="$gen_kb" 'BEGIN { print k / 1024 }')" \
    "$cc_s" "$(awk -v k="$cc_kb" 'BEGIN { print k / 1024 }')"
}

agree() {  # N -> agreement of the auto and dense builds
  local n=$1 d="$WORK/$1_agree"
  mkdir -p "$d"
  g++ -std=c++17 -O2 -I include -I "$WORK/${n}_auto" -I "$WORK/${n}_dense" -DMODEL_A="chain${n}_auto" \
    -DMODEL_B="chain${n}_dense" -DHEADER_A="\"chain${n}_auto/chain${n}_auto.hpp\"" \
    -DHEADER_B="\"chain${n}_dense/chain${n}_dense.hpp\"" bench/spatial_chain_driver.cpp \
    "$WORK/${n}_auto/chain${n}_auto/chain${n}_auto.cpp" "$WORK/${n}_dense/chain${n}_dense/chain${n}_dense.cpp" -o "$d/agree"
  "$d/agree" | sed -n 's/^agreement=//p'
}

OUT=bench/results/$KIND.md
{
  echo "| N | --solver | rhs | ops | instructions / call | generation (CPU, peak) | g++ -O2 (wall, peak) | auto vs dense |"
  echo "|---:|---|---|---:|---:|---:|---:|---:|"
} >"$OUT"
worst=0
for n in $NS; do
  row=$(measure "$n" auto)
  if [ "$n" -le "$DENSE_MAX_N" ]; then
    dense_row=$(measure "$n" dense)
    a=$(agree "$n")
    worst=$(awk -v a="$a" -v w="$worst" 'BEGIN { print (a > w) ? a : w }')
    echo "$row $a |" >>"$OUT"
    echo "$dense_row |" >>"$OUT"
  else
    echo "$row |" >>"$OUT"
  fi
done
cat "$OUT"
awk -v w="$worst" 'BEGIN { exit !(w <= 1e-10) }' || { echo "auto and dense disagree: $worst" >&2; exit 1; }
