// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// `mbsc eig MODEL.mbs --sweep NAME=FROM:TO:STEP [linearize's reference options]`: the
/// eigenvalues of the minimal linear model (run/linearize_command.hpp) along a parameter
/// sweep, modes tracked continuously (run/eigen_sweep.hpp), the values where a mode
/// changes stability found by root finding, written as CSV (and a plot: real and
/// imaginary parts against the parameter, eigenvector ratios). docs/linearization.md.
#include <iosfwd>
#include <string>
#include <vector>

#include "mbsc/driver/commands.hpp"

namespace mbsc::run {

struct EigArgs {
  std::string model;
  std::string sweep;                             // NAME=FROM:TO:STEP (a --let name, a parameter or a state component)
  std::vector<std::string> lets, sets, inits, inputs;
  std::vector<std::string> find, steady;         // a steady motion at every point (continued from the previous one)
  std::vector<std::string> keep;                 // components the minimal state takes first
  std::vector<std::string> ratios;               // --ratio NUM/DEN: eigenvector component ratios (state names)
  double t = 0.0;
  std::string csv;                               // -o (default <model>_eig.csv; - for standard output)
  std::string plot;                              // --plot FILE.svg|png
  std::string cache_dir;
  driver::WorkArgs work;
};

int run_eig(const EigArgs& a, std::ostream& out, std::ostream& err);

/// "NAME=FROM:TO:STEP" -> the name and the grid FROM, FROM + STEP, ... up to TO (TO
/// included when it is on the grid to rounding). False with `error` for a malformed
/// text, a zero, non-finite or wrong-signed step (an empty range), or over 10^5 points.
bool parse_sweep(const std::string& text, std::string& name, std::vector<double>& grid, std::string& error);

}  // namespace mbsc::run
