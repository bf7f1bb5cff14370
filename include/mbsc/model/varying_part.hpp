// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Which quantities may change during a motion: the one test behind every "must be a
/// constant" rule of the language (masses, inertias, initial values, rolling radii,
/// fixed planes and surfaces).
#include <ginac/ginac.h>

#include <string>
#include <vector>

#include "mbsc/model/model.hpp"

namespace mbsc::model {

/// What in e changes with the motion, named for a message ("coordinate 'x'", "speed 'u'",
/// "input 'F'", "the time t"), or "" when e reads parameters and constants only.
/// Coordinates whose indices are in `allowed_coords` do not count (a surface z = γ(x, y)
/// may read its own x and y).
std::string varying_part(const Model& m, const GiNaC::ex& e, const std::vector<int>& allowed_coords = {});

}  // namespace mbsc::model
