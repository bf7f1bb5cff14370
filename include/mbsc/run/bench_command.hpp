// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// `mbsc bench MODEL.mbs`: speed against error. For every formulation x integrator x
/// tolerance it integrates from the same initial state to the same end time and
/// measures the error of the final state and the largest error over the trajectory
/// (against a reference run at a much tighter tolerance, or a reference CSV), the
/// constraint residuals, the energy drift, rhs evaluations and CPU time; it writes a
/// CSV, a markdown table on standard output and a work-precision plot (error against
/// CPU time, log-log), with the rows of peer tools (e.g. bench/simbody) on the same plot.
#include <iosfwd>
#include <map>
#include <string>
#include <vector>

#include "mbsc/driver/commands.hpp"

namespace mbsc::run {

struct BenchArgs {
  std::string model;
  double t_end = 5.0;
  double dt_out = 0.0;  // error samples over the trajectory (0: t_end / 100)
  std::vector<std::string> formulations = {"complement", "multipliers"};
  std::vector<std::string> integrators;  // default: dopri5, dop853 and bdf when available
  std::vector<double> tolerances = {1e-4, 1e-6, 1e-8, 1e-10};
  std::vector<std::string> sets, inits;
  std::map<std::string, std::string> inputs;
  std::vector<std::string> error_columns;  // default: every coordinate and speed
  std::string reference;                   // a CSV whose last row is the reference final state
  std::vector<std::string> peers;          // CSVs of other tools (bench/simbody)
  std::string csv;                         // -o (default <model>_bench.csv)
  std::string plot;                        // --plot (default none)
  double min_cpu = 0.1;                    // each timing repeats the run until this much CPU time
  std::string cache_dir;
  driver::WorkArgs work;
};

int run_bench(const BenchArgs& a, std::ostream& out, std::ostream& err);

}  // namespace mbsc::run
