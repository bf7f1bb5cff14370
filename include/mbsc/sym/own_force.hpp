// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The generalized effective force along one speed at its own leaf or node, before any
/// reduction: bodies' inertia and gravity, custom leaves' `force` statements, and every
/// applied force aimed at the speed (user `force`, library actuators, springs,
/// dampers). Both formulations start from it: the modular method per node (f over y),
/// the multipliers form over all speeds (My, hy).
#include <ginac/ginac.h>

#include "mbsc/model/model.hpp"

namespace mbsc::sym {

/// f(speed) as a function of the speeds' rates (q1dot symbols), coordinates, speeds,
/// inputs, parameters and t. Frozen parameters are not substituted here.
GiNaC::ex own_force(const model::Model& m, int speed);

}  // namespace mbsc::sym
