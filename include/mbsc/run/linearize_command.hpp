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
  std::vector<std::string> sets, inits, inputs;  // --set, --init, --input NAME=VALUE
  double t = 0.0;                                // --t: the reference time
  bool equilibrium = false;                      // --equilibrium: the reference must be at rest (x' = 0)
  std::string state = "minimal";                 // --state minimal|full: which linear model is written
  std::vector<std::string> keep;                 // --keep: components the minimal state takes first
  std::string format = "text";                   // --format text|csv|json
  std::string out = "-";                         // -o FILE (default: standard output)
  std::string cache_dir;
  driver::WorkArgs work;
};

int run_linearize(const LinearizeArgs& a, std::ostream& out, std::ostream& err);

}  // namespace mbsc::run
