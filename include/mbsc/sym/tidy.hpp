// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Cheap, size-reducing rewrites applied to expressions before they are emitted:
/// common factors are pulled out of sums (a*b*x + a*b*y -> a*b*(x + y)) and
/// sin(u)^2 + cos(u)^2 becomes 1. Never expands, so it cannot blow an expression up.
#include <ginac/ginac.h>

namespace mbsc::sym {

GiNaC::ex tidy(const GiNaC::ex& e);

/// sin(u)^2 + cos(u)^2 = 1 where the squares do not meet as one sum (a s^2 + b + a c^2):
/// cos(u)^2 -> 1 - sin(u)^2 on the expanded form, kept when it has fewer nodes. It
/// expands, so it is for small expressions (a subsystem's M and h entries), not for
/// whole right-hand sides.
GiNaC::ex pythagoras(const GiNaC::ex& e);

}  // namespace mbsc::sym
