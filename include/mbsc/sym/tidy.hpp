// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Cheap, size-reducing rewrites applied to expressions before they are emitted:
/// common factors are pulled out of sums (a*b*x + a*b*y -> a*b*(x + y)) and
/// sin(u)^2 + cos(u)^2 becomes 1. Never expands, so it cannot blow an expression up.
#include <ginac/ginac.h>

namespace mbsc::sym {

GiNaC::ex tidy(const GiNaC::ex& e);

}  // namespace mbsc::sym
