#!/usr/bin/env bash
# Stiff runs to tolerance (issue 26, item 3): BDF with CVODE's projection on a stiff
# constrained model (tests/data/stiff/stiff_pendulums.mbs), its error against the
# tolerance next to the explicit methods (mbsc bench, work-precision plot), and BDF
# without projection (--projection off, what auto was before) against a DOP853
# reference at rtol 1e-12. The figures of docs/benchmarks.md, "Stiff runs to tolerance".
# Writes bench/results/stiff_projection.txt, stiff_projection.csv and stiff_projection.svg.
#   bash bench/run_stiff_projection.sh
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target mbsc >/dev/null
MBSC=./build/mbsc
M=tests/data/stiff/stiff_pendulums.mbs
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
out=bench/results/stiff_projection.txt
{
  echo "# $(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p')"
  echo "## mbsc bench $M --t-end 2 --formulations complement --integrators bdf dopri5 dop853 --tolerances 1e-4 1e-6 1e-8 1e-10"
  "$MBSC" bench "$M" --t-end 2 --formulations complement --integrators bdf dopri5 dop853 \
    --tolerances 1e-4 1e-6 1e-8 1e-10 --min-cpu 0.05 -q \
    -o bench/results/stiff_projection.csv --plot bench/results/stiff_projection.svg 2>&1
  echo "## bdf with CVODE's projection (auto) and without (off): final error against dop853 at rtol 1e-12"
  "$MBSC" run "$M" --t-end 2 --integrator dop853 --rtol 1e-12 --atol 1e-14 -o "$tmp/ref.csv" -q
  for proj in auto off; do
    for tol in 1e-4 1e-6 1e-8 1e-10 1e-12; do
      atol=$(awk -v t="$tol" 'BEGIN { printf "%g", t / 100 }')
      if "$MBSC" run "$M" --t-end 2 --integrator bdf --rtol "$tol" --atol "$atol" --projection "$proj" \
           -o "$tmp/bdf.csv" 2> "$tmp/log"; then
        err=$(paste -d, <(tail -1 "$tmp/ref.csv") <(tail -1 "$tmp/bdf.csv") | awk -F, '{
          n = (NF) / 2; e = 0; for (i = 2; i <= 13; i++) { d = $i - $(i + n); if (d < 0) d = -d; if (d > e) e = d } printf "%.3g", e }')
        res=$(sed -n 's/.*(at step ends \([^)]*\)).*/\1/p' "$tmp/log")
        steps=$(sed -n 's/.*: \([0-9]*\) steps.*/\1/p' "$tmp/log")
        echo "projection $proj | rtol $tol | steps $steps | final error $err | step-end residuals $res"
      else
        echo "projection $proj | rtol $tol | failed: $(sed -n 's/^mbsc: error: //p' "$tmp/log")"
      fi
    done
  done
} | tee "$out"
