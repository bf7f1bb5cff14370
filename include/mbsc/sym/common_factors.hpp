// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Common factors pulled out of sums by structure: a*b*x + 2*a*b*y -> a*b*(x + 2*y).
///
/// It replaces GiNaC::collect_common_factors, whose *result* depends on GiNaC's
/// run-dependent term order: it finds the factors by polynomial gcd, and when the gcd of
/// the top sum's terms comes out as 1 (rather than -1, by the order of the terms) it
/// returns its input and drops what it had already simplified inside, while a -1 keeps it;
/// and it divides by the gcd literally or by expanding, by the gcd's sign. So one run of
/// the same model held a1*(cos(p) - (cos(p) - 1)) and the next a1 (docs/backend.md
/// "Determinism"). Here every decision depends on the factors alone: a factor is common
/// when every term holds it (a sum or its negation: the same factor up to sign), with its
/// smallest integer power; rational coefficients give their positive gcd. Bottom-up (the
/// inner sums first), and it never expands.
#include <ginac/ginac.h>

namespace mbsc::sym {

GiNaC::ex common_factors(const GiNaC::ex& e);

}  // namespace mbsc::sym
