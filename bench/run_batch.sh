#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-2.0-or-later
#
# Batched evaluation (docs/batched.md): ns per state of the generated rhs called state by
# state, through rhs_batch on one thread, and through rhs_batch on every core, with the
# agreement of the batched values with the serial ones (bits). Models: the four-bar (full
# state), the Whipple bicycle in joint coordinates (--state minimal) and the planar
# 32-link chain (bench/chain_model.py, --state minimal). Also the ensemble app
# (apps/batch_trajectories): RK4 steps per second of 4000 double pendulums on 1 and all
# cores, and instructions per state of the serial loop and the batch (callgrind). GPU figures: tests/cuda_build.sh runs the app's CUDA twin where a device exists.
#
#   bash bench/run_batch.sh     (from the repository root; ~2 min on 2 cores)
#
# Environment: N (states per batch, default 4000; a power of two makes the rows alias in the
# cache: see docs/batched.md), BUDGET (seconds per timing, default 1),
# MBSC_BIN (an mbsc binary instead of build/mbsc). Writes bench/results/batch.csv and
# prints it; scratch in bench/work/batch (ignored).
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$ROOT"
N=${N:-4000}
BUDGET=${BUDGET:-1}
MBSC=${MBSC_BIN:-build/mbsc}
WORK=bench/work/batch
mkdir -p "$WORK" bench/results
if [ -z "${MBSC_BIN:-}" ]; then
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build build -j"$(nproc)" --target mbsc batch_trajectories >/dev/null
fi
/usr/bin/python3 bench/chain_model.py 32 "$WORK/chain32.mbs"
gen() {  # gen MODEL NAME [flags]
  local model=$1 name=$2; shift 2
  "$MBSC" generate "$model" -o "$WORK" --name "$name" --force --quiet "$@"
}
gen models/four_bar.mbs four_bar
gen models/whipple_bicycle_joints.mbs bicycle_joints --state minimal
gen "$WORK/chain32.mbs" chain32 --state minimal
csv=bench/results/batch.csv
echo "model,states,threads,serial_ns_per_state,batch_1_thread_ns,batch_all_threads_ns,largest_difference,differing_values,failed_states,serial_instructions_per_state,batch_instructions_per_state" > "$csv"
for name in four_bar bicycle_joints chain32; do
  g++ -std=c++17 -O2 -march=x86-64 -Iinclude -I"$WORK" -DMODEL_HEADER="\"$name/$name.hpp\"" -DMODEL_NS="$name" \
      -DMODEL_NAME="\"$name\"" bench/batch_driver.cpp "$WORK/$name/$name.cpp" -pthread -o "$WORK/batch_$name"
  line=$("$WORK/batch_$name" "$N" "$BUDGET")
  # Instructions per state (callgrind; the load-independent figure): 256 states, each
  # pass run 3 times.
  ir() {
    valgrind --tool=callgrind --callgrind-out-file="$WORK/cg_${name}_$1.out" --collect-atstart=no \
      --toggle-collect="*$1*" "$WORK/batch_$name" 256 0 >/dev/null 2>&1
    awk '/^summary:/ { printf "%.0f", $2 / (3 * 256) }' "$WORK/cg_${name}_$1.out"
  }
  echo "$line,$(ir serial_pass),$(ir batch_pass)" | tee -a "$csv"
done
echo "ensemble app (4000 double pendulums, 2000 RK4 steps):"
build/apps/batch_trajectories 4000 2000 1
build/apps/batch_trajectories 4000 2000 0
