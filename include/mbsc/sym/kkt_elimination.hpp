// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The O(N) right-hand side: the dependent-coordinate system over all speeds,
///
///   [ My  -A^T ] [ q1'    ]   [ hy ]
///   [ -A   0   ] [ lambda ] = [ -c ]      (A q1' = c at order 2)
///
/// solved by block Gaussian elimination in an order fixed at generation time, emitted
/// as straight-line steps: small dense pivot solves and Schur-complement updates.
/// Unknowns are grouped into blocks (a leaf's speeds and the speeds its inertia couples;
/// the constraint rows that touch the same speed blocks) and a block is eliminated when
/// its current pivot is definite at the probe point (speeds: positive, constraints:
/// negative), cheapest first (fewest scalar neighbours). For a tree of bodies this is the
/// articulated-body order of the literature (Baraff 1996, "Linear-time dynamics using
/// Lagrange multipliers"): leaves first, bounded fill, O(N) operations, every pivot an
/// articulated inertia or its constraint's counterpart. Closed loops add fill where the
/// loops are (docs/formulation.md, "O(N) right-hand side").
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mbsc/ir/function_spec.hpp"
#include "mbsc/model/model.hpp"
#include "mbsc/sym/kkt_system.hpp"
#include "mbsc/sym/probe.hpp"
#include "mbsc/sym/tree_sweep.hpp"

namespace mbsc::sym {

struct KktElimination {
  /// Pivot solves and definitions; after them every m.speed_dots[j] and lambda[r] is
  /// defined (named Defines).
  std::vector<ir::Step> steps;
  /// No closed loop: the block graph is a forest and no constraint pivot joined two parts
  /// eliminated apart (a tree of bodies). Then every pivot is an articulated inertia or a
  /// joint's counterpart, regular wherever the joint itself is; in a loop such a pivot
  /// can vanish where the loop's open parts fold. Pivots are `reported` unless forest.
  bool forest = false;
  /// Every speed block was eliminated before the first constraint block (the order
  /// eliminate_kkt tries when the model has a loop). The speed pivots are then My's own
  /// blocks and every constraint pivot a Schur complement of -A My^-1 A^T, which is
  /// negative definite wherever A has full row rank: the pivots fail only where the
  /// dense multipliers form fails too. Then only the constraint pivots are `reported`.
  bool speeds_first = false;
  /// No pivot can vanish where the constraints keep their rank: forest or speeds_first.
  bool regular() const { return forest || speeds_first; }
  int blocks = 0;       // pivot blocks eliminated
  int largest = 0;      // size of the largest pivot block
  long fill = 0;        // block pairs coupled by the elimination that were not coupled before
  /// A tree recursion with no loop: its pivots, for more right-hand sides (sym/tree_sweep.hpp).
  std::shared_ptr<const TreeFactors> tree;
};

/// Eliminates the system with constraint right-hand sides `c` (A q1' = c): fewest
/// neighbours first; with `loops_speeds_first`, when that order does not find a tree,
/// once more with every speed block first (kept when it gets through: `speeds_first`). `fin` prepares
/// every expression for emission (formals, frozen values); `probe` evaluates prepared
/// expressions. nullopt, with `why` set, when no order with definite pivots exists at the
/// probe point (a massless part that no constraint fixes, redundant constraints).
std::optional<KktElimination> eliminate_kkt(const model::Model& m, const KktSystem& sys, const std::vector<GiNaC::ex>& c,
                                            const std::vector<GiNaC::symbol>& lambda,
                                            const std::function<GiNaC::ex(const GiNaC::ex&)>& fin, const Probe& probe,
                                            bool loops_speeds_first, std::string& why);

}  // namespace mbsc::sym
