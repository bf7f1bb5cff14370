#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-2.0-or-later
#
# The speed-versus-error comparison of docs/benchmarks.md in one run: Simbody's
# integrations of every closed-loop model (bench/run_simbody.sh), then `mbsc bench` on
# the same models from the same initial states, with Simbody's rows on the same plots
# (bench/run_mbsc_bench.sh), so the ratios come from one sitting on one machine.
#   bash bench/run_speed_vs_error.sh            (repository root, after a Release build)
# env: as the two scripts; by default Simbody runs its two Runge-Kutta pairs (its CPodes
# BDF fails on most of these models, bench/results/simbody_failures.txt).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
TOLS=${TOLS-"1e-4 1e-5 1e-6 1e-7 1e-8 1e-9 1e-10"} METHODS=${METHODS-"rkmerson rkfeldberg"} LOW_ORDER=${LOW_ORDER-""} \
  bash bench/run_simbody.sh "$@"
bash bench/run_mbsc_bench.sh "$@"
