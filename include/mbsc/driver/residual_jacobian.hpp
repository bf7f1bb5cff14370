// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The implicit form of rhs_jacobian for a tree (docs/derivatives.md, "Two forms").
///
/// The rates z = (q1', lambda) solve K(x) z = r(x, u): My q1' - A^T lambda = hy,
/// A q1' = c. Differentiating the residual rho(x, u, z) = r - K z = 0 with z held,
///
///   K dz/dx_j = d rho/dx_j |_z,
///
/// so each direction needs the residual's partial derivative (the equations of every
/// body's motion and every joint's rows, O(N) vectors, by forward mode with z held) and
/// one solve with K, made by the tree recursion's own pivots (sym/tree_sweep.hpp). Forward
/// mode through the whole recursion instead differentiates every articulated inertia
/// once per direction.
#include <memory>
#include <optional>
#include <vector>

#include "mbsc/ir/function_spec.hpp"
#include "mbsc/sym/tree_sweep.hpp"

namespace mbsc::driver {

/// What the implicit form needs from the rhs the pipeline built.
struct TreeResidual {
  std::vector<ir::Step> steps;         // the rhs's steps, the multipliers defined too
  std::vector<GiNaC::ex> forces;       // per speed: hy - My q1' + A^T lambda
  std::vector<GiNaC::ex> rows;         // per constraint row: c - A q1'
  std::vector<GiNaC::symbol> held;     // q1' (every speed's rate) and lambda
  std::shared_ptr<const sym::TreeFactors> tree;
};

/// The derivative of `rhs`'s outputs over the blocks of directions (row-major per block,
/// as sym::forward_derivative), by the implicit form. Every output must be either free
/// of the held rates or one of them; sym::NotDifferentiable otherwise.
ir::FunctionSpec implicit_rhs_jacobian(const ir::FunctionSpec& rhs, const TreeResidual& residual,
                                       const std::vector<std::vector<GiNaC::symbol>>& blocks);

}  // namespace mbsc::driver
