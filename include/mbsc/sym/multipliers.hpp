// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The dependent-coordinate formulation with Lagrange multipliers and Baumgarte
/// stabilization (AMESim paper [P] eqs 22-23, docs/references.md), from the same model
/// as the modular method (`mbsc generate --formulation multipliers`):
///   My q1' - A^T lambda = hy                          (every leaf's own forces, all speeds)
///   A q1' = -(b + 2 alpha (A q1 + a) + beta^2 g)      (f'' + 2 alpha f' + beta^2 f = 0)
/// with A = d(velocity residuals)/d q1, A q1 + a the velocity residuals, b the order-2
/// invariants at q1' = 0, and g the position residuals (0 for velocity constraints).
/// The generated code solves the (nu + nc) system numerically; lambda and the
/// generalized reaction forces A^T lambda are outputs.
#include <ginac/ginac.h>

#include "mbsc/model/model.hpp"
#include "mbsc/sym/kkt_system.hpp"

namespace mbsc::sym {

struct MultiplierForm {
  GiNaC::matrix My;  // nu x nu
  GiNaC::matrix hy;  // nu x 1
  GiNaC::matrix A;   // nc x nu
  GiNaC::matrix velocity;  // nc x 1: the velocity residuals A q1 + a
  GiNaC::matrix b;   // nc x 1: order-2 invariants at q1' = 0
  GiNaC::matrix g;   // nc x 1: position residuals (0 rows for velocity constraints)
};

MultiplierForm multiplier_form(const model::Model& m);
/// The same from an already built sparse system (its entries spread into the matrices).
MultiplierForm multiplier_form(const model::Model& m, const KktSystem& sys);

}  // namespace mbsc::sym
