// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// A triangular node's reduced forces h = C^T (hy - My e) are built on named variables:
/// e_<speed> (the dependent rates with the independent accelerations zero) and r_<speed>
/// (the adjoint sums of the transposed rate steps). That keeps h linear in size for long
/// chains, but hides cancellations between the named values: in the two-link chain the
/// bobs' centripetal terms u0^2 sin q0 cos q0 cancel only once e is written out. For a
/// node with few steps, inline_small_recurrences substitutes every named value into h,
/// expands and tidies it, and keeps the result when it is smaller than the named form
/// (h plus the named values, distinct subexpressions counted once). An exact identity either way.
#include <ginac/ginac.h>

#include <cstddef>
#include <vector>

#include "mbsc/ir/function_spec.hpp"

namespace mbsc::sym {

/// At most this many named values are substituted (their expansion grows with the
/// product of the sums' lengths; long chains keep their recurrences).
inline constexpr std::size_t kMaxInlinedRecurrences = 8;

/// Replaces h (a column) by its substituted, expanded form when that needs fewer
/// operations than h with the names plus the named values; true when it did. named: the
/// node's values in order; the first `kept` (the e_ rates, which the full state's
/// accelerations read anyway) count half.
bool inline_small_recurrences(const std::vector<ir::Define>& named, std::size_t kept, GiNaC::matrix& h);

/// Operations of a set of expressions, each distinct subexpression counted once (as the
/// back end's common-subexpression elimination would leave them, roughly).
int shared_operations(const std::vector<GiNaC::ex>& exprs);

}  // namespace mbsc::sym
