#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-2.0-or-later
#
# Speed against error on every shipped closed-loop model, mbsc beside Simbody, in one
# run of `mbsc bench` per model (docs/benchmarks.md, "Speed against error"):
#   bash bench/run_mbsc_bench.sh [MODEL ...]          (repository root, after a build)
# For each model it starts mbsc from the initial state the Simbody peer uses
# (bench/simbody/initial_states.txt: the `=` entries; the model's own guesses pick the
# same branch), measures the error on the coordinates and speeds Simbody reports, and
# reads Simbody's rows from bench/results/simbody_<model>.csv (bash bench/run_simbody.sh
# writes them) so both tools are measured against the same reference run.
# Writes bench/results/wp_<model>.csv and .md, docs/figures/wp_<model>.svg, and
# bench/results/wp_ratios.md (CPU time to reach a final error of 1e-6 and 1e-9, best
# method of each tool, and their ratio).
#   env: MBSC (default build/mbsc), T_END (5), TOLS, INTEGRATORS, MIN_CPU (0.2)
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$ROOT"
MBSC=${MBSC:-build/mbsc}
T_END=${T_END:-5}
TOLS=${TOLS:-1e-3,1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10,1e-11,1e-12}
INTEGRATORS=${INTEGRATORS:-dopri5,dop853,bdf}
MIN_CPU=${MIN_CPU:-0.2}
MODELS=("$@")
[ ${#MODELS[@]} -eq 0 ] && MODELS=(four_bar four_bar_toggle slider_crank five_bar whitworth three_rrr parallelogram_chain)
mkdir -p bench/results docs/figures
for m in "${MODELS[@]}"; do
  line=$(grep -E "^$m[[:space:]]" bench/simbody/initial_states.txt)
  inits=()
  for item in $line; do
    case "$item" in *=*) inits+=(--init "$item");; esac
  done
  peer=bench/results/simbody_$m.csv
  cols=$(head -1 "$peer" | cut -d, -f15- )
  echo "== $m (${inits[*]}; error on $cols)"
  "$MBSC" bench "models/$m.mbs" --t-end "$T_END" "${inits[@]}" --error-columns "$cols" \
    --integrators "$INTEGRATORS" --tolerances "$TOLS" --min-cpu "$MIN_CPU" --peer "$peer" \
    -o "bench/results/wp_$m.csv" --plot "docs/figures/wp_$m.svg" > "bench/results/wp_$m.md"
done
{
  echo "# CPU time to reach a final-state error (best method of each tool), $(date -u +%Y-%m-%d), $(nproc) cores"
  echo "# $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), load $(cut -d' ' -f1-3 /proc/loadavg)"
  /usr/bin/python3 - "${MODELS[@]}" <<'PY'
import csv, sys
print("| model | target | mbsc CPU s (method) | Simbody CPU s (method) | Simbody / mbsc |")
print("|---|---|---|---|---|")
for m in sys.argv[1:]:
    rows = list(csv.DictReader(open(f"bench/results/wp_{m}.csv")))
    for target in (1e-6, 1e-9):
        best = {}
        for r in rows:
            if r["status"] != "ok":
                continue
            try:
                e, c = float(r["err_final"]), float(r["cpu_s"])
            except ValueError:
                continue
            if e <= target and c > 0:
                tool = r["tool"]
                label = f'{r["formulation"]} {r["method"]}' if tool == "mbsc" else r["method"]
                if tool not in best or c < best[tool][0]:
                    best[tool] = (c, label)
        a, b = best.get("mbsc"), best.get("simbody")
        fa = f"{a[0]:.3g} ({a[1]})" if a else "not reached"
        fb = f"{b[0]:.3g} ({b[1]})" if b else "not reached"
        ratio = f"{b[0] / a[0]:.0f}x" if a and b else "-"
        print(f"| {m} | {target:.0e} | {fa} | {fb} | {ratio} |")
PY
} > bench/results/wp_ratios.md
cat bench/results/wp_ratios.md
