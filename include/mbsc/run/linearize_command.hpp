// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// `mbsc linearize MODEL.mbs [--init NAME=VALUE ...] [--set ...] [--input ...]`: compile
/// the model with its linear_parts (cached, as for `mbsc run`), complete the reference
/// state by assembly, form the linear model about it (runtime/linear_model.hpp, thesis
/// section 4.5) and write A, B and the eigenvalues as text, CSV or JSON
/// (docs/linearization.md). Exit codes as for `mbsc run`.
#include <iosfwd>
#include <string>
#include <vector>

#include "mbsc/driver/commands.hpp"

namespace mbsc::run {

struct LinearizeArgs {
  std::string model;
  std::vector<std::string> lets;                 // --let NAME=VALUE (names the other values may use)
  std::vector<std::string> sets, inits, inputs;  // --set, --init, --input NAME=EXPR
  double t = 0.0;                                // --t: the reference time
  bool equilibrium = false;                      // --equilibrium: the reference must be at rest (x' = 0)
  /// --find NAMES --steady NAMES: a steady motion, the unknowns solved so that the
  /// rates of the steady components vanish (run/linear_reference.hpp, find_steady).
  std::vector<std::string> find, steady;
  std::string state = "minimal";                 // --state minimal|full: which linear model is written
  std::vector<std::string> keep;                 // --keep: components the minimal state takes first
  /// --second-order q1,q2,...: also M q'' + C q' + K q = T in these coordinates.
  std::vector<std::string> second_order;
  /// --speed NAME, --gravity NAME (a --let or a parameter each): split that form as
  /// M q'' + v C1 q' + (g K0 + v^2 K2) q = T (the benchmark bicycle's form).
  std::string speed, gravity;
  /// --symbolic NAMES: parameters or --let names left as symbols (or "all"); the model is
  /// then written symbolically (analysis/symbolic_linearize.hpp) as text, LaTeX or JSON.
  std::vector<std::string> symbolic;
  std::string format = "text";                   // --format text|csv|json|latex (latex: with --symbolic)
  std::string out = "-";                         // -o FILE (default: standard output)
  std::string cache_dir;
  driver::WorkArgs work;
};

int run_linearize(const LinearizeArgs& a, std::ostream& out, std::ostream& err);

}  // namespace mbsc::run
