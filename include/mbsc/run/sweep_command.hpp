// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// `mbsc sweep MODEL --grid ... --sample ... -n N --summary ... -o TABLE.csv`
/// (docs/sweep.md): one `mbsc run` of the compiled model per row, each with its own
/// parameters and initial values, on every core; a table row per run (its values, its
/// seed, the summaries, status, residuals). Rows are appended to TABLE.csv.partial in row
/// order as they finish, so a killed sweep, run again with the same command, continues
/// where it stopped; TABLE.csv appears once every row is done. Exit codes: 0 the table is
/// complete (rows whose run failed say so in it), 1 a user error or a spent budget (the
/// partial table stays for the next run).
#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "mbsc/run/run_command.hpp"

namespace mbsc::run {

struct SweepArgs {
  RunArgs run;                         // the model and the options of each run (not its -o or plot)
  std::vector<std::string> grids;      // --grid NAME=FROM:TO:STEP | NAME=FROM:TO:logN | NAME=V1,V2
  std::vector<std::string> samples;    // --sample 'NAME~LAW(A,B)'
  long per_point = 0;                  // -n: rows per grid point (0: 1; needed with --sample)
  std::uint64_t seed = 1;              // --seed
  std::vector<std::string> summaries;  // --summary (default: final)
  int threads = 0;                     // --threads (0: every core)
  std::string out;                     // -o (default: <model name>_sweep.csv)
  std::string trajectories;            // --trajectories DIR: each row's CSV as mbsc run writes it (run.columns, run.large_output)
  bool eig = false;                    // --eig: each row's eigenvalues of the linear model instead of a run
  std::vector<std::string> find, steady, keep;  // with --eig: a steady motion per row; the minimal state's first components
  double eig_t = 0.0;                  // with --eig: the reference time (--t)
};

int run_sweep(const SweepArgs& a, std::ostream& out, std::ostream& err);

}  // namespace mbsc::run
