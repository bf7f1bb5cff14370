#!/usr/bin/env bash
# IFToMM A02 (the 40-window parallelogram chain, tests/data/chain/iftomm_a02.mbs) through
# its 20 flat poses in 20 s with `mbsc run --continuation --integrator dop853` at three
# tolerances: steps, CPU, poses crossed, energy change, and the crank angle's error
# against the exact one-degree-of-freedom motion (bench/a02_reference.py). The figures of
# docs/benchmarks.md, "Hard cases: a chain through its flat poses".
# Writes bench/results/a02.txt.
#   bash bench/run_a02.sh
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target mbsc >/dev/null
MBSC=./build/mbsc
M=tests/data/chain/iftomm_a02.mbs
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
out=bench/results/a02.txt
"$MBSC" generate "$M" -o "$tmp/gen" -q  # compiled once before the timed runs
{
  echo "# $(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p')"
  for tol in 1e-8 1e-10 1e-12; do
    echo "## mbsc run $M --continuation --integrator dop853 --rtol $tol --atol $tol --t-end 20"
    "$MBSC" run "$M" --continuation --integrator dop853 --rtol "$tol" --atol "$tol" --t-end 20 -o "$tmp/a02.csv" 2>&1 |
      grep -E "steps|energy|continuation|residuals"
    /usr/bin/python3 bench/a02_reference.py "$tmp/a02.csv"
  done
} | tee "$out"
