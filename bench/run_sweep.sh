#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-2.0-or-later
#
# `mbsc sweep` (docs/sweep.md): throughput on 1 thread and on every core, and peak memory
# as the number of rows grows. Runs the Whipple bicycle in joint coordinates (its roll
# rate sampled) and the four-bar (its crank torque on a grid):
#   1. ROWS rows of T_END s on 1 thread and on $(nproc) threads: wall time, rows per
#      second, the speed-up against the ideal (threads x the 1-thread rate; target 0.9),
#      and whether both tables are the same bytes;
#   2. 1 000, 10 000 and 100 000 rows of 0.01 s: wall time and peak resident memory
#      (GNU time), which must not grow with the rows;
#   3. where mbsc was built with MPI and mpirun exists: the bicycle's ROWS rows on N local
#      threads against `mpirun -n N` ranks of one thread (N = 2, and 3 oversubscribed on 2
#      cores), REPEAT times each, alternating: the median of the whole command (the launch
#      included) and of the sweep itself (the time its summary line reports: rows only),
#      CPU seconds, and whether the tables are the same bytes (target: the sweep itself
#      within 5 % of the local one at 3 ranks).
#
#   bash bench/run_sweep.sh     (from the repository root; ~5 min on 2 cores)
#
# Environment: ROWS (default 2000), T_END (default 2), REPEAT (default 3), PARTS (default
# "1 2 3": which of the parts above run), MBSC_BIN (an mbsc binary instead of
# build/mbsc). Writes bench/results/sweep.csv and prints it; scratch in bench/work/sweep.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$ROOT"
ROWS=${ROWS:-2000}
T_END=${T_END:-2}
REPEAT=${REPEAT:-3}
PARTS=${PARTS:-1 2 3}
part() { [[ " $PARTS " == *" $1 "* ]]; }
MBSC=${MBSC_BIN:-build/mbsc}
WORK=bench/work/sweep
mkdir -p "$WORK" bench/results
if [ -z "${MBSC_BIN:-}" ]; then
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build build -j"$(nproc)" --target mbsc >/dev/null
fi
[ -x /usr/bin/time ] || { echo "run_sweep: needs GNU time (apt-get install time)" >&2; exit 1; }
CACHE="--cache-dir $WORK/cache"
cores=$(nproc)
csv=bench/results/sweep.csv
part 1 || part 2 && echo "case,model,rows,t_end,threads,wall_s,rows_per_s,speedup,ideal_fraction,peak_rss_mib,same_table" > "$csv"
measure() {  # measure CASE MODEL ROWS T_END THREADS OUT ARGS...
  local case=$1 model=$2 rows=$3 t_end=$4 threads=$5 out=$6; shift 6
  rm -f "$out" "$out.partial"
  /usr/bin/time -f "%e %M" -o "$WORK/time.txt" "$MBSC" sweep "$model" $CACHE --t-end "$t_end" --threads "$threads" \
    -o "$out" -q "$@"
  read -r wall rss < "$WORK/time.txt"
  echo "$wall $rss"
}
# Compile once (not timed).
"$MBSC" sweep models/whipple_bicycle_joints.mbs $CACHE --grid rear_frame.wx=0.5 --t-end 0.01 -o "$WORK/warm.csv" -q
"$MBSC" sweep models/four_bar.mbs $CACHE --grid tau0=0 --t-end 0.01 -o "$WORK/warm.csv" -q
part 1 && for model in whipple_bicycle_joints four_bar; do
  if [ $model = four_bar ]; then
    swept=(--grid "tau0=0:1:$(awk -v n="$ROWS" 'BEGIN { printf "%.12g", 1 / (n - 1) }')")
  else
    swept=(--sample 'rear_frame.wx~uniform(0,1)' -n "$ROWS")
  fi
  read -r w1 r1 < <(measure throughput models/$model.mbs "$ROWS" "$T_END" 1 "$WORK/${model}_1.csv" "${swept[@]}")
  read -r wn rn < <(measure throughput models/$model.mbs "$ROWS" "$T_END" "$cores" "$WORK/${model}_n.csv" "${swept[@]}")
  same=no; cmp -s "$WORK/${model}_1.csv" "$WORK/${model}_n.csv" && same=yes
  rows=$(( $(wc -l < "$WORK/${model}_1.csv") - 1 ))
  awk -v m="$model" -v n="$rows" -v t="$T_END" -v c="$cores" -v w1="$w1" -v wn="$wn" -v r1="$r1" -v rn="$rn" -v s="$same" 'BEGIN {
    printf "throughput,%s,%d,%s,1,%.2f,%.1f,1,1,%.0f,%s\n", m, n, t, w1, n / w1, r1 / 1024, s
    printf "throughput,%s,%d,%s,%d,%.2f,%.1f,%.2f,%.2f,%.0f,%s\n", m, n, t, c, wn, n / wn, w1 / wn, w1 / wn / c, rn / 1024, s }' \
    | tee -a "$csv"
done
part 2 && for rows in 1000 10000 100000; do
  read -r w r < <(measure memory models/whipple_bicycle_joints.mbs "$rows" 0.01 "$cores" "$WORK/memory.csv" \
                    --sample 'rear_frame.wx~uniform(0,1)' -n "$rows")
  awk -v n="$rows" -v c="$cores" -v w="$w" -v r="$r" 'BEGIN {
    printf "memory,whipple_bicycle_joints,%d,0.01,%d,%.2f,%.0f,,,%.0f,\n", n, c, w, n / w, r / 1024 }' | tee -a "$csv"
done
# 3. MPI against local threads.
part 3 || exit 0
mpirun_cmd=(mpirun --oversubscribe)
[ "$(id -u)" -eq 0 ] && mpirun_cmd+=(--allow-run-as-root)
if ! command -v mpirun >/dev/null ||
   ! "${mpirun_cmd[@]}" -n 2 "$MBSC" sweep models/four_bar.mbs $CACHE --grid tau0=0,1 --t-end 0.01 -o "$WORK/warm.csv" -q \
     >/dev/null 2>&1; then
  echo "run_sweep: no mpirun, or this mbsc was built without MPI: the MPI part is skipped"
  exit 0
fi
mpi_csv=bench/results/sweep_mpi.csv
echo "model,rows,t_end,n,launch,command_s,sweep_s,cpu_s,same_table" > "$mpi_csv"
sweep_args=(models/whipple_bicycle_joints.mbs $CACHE --t-end "$T_END" --sample 'rear_frame.wx~uniform(0,1)' -n "$ROWS")
median() { sort -g | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }'; }
for n in 2 3; do
  for launch in local mpirun; do : > "$WORK/$launch.times"; done
  for ((k = 0; k < REPEAT; ++k)); do
    for launch in local mpirun; do
      out="$WORK/${launch}_$n.csv"
      rm -f "$out"
      if [ $launch = local ]; then
        cmd=("$MBSC" sweep "${sweep_args[@]}" --threads "$n" -o "$out")
      else
        cmd=("${mpirun_cmd[@]}" -n "$n" "$MBSC" sweep "${sweep_args[@]}" -o "$out")
      fi
      /usr/bin/time -f "%e %U %S" -o "$WORK/time.txt" "${cmd[@]}" 2> "$WORK/summary.txt"
      sweep_s=$(sed -n 's/.* in \([0-9.e+-]*\) s, .*/\1/p' "$WORK/summary.txt" | tail -1)
      read -r wall user sys < "$WORK/time.txt"
      echo "$wall $sweep_s $(awk -v u="$user" -v s="$sys" 'BEGIN { print u + s }')" >> "$WORK/$launch.times"
    done
  done
  same=no; cmp -s "$WORK/local_$n.csv" "$WORK/mpirun_$n.csv" && same=yes
  for launch in local mpirun; do
    c=$(cut -d' ' -f1 "$WORK/$launch.times" | median)
    w=$(cut -d' ' -f2 "$WORK/$launch.times" | median)
    u=$(cut -d' ' -f3 "$WORK/$launch.times" | median)
    echo "whipple_bicycle_joints,$ROWS,$T_END,$n,$launch,$c,$w,$u,$same" | tee -a "$mpi_csv"
  done
done
