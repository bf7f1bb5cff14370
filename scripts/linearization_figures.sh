#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-2.0-or-later
# The figures of docs/linearization.md, made with mbsc eig (and gnuplot):
#   docs/figures/bicycle_eig.svg           the benchmark bicycle's eigenvalues against speed
#   docs/figures/tricycle_eig.svg          the tadpole tricycle's (thesis section 5.2, Fig 5.4)
#   docs/figures/ring_disc_continuation.svg the ring-disc's steady angle and oscillation
#                                           frequency against the incline, several mass ratios
# Usage: MBSC=build/mbsc bash scripts/linearization_figures.sh
set -euo pipefail
cd "$(dirname "$0")/.."
MBSC=${MBSC:-build/mbsc}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
mkdir -p docs/figures

"$MBSC" eig models/whipple_bicycle_joints.mbs --sweep v=0:10:0.01 --let v=5 --init 'theta_R_dot=-v/rR' \
  --init rear_frame.wx=0 --init delta_dot=0 --keep rear_frame.theta,delta,rear_frame.wx,delta_dot \
  --ratio delta/rear_frame.theta -o "$out/bicycle.csv" --plot docs/figures/bicycle_eig.svg -q --cache-dir "$out/cache"

# The tadpole tricycle (its model is compiled in over a minute).
"$MBSC" eig tests/data/linear/tadpole_tricycle.mbs --sweep v=0:10:0.02 --let v=5 --init 'theta_W_dot=-v/rW' \
  --init rear_frame.wx=0 --init delta_dot=0 --keep rear_frame.theta,delta,rear_frame.wx,delta_dot \
  --ratio delta/rear_frame.theta -o "$out/tricycle.csv" --plot docs/figures/tricycle_eig.svg -q --cache-dir "$out/cache"

# Ring-disc (thesis Ex 4.2/4.7): the ring's mass fixed, the disc's mass m2 = ratio * m1.
plots_theta="" plots_omega=""
for ratio in 0.1194 0.5 1 2 4; do
  m2=$(awk -v r="$ratio" 'BEGIN { printf "%.17g", r * 0.67 }')  # m1 = 0.67 (the model's default)
  "$MBSC" eig models/ring_disc.mbs --sweep xi=0.05:1.5:0.005 --set "m2=$m2" --init theta=0.04 --find theta --steady dtheta \
    -o "$out/ring_disc_$ratio.csv" -q --cache-dir "$out/cache" > /dev/null
  plots_theta+="'$out/ring_disc_$ratio.csv' using 1:2 every ::1 with lines lw 1.5 title 'm2/m1 = $ratio', "
  plots_omega+="'$out/ring_disc_$ratio.csv' using 1:6 every ::1 with lines lw 1.5 title 'm2/m1 = $ratio', "
done
gnuplot <<GP
set terminal svg size 1000,700 noenhanced font 'sans,11' background '#ffffff'
set output 'docs/figures/ring_disc_continuation.svg'
set datafile separator ','
set grid
set key outside right
set multiplot layout 2,1 title 'ring_disc: steady motion and its oscillation against the incline xi'
set ylabel 'theta_bar, rad'
plot ${plots_theta%, }
set ylabel 'omega_bar, rad/s'
set xlabel 'xi, rad'
plot ${plots_omega%, }
unset multiplot
GP
echo "wrote docs/figures/bicycle_eig.svg docs/figures/ring_disc_continuation.svg"
