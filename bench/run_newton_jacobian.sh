#!/usr/bin/env bash
# The Newton matrices of bdf and ark-dirk from the generated rhs_jacobian against
# difference quotients (issue 27, part 2): each stiff model integrated by each method
# with --newton-jacobian generated, differences and sundials; steps, rhs calls,
# Jacobians, Newton iterations and failures, CPU time (mbsc run's summary line), and the
# final error against DOP853 at rtol 1e-12 (largest difference over the state).
# The figures of docs/benchmarks.md, "Implicit integration with the generated Jacobian".
# Writes bench/results/newton_jacobian.txt.
#   bash bench/run_newton_jacobian.sh
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target mbsc >/dev/null
MBSC=./build/mbsc
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
out=bench/results/newton_jacobian.txt
# model, t_end, extra run options
models=(
  "models/stiff_spring_damper.mbs 2"
  "tests/data/stiff/stiff_pendulums.mbs 2"
  "tests/data/determinism/flyball.mbs 1"
)
{
  echo "# $(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p')"
  for entry in "${models[@]}"; do
    read -r M T <<<"$entry"
    "$MBSC" run "$M" --t-end "$T" --integrator dop853 --rtol 1e-12 --atol 1e-14 -o "$tmp/ref.csv" -q
    for method in bdf ark-dirk; do
      for tol in 1e-6 1e-9; do
        atol=$(awk -v t="$tol" 'BEGIN { printf "%g", t / 100 }')
        for source in generated differences sundials; do
          # Compiled (and cached) first, so that CPU time is the integration's.
          "$MBSC" run "$M" --t-end "$T" --integrator "$method" --rtol "$tol" --atol "$atol" \
            --newton-jacobian "$source" -o "$tmp/run.csv" -q 2>/dev/null || true
          if "$MBSC" run "$M" --t-end "$T" --integrator "$method" --rtol "$tol" --atol "$atol" \
               --newton-jacobian "$source" -o "$tmp/run.csv" 2> "$tmp/log"; then
            err=$(paste -d, <(tail -1 "$tmp/ref.csv") <(tail -1 "$tmp/run.csv") | awk -F, '{
              n = NF / 2; e = 0; for (i = 2; i <= n; i++) { d = $i - $(i + n); if (d < 0) d = -d; if (d > e) e = d } printf "%.2g", e }')
            summary=$(sed -n 's/^mbsc: [^ ]* [^ ]* t = [^:]*: //p' "$tmp/log" | head -1)
            echo "$M | $method | rtol $tol | $source | $summary | final error $err"
          else
            echo "$M | $method | rtol $tol | $source | failed: $(sed -n 's/^mbsc: error: //p' "$tmp/log" | head -1)"
          fi
        done
      done
    done
  done
} | tee "$out"
