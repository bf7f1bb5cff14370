// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The reference of `mbsc linearize --symbolic NAMES` as expressions of the symbols kept
/// (parameters or --let names): each state component and input is a number when it does
/// not change with them, else the expression the user or the model gave for it (--init,
/// the model's `initial`, --input), or for a speed without one the solution of the
/// velocity constraints; each checked against the numeric reference at the nominal
/// values and at values moved one symbol at a time. A coordinate that changes with a
/// symbol but was assembled or found numerically has no expression: an error names it.
#include <ginac/ginac.h>

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "mbsc/model/model.hpp"
#include "mbsc/run/linear_reference.hpp"

namespace mbsc::analysis {

struct SymbolicReference {
  std::vector<GiNaC::symbol> symbols;  // the kept symbols, in the order named
  GiNaC::exmap nominal;                // symbol -> its nominal value (exact)
  /// Every coordinate, speed, input, the time and every parameter not kept -> its value.
  GiNaC::exmap at;
  std::vector<GiNaC::ex> state;  // the full layout's reference values (as in `at`)
  /// The probes: one symbol moved, the symbols' values there and the numeric reference
  /// recomputed there.
  struct Probe {
    std::string name;
    double value = 0.0;
    GiNaC::exmap at;
    run::LinearReference ref;
  };
  std::vector<Probe> moved;
};

/// The numeric reference at the request's values with some names moved (name -> value).
using ReferenceAt = std::function<bool(const std::map<std::string, double>& moved, run::LinearReference& ref, std::string& error)>;

/// Speeds that follow the symbols without an expression that does (assembled from the
/// velocity constraints, as a wheel's spin from the forward speed): given `at` with
/// everything else, puts their expressions there (state indices of the full layout).
using SpeedSolver = std::function<bool(const std::vector<int>& speeds, GiNaC::exmap& at, std::string& error)>;

/// `names`: the --symbolic list ("all": every run-time parameter and --let name).
bool symbolic_reference(const model::Model& m, const runtime::ModelTable& T, const run::ReferenceRequest& req,
                        const std::vector<std::string>& names, const run::LinearReference& ref, const ReferenceAt& reference_at,
                        const SpeedSolver& solve_speeds, SymbolicReference& out, std::string& error);

}  // namespace mbsc::analysis
