// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// `mbsc linearize --symbolic NAMES`: the linear model with those parameters (or --let
/// names) left as symbols, written as text, LaTeX or JSON (docs/linearization.md,
/// "Symbolic linear models"). The numeric model at the same reference chooses the minimal
/// state and checks the symbolic one at the nominal values.
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "mbsc/analysis/symbolic_reference.hpp"
#include "mbsc/model/model.hpp"
#include "mbsc/run/linear_reference.hpp"
#include "mbsc/run/linearize_command.hpp"

namespace mbsc::analysis {

/// What the numeric linearization found: the reference, the state written (indices of
/// the full layout) and its A, B.
struct NumericLinearModel {
  const run::LinearReference* ref = nullptr;
  const runtime::LinearModel* lin = nullptr;  // over the full layout
  std::vector<int> sel;
  const std::vector<double>* A = nullptr;
  const std::vector<double>* B = nullptr;
  /// A and B in the same components at another reference (one symbol moved: the symbolic
  /// model is checked there too).
  std::function<bool(const run::LinearReference& ref, std::vector<double>& A, std::vector<double>& B, std::string& error)> at_moved;
};

/// The symbolic model's text in a.format (text, latex, json). False with `error` (and
/// `exit_code` 1 for the user's request, 2 when the symbolic and numeric models disagree).
bool symbolic_linear_text(const run::LinearizeArgs& a, const model::Model& m, const runtime::ModelTable& T,
                          const run::ReferenceRequest& req, const NumericLinearModel& numeric, const ReferenceAt& reference_at,
                          std::string& text, std::string& error, int& exit_code);

}  // namespace mbsc::analysis
