#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-2.0-or-later
# `mbsc sweep` under MPI (ctest entry sweep_mpi, where mbsc was built with MPI): the table
# and trajectories of `mpirun --oversubscribe -n 3 mbsc sweep ...` equal the local ones
# byte for byte, and so do the table of 300 short rows over 4 ranks of 2 threads and rows
# of eigenvalues (--eig); bad input gives one message and no table; a sweep stopped by
# its time budget keeps the right rows; a sweep killed under MPI after 4 rows continues
# under MPI to the same table and trajectories, and one continued without mpirun too.
#   sweep_mpi.sh MBSC WORK_DIR
set -euo pipefail
mbsc=$1 work=$2
rm -rf "$work"
mkdir -p "$work"
cd "$work"
cat > pend.mbs <<'MODEL'
model pend
parameter l = 1.5, m = 2, g = 9.81
gravity (0, -g)
body b : particle2d { mass m }
subsystem arm {
  coordinate th
  speed w = th'
}
constraint position { b.x - l*sin(arm.th) = 0; b.y + l*cos(arm.th) = 0 }
independent arm.w
initial arm.th = 2.5
output angle = arm.th
MODEL
mpirun_cmd=(mpirun --oversubscribe)
[ "$(id -u)" -eq 0 ] && mpirun_cmd+=(--allow-run-as-root)
sweep=("$mbsc" sweep pend.mbs --cache-dir cache --grid l=1:2:0.25 --sample 'arm.th~normal(1,0.2)' -n 4 --t-end 0.5
       --summary final,max:energy_change -q)
"${sweep[@]}" -o local.csv --trajectories local_traj
"${mpirun_cmd[@]}" -n 3 "${sweep[@]}" -o mpi.csv --trajectories mpi_traj
cmp local.csv mpi.csv
diff -r local_traj mpi_traj
echo "sweep_mpi: 3 ranks: the same $(($(wc -l < mpi.csv) - 1)) rows and trajectories as the local sweep"
# Many short rows over 4 ranks of 2 threads (rows handed out many times, in batches).
many=("$mbsc" sweep pend.mbs --cache-dir cache --sample 'arm.th~uniform(0.5,2.5)' --sample 'l~loguniform(0.5,2)' -n 300
      --t-end 0.05 --summary max:angle -q)
"${many[@]}" -o many_local.csv
"${mpirun_cmd[@]}" -n 4 --bind-to none "${many[@]}" --threads 2 -o many_mpi.csv
cmp many_local.csv many_mpi.csv
echo "sweep_mpi: 4 ranks of 2 threads: the same $(($(wc -l < many_mpi.csv) - 1)) rows"
# Rows of eigenvalues (--eig) over 3 ranks.
eig=("$mbsc" sweep pend.mbs --cache-dir cache --eig --grid l=0.5:2:0.1 --grid arm.th=0,3.141592653589793 -q)
"${eig[@]}" -o eig_local.csv
"${mpirun_cmd[@]}" -n 3 "${eig[@]}" -o eig_mpi.csv
cmp eig_local.csv eig_mpi.csv
echo "sweep_mpi: --eig over 3 ranks: the same $(($(wc -l < eig_mpi.csv) - 1)) rows"
# Bad input under MPI: one message (from rank 0), exit code 1, no table.
if "${mpirun_cmd[@]}" -n 3 "$mbsc" sweep pend.mbs --cache-dir cache --grid nosuch=1:2:0.5 -o bad.csv 2> bad.err; then
  echo "sweep_mpi: a sweep of an unknown parameter succeeded" >&2
  exit 1
fi
[ "$(grep -c "nosuch" bad.err)" -eq 1 ] || { cat bad.err >&2; echo "sweep_mpi: not one message" >&2; exit 1; }
[ ! -e bad.csv ] && [ ! -e bad.csv.partial ]
echo "sweep_mpi: bad input: one message, no table"
# The time budget under MPI: a sweep far too long for it stops (exit 1, no hang), and the
# rows it kept are those of the same rows run locally.
long=("$mbsc" sweep pend.mbs --cache-dir cache --sample 'arm.th~uniform(0.5,2.5)' --t-end 5 --summary final -q)
if timeout 120 "${mpirun_cmd[@]}" -n 3 "${long[@]}" -n 1000000 --budget 2 -o budget.csv 2> budget.err; then
  echo "sweep_mpi: a million rows fit in 2 s" >&2
  exit 1
fi
grep -q "ran out of its time budget" budget.err || { cat budget.err >&2; exit 1; }
kept=$(($(wc -l < budget.csv.partial) - 2))
[ "$kept" -gt 0 ] || { echo "sweep_mpi: no row in 2 s" >&2; exit 1; }
"${long[@]}" -n "$kept" -o kept.csv
cmp <(tail -n +3 budget.csv.partial) <(tail -n +2 kept.csv)
echo "sweep_mpi: stopped by its budget after $kept rows, the same as run alone"
# Killed under MPI after 4 rows (rank 0 ends as a kill would; mpirun ends the others).
if MBSC_SWEEP_ABORT_AFTER_ROWS=4 "${mpirun_cmd[@]}" -n 3 -x MBSC_SWEEP_ABORT_AFTER_ROWS "${sweep[@]}" -o resumed.csv \
     --trajectories resumed_traj \
     >/dev/null 2>&1; then
  echo "sweep_mpi: the killed sweep finished" >&2
  exit 1
fi
[ -f resumed.csv.partial ] && [ ! -f resumed.csv ]
[ "$(($(wc -l < resumed.csv.partial) - 2))" -eq 4 ]
"${mpirun_cmd[@]}" -n 3 "${sweep[@]}" -o resumed.csv --trajectories resumed_traj
cmp local.csv resumed.csv
diff -r local_traj resumed_traj
[ ! -f resumed.csv.partial ]
# Killed under MPI, continued alone.
MBSC_SWEEP_ABORT_AFTER_ROWS=7 "${mpirun_cmd[@]}" -n 3 -x MBSC_SWEEP_ABORT_AFTER_ROWS "${sweep[@]}" -o mixed.csv \
  >/dev/null 2>&1 || true
"${sweep[@]}" -o mixed.csv
cmp local.csv mixed.csv
echo "sweep_mpi: killed sweeps continued to the same table"
