// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The generated function linear_parts(t, x, w, p, OUT) with w = (u, q1', lambda): the
/// Taylor coefficients of the dependent-coordinate equations that
/// include/mbsc/runtime/linear_model.hpp turns into the linear model (docs/linearization.md).
/// Emitted only when asked (--outputs linear_parts, or what `mbsc linearize` compiles).
#include <functional>
#include <vector>

#include "mbsc/ir/function_spec.hpp"
#include "mbsc/model/model.hpp"

namespace mbsc::driver {

/// `fin` finalizes an expression (formals, frozen parameters); `rebuild` are the steps
/// that rebuild the full state of a --state minimal model (empty otherwise). A model
/// with Coulomb friction gets the function undefined (status 4).
ir::FunctionSpec linear_parts_spec(const model::Model& m, const std::function<GiNaC::ex(const GiNaC::ex&)>& fin,
                                   std::vector<ir::Step> rebuild);

/// The coordinates (indices) of every unit quaternion the model's bodies carry.
std::vector<std::vector<int>> unit_quaternion_coords(const model::Model& m);

/// The number of values it writes (kLinearPartsSize).
long linear_parts_size(const model::Model& m);

}  // namespace mbsc::driver
