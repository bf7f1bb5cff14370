// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Configurations on the constraint manifold, found at generation time.
///
/// The generic probe point (sym/probe.hpp) is not on the mechanism, so the rank of the
/// constraint Jacobian there is the generic rank. Constraints that are redundant only
/// where they hold (Bricard's linkage, a parallelogram with a third crank) are full rank
/// there and lose rank on every assembled configuration. So ranks are also measured at
///   * the start: the model's `initial` values fixed, its `initial guess` values and
///     zeros (quaternions at the identity) as the guess for the rest, and Newton's
///     minimum-norm steps on the position constraints (as `mbsc run` assembles);
///   * two points near it on the manifold: a step along the null space of the position
///     Jacobian there, pulled back onto the manifold with every coordinate free.
/// A rank deficit at all three is a redundancy of the mechanism; a deficit at the start
/// alone marks a singular start (a flat parallelogram chain, a toggle).
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "mbsc/model/model.hpp"
#include "mbsc/sym/probe.hpp"

namespace mbsc::sym {

struct ManifoldPoints {
  std::optional<Probe> start;  // the assembled initial state; empty when there is none
  std::vector<Probe> nearby;   // points on the manifold near the start (fewer when not found)
  std::string why_not;         // when there is no start: why (for `check`)
};

ManifoldPoints manifold_points(const model::Model& m, const std::map<std::string, double>& param_values);

}  // namespace mbsc::sym
