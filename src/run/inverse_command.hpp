// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The core of `mbsc inverse MODEL.mbs --prescribe name="expr of t" ... --unknowns u1,...`:
/// given a loaded model (a ModelTable) and the parsed options, prescribe the coordinates,
/// solve the inverse dynamics along [t_start, t_end] every dt_out
/// (include/mbsc/runtime/inverse_dynamics.hpp) and write the table as CSV.
///
/// The prescribed expressions are read with the model language's expression syntax and
/// functions (sin, cos, ^, pi, ...; docs/language.md), in t and the model's parameters;
/// their first and second time derivatives are taken symbolically (GiNaC) and evaluated
/// at every output time before the first is solved (run/prescribed_motion.hpp): a motion
/// undefined or not finite at one is a bad option (exit code 1), not a failed run.
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "mbsc/runtime/model_table.hpp"

namespace mbsc::run {

struct InverseCommandOptions {
  /// (coordinate name, expression text) in the order given on the command line.
  std::vector<std::pair<std::string, std::string>> prescribe;
  /// Input names to solve for; empty: every input of the model.
  std::vector<std::string> unknowns;
  /// Parameter values (--set); the others keep the model's defaults.
  std::map<std::string, double> params;
  /// Values of the inputs that are not unknowns (default 0).
  std::map<std::string, double> fixed_inputs;
  /// Guesses for coordinates (--init name=value, or the model's initial values): they
  /// pick the assembly branch at t_start; the rest start at 0.
  std::map<std::string, double> guess;
  double t_start = 0.0;
  double t_end = 1.0;
  double dt_out = 0.01;
  std::string output_csv;  // empty: no file
  /// The command's seconds left (its --budget); the solve stops where it returns <= 0.
  std::function<double()> seconds_left;
  /// The joints whose Coulomb friction the rhs closes (`friction mu`), with their slide
  /// rate v(t, x, u, p) at a full state (NaN where it does not evaluate). Such a model's rhs is not affine in its inputs, and the
  /// inputs are solved with the friction law; where the prescribed motion holds one at
  /// rest (v = 0 and v' = 0) its force may be anything up to mu |N| (stiction), and the
  /// inputs are not determined: a failure there.
  struct FrictionJoint {
    std::string name;
    std::function<double(double t, const std::vector<double>& x, const std::vector<double>& u, const std::vector<double>& p)>
        slide_rate;
  };
  std::vector<FrictionJoint> friction_joints;
  /// The unit quaternions of the state, four indices each: their assembly keeps them unit.
  std::vector<int> quaternion_indices;
};

/// The computed table: t, every coordinate and speed (kStateNames), every input
/// (kInputNames), and for the multipliers form the reaction along every speed
/// ("reaction:<speed>").
struct InverseTable {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
};

struct InverseOutcome {
  /// 0: done; 1: bad input (nothing computed, no file written); 2: a numerical failure
  /// during the run (the rows up to it are kept, and written when a file was asked for).
  int exit_code = 0;
  std::string message;  // the error ("--prescribe crank.theta: ...") or empty
  InverseTable table;
};

/// Runs the inverse dynamics of `m` as `opt` says. `model_label` names the model in
/// messages (its file path or name).
InverseOutcome inverse_command(const runtime::ModelTable& m, const InverseCommandOptions& opt, const std::string& model_label);

/// The CSV text of a table (header line, then one line per row, 17 significant digits).
std::string inverse_csv(const InverseTable& table);

}  // namespace mbsc::run
