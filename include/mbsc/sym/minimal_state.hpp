// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The minimal state (`mbsc generate --state minimal`): x = (kept q0, z) instead of
/// (all q0, all q1). Everything else is rebuilt at the start of each function:
///   * a coordinate that a position constraint gives explicitly (g = a q_c - rest with a
///     a nonzero number) is computed from the others, in dependency order;
///   * every dependent speed is computed top-down from z through the order-1 form of
///     the constraints, in the same triangular order as its rate (docs/formulation.md).
/// The explicit position constraints then hold exactly and the velocity constraints hold
/// to rounding; only the non-explicit position constraints can drift.
#include <optional>
#include <vector>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/ir/function_spec.hpp"
#include "mbsc/model/model.hpp"
#include "mbsc/sym/eom.hpp"

namespace mbsc::sym {

struct MinimalState {
  std::vector<int> kept_coords;        // coordinates in the state, model order
  std::vector<ir::Define> coords;      // the others: q_c = value(kept, earlier), evaluation order
  /// Dependent q1, root to leaves: Defines (triangular or small exact blocks) or a
  /// numeric Solve whose X are the speeds themselves.
  std::vector<ir::Step> speeds;
  std::vector<int> eliminated_coords;  // coordinate index of each entry of `coords`
};

/// A node whose dependent speeds need a numeric solve gets one at order 1; reports an
/// error (at the subsystem) when its parent needs them in closed form (nested numeric
/// blocks: the parent's solve would read values only its child's solve produces).
std::optional<MinimalState> minimal_state(const model::Model& m, const Eom& eom, Diagnostics& diags);

}  // namespace mbsc::sym
