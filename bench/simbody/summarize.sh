#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-2.0-or-later
# Work-precision summary of the Simbody runs (bench/results/simbody_<model>.csv, written by
# bench/run_simbody.sh): the error of each run's final state against a reference computed
# by the mbsc-generated model (bench/simbody/mbsc_reference.cpp: RK4, h = 2.5e-5; its own
# error is estimated as its difference from h = 5e-5 and printed with it), and the least
# CPU time Simbody needs for a final-state error of 1e-6 and 1e-9.
# Writes bench/results/simbody_summary.md. Usage (repository root, mbsc built in BUILD):
#   bash bench/simbody/summarize.sh [MODEL ...]
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD=${BUILD:-build}
SB=${SB_BUILD:-build-simbody}
MODELS=("$@")
[ ${#MODELS[@]} -gt 0 ] || MODELS=(four_bar four_bar_toggle slider_crank five_bar whitworth three_rrr parallelogram_chain)
cmake -S bench/simbody -B "$SB" -DCMAKE_BUILD_TYPE=Release -DMBSC_EXE="$PWD/$BUILD/mbsc" > /dev/null
cmake --build "$SB" -j2 > /dev/null
out=bench/results/simbody_summary.md
{
  echo "Error = max over the independent coordinates and speeds of |final value - reference| at t_end;"
  echo "reference: mbsc-generated model, RK4 h = 2.5e-5 (its error estimate: |h = 2.5e-5 - h = 5e-5|)."
  echo
  echo "| model | t_end | reference error | method | best CPU (s) for error ≤ 1e-6 | best CPU (s) for error ≤ 1e-9 |"
  echo "|---|---:|---:|---|---:|---:|"
} > "$out.head"
: > "$out.body"
for m in "${MODELS[@]}"; do
  csv=bench/results/simbody_$m.csv
  [ -f "$csv" ] || { echo "summarize: no $csv (run bench/run_simbody.sh)" >&2; continue; }
  t_end=$(awk -F, 'NR == 2 { print $5 }' "$csv")
  ref=$("$SB/mbsc_reference_$m" "$t_end" "$t_end" 2.5e-5 2> /dev/null | tail -1)
  ref2=$("$SB/mbsc_reference_$m" "$t_end" "$t_end" 5e-5 2> /dev/null | tail -1)
  referr=$(awk -F, -v a="$ref" -v b="$ref2" 'BEGIN { n = split(a, x, ","); split(b, y, ",");
    for (i = 2; i <= n; ++i) { d = x[i] - y[i]; if (d < 0) d = -d; if (d > w) w = d } printf "%.1e", w }')
  awk -F, -v ref="$ref" -v m="$m" -v t="$t_end" -v referr="$referr" -v body="$out.body" '
    BEGIN { n = split(ref, r, ",") }
    NR == 1 { next }
    {
      err = 0; for (i = 2; i <= n; ++i) { d = $(13 + i) - r[i]; if (d < 0) d = -d; if (d > err) err = d }
      printf "| %s | %s | %s | %.3g | %d | %d | %.2e | %.2e |\n", m, $3, $4, $6 * 1000, $8, $10, err, $12 >> body
      if (err <= 1e-6 && (!(($3) in b6) || $6 < b6[$3])) b6[$3] = $6
      if (err <= 1e-9 && (!(($3) in b9) || $6 < b9[$3])) b9[$3] = $6
      seen[$3] = 1
    }
    END {
      for (k in seen) printf "| %s | %s | %s | %s | %s | %s |\n", m, t, referr, k, (k in b6 ? sprintf("%.3g", b6[k]) : "not reached"), (k in b9 ? sprintf("%.3g", b9[k]) : "not reached")
    }' "$csv" | sort >> "$out.head"
done
{
  cat "$out.head"
  echo
  echo "Every run:"
  echo
  echo "| model | method | tol | cpu (ms) | steps | rhs_evals | final error | pos_residual |"
  echo "|---|---|---:|---:|---:|---:|---:|---:|"
  cat "$out.body"
} > "$out"
rm -f "$out.head" "$out.body"
cat "$out"
