#!/usr/bin/env bash
# Constraints redundant on the mechanism (issue 26, item 1): Bricard's linkage (IFToMM
# A04) and the parallelogram with a third crank, 10 s with `mbsc run` in both
# formulations at a tight tolerance, and the non-redundant Bricard twin for 2 s. The
# figures of docs/benchmarks.md, "Hard cases: redundant constraints". Writes
# bench/results/redundant.txt (each run's summary lines).
#   bash bench/run_redundant.sh
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target mbsc >/dev/null
MBSC=./build/mbsc
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
out="bench/results/redundant.txt"
run() {  # label, model, mbsc run options
  local label=$1 model=$2
  shift 2
  echo "## $label: mbsc run $model $*"
  "$MBSC" run "$model" "$@" -o "$tmp/out.csv" 2>&1 | sed -n 's/^mbsc: //p' | grep -v "^compiled\|^wrote"
  echo "final state: $(tail -1 "$tmp/out.csv" | cut -d, -f1-8)"
}
{
  echo "# $(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p')"
  B=tests/data/redundant/bricard.mbs
  P=tests/data/linear/parallelogram_redundant.mbs
  run "Bricard, complement" $B --t-end 10 --integrator dop853 --rtol 1e-11 --atol 1e-13
  run "Bricard, multipliers" $B --formulation multipliers --t-end 10 --integrator dop853 --rtol 1e-12 --atol 1e-14
  run "Bricard, complement, 2 s" $B --t-end 2 --integrator dop853 --rtol 1e-11 --atol 1e-13
  run "Bricard twin (no redundancy), 2 s" tests/data/redundant/bricard_twin.mbs --t-end 2 --integrator dop853 --rtol 1e-11 --atol 1e-13
  run "parallelogram + third crank, complement" $P --t-end 10 --integrator dop853 --rtol 1e-11 --atol 1e-13
  run "parallelogram + third crank, multipliers" $P --formulation multipliers --t-end 10 --integrator dop853 --rtol 1e-11 --atol 1e-13
  run "parallelogram + third crank, minimal state" $P --state minimal --t-end 10 --integrator dop853 --rtol 1e-11 --atol 1e-13
} | tee "$out"
