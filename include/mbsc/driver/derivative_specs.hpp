// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The generated derivatives (docs/derivatives.md): rhs_jacobian and
/// inverse_dynamics_jacobian, forward-mode derivatives of the rhs and inverse_dynamics
/// functions already built (sym/forward_derivative.hpp).
#include <vector>

#include "mbsc/driver/residual_jacobian.hpp"
#include "mbsc/ir/function_spec.hpp"
#include "mbsc/model/model.hpp"
#include "mbsc/sym/eom.hpp"
#include "mbsc/sym/minimal_state.hpp"

namespace mbsc::driver {

/// rhs_jacobian(t, x, u, p, OUT): OUT = (dxdot/dx, kNx x kNx, then dxdot/du, kNx x kNin),
/// both row-major, from `rhs` (the spec rhs emits, with its friction closure). With
/// `max_ops` > 0, a Jacobian whose entries alone (a few operations each) would exceed it
/// is not derived: the function is written undefined (GenerateOptions::rhs_jacobian_max_ops).
/// With `residual` (a tree's rhs), by the implicit form (driver/residual_jacobian.hpp).
ir::FunctionSpec rhs_jacobian_spec(const model::Model& m, const sym::Eom& eom, const sym::MinimalState* minimal,
                                   const ir::FunctionSpec& rhs, long max_ops = 0, const TreeResidual* residual = nullptr);

/// inverse_dynamics_jacobian(t, x, zdot, p, OUT): OUT = (du/dx, kNin x kNx, then
/// du/dzdot, kNin x kNdof), both row-major, from `inverse_dynamics`.
ir::FunctionSpec inverse_dynamics_jacobian_spec(const model::Model& m, const sym::Eom& eom,
                                                const sym::MinimalState* minimal, const ir::FunctionSpec& inverse_dynamics);

/// Appends the derivatives asked for to `specs`, each taken of its function there.
void add_derivative_specs(const model::Model& m, const sym::Eom& eom, const sym::MinimalState* minimal, bool rhs_jacobian,
                          bool inverse_dynamics_jacobian, long rhs_jacobian_max_ops, const TreeResidual* residual,
                          std::vector<ir::FunctionSpec>& specs);

}  // namespace mbsc::driver
