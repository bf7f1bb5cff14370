// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// `mbsc run MODEL.mbs`: compile (or take from the cache), find a consistent initial
/// state, integrate, write the CSV and the plot, and summarise the run on stderr.
/// Exit codes: 0 done, 1 a user error (model, option, initial state, compiler, output
/// path, a spent budget), 2 a numerical failure during the run (the destination is left
/// as it was; a temporary file beside it, named in the message, keeps every row up to
/// the failure) or, with --strict, an accuracy warning.
#include <iosfwd>
#include <map>
#include <string>
#include <vector>

#include "mbsc/driver/commands.hpp"

namespace mbsc::run {

struct RunArgs {
  std::string model;
  double t_end = 10.0;
  double dt_out = 0.0;            // 0: t_end / 500
  std::string integrator = "dopri5";
  double rtol = 1e-8, atol = 1e-10;
  double h = 0.0;                 // fixed-step methods (0: dt_out / 10)
  bool multipliers = false;       // --formulation multipliers
  bool minimal_state = false;     // --state minimal
  std::string solver = "auto";    // --solver auto|dense|sparse (as for generate)
  std::vector<std::string> sets;  // --set name=value
  std::vector<std::string> inits; // --init name=value
  std::map<std::string, std::string> inputs;  // --input name=EXPR or name=@FILE[:COLUMN]
  std::string input_interpolation = "linear";  // --input-interpolation: a table's, linear|cubic
  std::string csv;                // -o (default: <model name>.csv)
  std::vector<std::string> columns;       // --columns (default: t, the state, outputs, energy)
  std::string plot;               // --plot file.svg|png
  std::vector<std::string> plot_columns;  // --plot-columns (default: outputs, else the dof speeds)
  bool continuation = false;      // --continuation: through rank loss of the constraints
  std::string projection = "auto";  // auto (on for full state with constraints), on, off
  std::string newton_jacobian = "generated";  // bdf, ark-dirk: generated|differences|sundials (NewtonJacobian)
  double baumgarte_alpha = -1, baumgarte_beta = -1;  // < 0: the model's defaults
  std::string cache_dir;
  bool strict = false;            // --strict: accuracy warnings are failures (exit 2)
  bool large_output = false;      // --large-output: write a CSV estimated above a gigabyte
  driver::WorkArgs work;
};

int run_simulation(const RunArgs& a, std::ostream& out, std::ostream& err);

/// The options of the integration that need no model (--t-end, --dt-out, --integrator,
/// --rtol, --atol, --projection, --h, --baumgarte-*): false with `error` (no "mbsc:
/// error:" prefix) for the first bad one. `mbsc run` and `mbsc sweep` check them first.
bool check_integration_options(const RunArgs& a, std::string& error);

/// The integrators `--integrator` accepts here (the runtime's and, when mbsc was built
/// with SUNDIALS, its methods).
std::vector<std::string> integrator_names();

}  // namespace mbsc::run
