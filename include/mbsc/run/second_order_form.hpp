// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The linear model written as second-order equations in chosen coordinates q
/// (docs/linearization.md, "Second-order form"):
///
///   M q'' + C q' + K q = T      (T: generalized forces conjugate to q)
///
/// The tangent space of the linear model (runtime/linear_model.hpp) is given the
/// coordinates xi = (q, q', the rest): q' is a linear function of the state (the rows of
/// A for q). M^-1 is the response of q'' to generalized forces on q (LinearModel::Bq),
/// C and K the columns of q'' over q' and q, multiplied by -M. Where q'' also depends on
/// the rest of xi (other coordinates, speeds the form leaves out), `coupling` says how much.
#include <string>
#include <vector>

#include "mbsc/runtime/linear_model.hpp"

namespace mbsc::run {

struct SecondOrderForm {
  int k = 0;                    // number of coordinates
  std::vector<double> M, C, K;  // k x k, row-major
  /// max |d q''/d rest| over max(|d q''/d q|, |d q''/d q'|, 1e-300): 0 when q, q'
  /// evolve by themselves (the bicycle's lean and steer at straight running).
  double coupling = 0.0;
};

/// `coords`: indices of coordinates (into the full layout's first nq components). False
/// with `why` when they cannot form such a form (a rate fixed by the constraints, a
/// coordinate the linearized constraints fix, M singular).
bool second_order_form(const runtime::LinearModel& lin, int nq, const std::vector<int>& coords, SecondOrderForm& out,
                       std::string& why);

}  // namespace mbsc::run
