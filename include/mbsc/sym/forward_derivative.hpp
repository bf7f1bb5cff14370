// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Forward-mode differentiation of an emitted function, as straight-line steps: the
/// derivative of every output of an ir::FunctionSpec with respect to chosen input
/// symbols (the state x and the inputs u of rhs: the generated rhs_jacobian;
/// docs/derivatives.md).
///
/// Each step s := v gets tangents ds/dy_d, derived node by node over v's expression
/// graph (sums, the product rule, powers, functions by their partials), each shared node
/// once, and kept sparse (a tangent that is zero is never formed); each numeric solve
/// X = A^-1 B gets one more solve with the same matrix, dX = A^-1 (dB - dA X), over all
/// its nonzero directions at once. The back end's CSE shares the rest.
#include <ginac/ginac.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "mbsc/ir/function_spec.hpp"

namespace mbsc::sym {

/// What forward mode does not differentiate: a minimum-norm solve of a semidefinite
/// matrix (redundant constraints' multipliers), a conditioning estimate, a function
/// formed by a congruence product.
struct NotDifferentiable : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The steps and outputs of the derivative of `f`: for each block of symbols, the
/// derivatives d(outputs)/d(block), row-major (outputs x block size), the blocks one
/// after the other. The name, documentation and shape are left to the caller.
/// abs(a) is differentiated as sign(a) a' (0 at a = 0) and the sign function as 0.
/// `held` symbols are defined by steps of `f` but taken as constants (their tangent is
/// zero): partial derivatives, as the implicit form of rhs_jacobian needs. Steps that no
/// output's tangent reads are kept for their values and not differentiated.
ir::FunctionSpec forward_derivative(const ir::FunctionSpec& f, const std::vector<std::vector<GiNaC::symbol>>& blocks,
                                    const std::vector<GiNaC::symbol>& held = {});

}  // namespace mbsc::sym
