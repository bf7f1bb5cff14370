#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-2.0-or-later
#
# Callgrind instructions per rhs call of the planar mechanisms' generated code, for one
# or two mbsc binaries side by side (before/after a change to the code generator):
#   bash bench/count_rhs.sh BUILD/mbsc [OTHER/mbsc]      (from the repository root)
# MODELS (default: four_bar five_bar slider_crank whitworth three_rrr parallelogram_chain)
# and BUILDS (default: "complement minimal multipliers") choose what is counted. Every
# build is compiled with g++ -std=c++17 -O2 -march=x86-64 together with
# bench/rhs_count_driver.cpp, which calls rhs at 20 fixed states through count_calls();
# instructions per call = callgrind's total inside count_calls / 20. Prints a Markdown
# table (model, build, rhs ops and instructions per binary). Scratch: bench/work/count/.
# SYMPY=1 adds a "sympy" row under each planar mechanism sympy's peer knows (four_bar
# slider_crank whitworth three_rrr): bench/sympy_planar.py's generated mass_forcing plus
# the driver's o x o LU (the rhs bench/planar_driver.cpp times), compiled the same way with
# bench/rhs_count_sympy_driver.cpp (same 20 states, in sympy's coordinates); its ops are
# mbsc's convention on sympy's CSE'd expressions plus o^3/3 + o^2 for the LU, as in
# bench/run_planar.sh. Needs /usr/bin/python3 with sympy. With two binaries the sympy
# row repeats its figures in both columns (it does not depend on mbsc).
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$ROOT"
[ $# -ge 1 ] || { echo "usage: bash bench/count_rhs.sh MBSC [MBSC2]" >&2; exit 2; }
MODELS=${MODELS:-"four_bar five_bar slider_crank whitworth three_rrr parallelogram_chain"}
BUILDS=${BUILDS:-"complement minimal multipliers"}
WORK=${COUNT_WORK:-bench/work/count}   # COUNT_WORK: another scratch folder
MBSC_A=$1
rm -rf "$WORK"; mkdir -p "$WORK"
flags() { case $1 in complement) echo "";; minimal) echo "--state minimal";; multipliers) echo "--formulation multipliers";; esac; }
count() {  # mbsc index model build -> "ops instructions"
  local mbsc=$1 i=$2 m=$3 b=$4
  local d="$WORK/$i"
  mkdir -p "$d"
  # shellcheck disable=SC2046
  "$mbsc" generate "models/$m.mbs" -o "$d" --name "${m}_$b" $(flags "$b") >/dev/null
  local ops
  ops=$(sed -n 's|^//   rhs: .*total \([0-9]*\)$|\1|p' "$d/${m}_$b/${m}_$b.cpp")
  g++ -std=c++17 -O2 -march=x86-64 -I include -I "$d" -DMODEL="${m}_$b" -DHEADER="\"${m}_$b/${m}_$b.hpp\"" \
    bench/rhs_count_driver.cpp "$d/${m}_$b/${m}_$b.cpp" -o "$d/count_${m}_$b"
  valgrind --tool=callgrind --toggle-collect='*count_calls*' --callgrind-out-file="$d/cg.${m}_$b" \
    "$d/count_${m}_$b" >"$d/out_${m}_$b.txt" 2>"$d/cg_${m}_$b.log"
  local total calls
  total=$(sed -n 's/.*Collected : \([0-9]*\).*/\1/p' "$d/cg_${m}_$b.log")
  calls=$(sed -n 's/^count_calls=//p' "$d/out_${m}_$b.txt")
  echo "$ops $(awk -v a="$total" -v b="$calls" 'BEGIN { printf "%.0f", a / b }')"
}
count_sympy() {  # model -> "ops instructions" of sympy's rhs, or "" when sympy has no such model
  local m=$1 d="$WORK/sympy"
  case $m in four_bar | slider_crank | whitworth | three_rrr) ;; *) return 0 ;; esac
  mkdir -p "$d"
  /usr/bin/python3 bench/sympy_planar.py "$m" "$d" >"$d/$m.log" 2>&1
  local o conv
  read -r o conv < <(/usr/bin/python3 -c '
import json, sys
d = json.load(open(sys.argv[1]))
print(d["speeds"], d["ops_mbsc_conv"])' "$d/sympy_$m.json")
  # the header of mbsc's complement build names the parameters and inputs sympy reads
  "$MBSC_A" generate "models/$m.mbs" -o "$d" --name "$m" >/dev/null
  g++ -std=c++17 -O2 -march=x86-64 -I include -I "$d" -DMODEL="$m" -DHEADER="\"$m/$m.hpp\"" -DSYMPY_NQ="$o" \
    bench/rhs_count_sympy_driver.cpp -x c++ "$d/sympy_$m.c" -o "$d/count_$m"
  valgrind --tool=callgrind --toggle-collect='*count_calls*' --callgrind-out-file="$d/cg.$m" \
    "$d/count_$m" >"$d/out_$m.txt" 2>"$d/cg_$m.log"
  local total calls
  total=$(sed -n 's/.*Collected : \([0-9]*\).*/\1/p' "$d/cg_$m.log")
  calls=$(sed -n 's/^count_calls=//p' "$d/out_$m.txt")
  echo "$((conv + $(awk -v n="$o" 'BEGIN { printf "%d", n * n * n / 3.0 + n * n + 0.5 }'))) $(awk -v a="$total" -v b="$calls" 'BEGIN { printf "%.0f", a / b }')"
}
if [ $# -ge 2 ]; then
  echo "| model | build | rhs ops, A | rhs ops, B | instructions / call, A | instructions / call, B | B / A |"
  echo "|---|---|---:|---:|---:|---:|---:|"
else
  echo "| model | build | rhs ops | instructions / call |"
  echo "|---|---|---:|---:|"
fi
for m in $MODELS; do
  for b in $BUILDS; do
    read -r oa ia < <(count "$1" a "$m" "$b")
    if [ $# -ge 2 ]; then
      read -r ob ib < <(count "$2" b "$m" "$b")
      echo "| $m | $b | $oa | $ob | $ia | $ib | $(awk -v a="$ia" -v b="$ib" 'BEGIN { printf "%.3f", b / a }') |"
    else
      echo "| $m | $b | $oa | $ia |"
    fi
  done
  if [ -n "${SYMPY:-}" ]; then
    read -r os is < <(count_sympy "$m") || true
    if [ -n "${os:-}" ]; then
      if [ $# -ge 2 ]; then echo "| $m | sympy | $os | $os | $is | $is | 1.000 |"; else echo "| $m | sympy | $os | $is |"; fi
    fi
    os="" is=""
  fi
done
