// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// `mbsc inverse MODEL.mbs --prescribe NAME=EXPR ... [--unknowns u1,...]`: compile the
/// model (cached, as for `mbsc run`), solve its inverse dynamics along the prescribed
/// motion (src/run/inverse_command.hpp) and write the CSV and a plot. Exit codes as for
/// `mbsc run`.
#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

#include "mbsc/driver/commands.hpp"

namespace mbsc::run {

struct InverseArgs {
  std::string model;
  std::vector<std::pair<std::string, std::string>> prescribe;  // --prescribe NAME=EXPR
  std::vector<std::string> unknowns;                            // --unknowns (default: every input)
  std::vector<std::string> sets, inits, fixed_inputs;          // --set, --init (guesses), --input NAME=VALUE
  bool multipliers = false;  // --formulation multipliers: the constraint reactions too
  double t_start = 0.0, t_end = 1.0, dt_out = 0.0;  // dt_out 0: (t_end - t_start) / 500
  std::string csv;           // -o (default <model>_inverse.csv)
  std::string plot;
  std::vector<std::string> plot_columns;  // default: the unknown inputs
  std::string cache_dir;
  driver::WorkArgs work;
};

int run_inverse(const InverseArgs& a, std::ostream& out, std::ostream& err);

}  // namespace mbsc::run
