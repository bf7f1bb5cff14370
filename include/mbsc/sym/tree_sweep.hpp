// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// More right-hand sides through a tree recursion that has already run
/// (sym/tree_recursion.hpp): the system over all speeds
///
///   My q1' - A^T lambda = f,      A q1' = c,
///
/// solved again for new columns f and c with the pivots the recursion formed (its
/// articulated inertias IA, the joint pivots D, the gains G, the maps T and Phi). Each
/// column costs two vector sweeps, leaves to root for the articulated forces and root to
/// leaves for the rates: no articulated inertia is formed again. The implicit form of
/// rhs_jacobian uses it (driver/residual_jacobian.hpp): the tangents of the equations'
/// residual are such columns.
#include <ginac/ginac.h>

#include <vector>

#include "mbsc/ir/function_spec.hpp"

namespace mbsc::sym {

/// What the recursion keeps for later solves: per body, the matrices of its sweeps as the
/// expressions (or named intermediates) the generated code already computes.
struct TreeFactors {
  /// Row `row` gives the body's speed at position `a` (in Body::speeds); its share of
  /// k is k_a = c_row * inverse + sum_l w_l k_l over the body's speeds solved before it
  /// (`own`: position l, w_l). The parent's and joint's terms are in T and Phi.
  struct Substitution {
    int a = 0;
    int row = 0;
    GiNaC::ex inverse;
    std::vector<std::pair<int, GiNaC::ex>> own;
  };
  struct Body {
    std::vector<int> speeds;  // u_c (indices into the model's speeds)
    std::vector<int> joint;   // s_c
    int parent = -1;          // index into bodies; -1: the ground
    bool free_root = false;
    // Row-major: T (|u_c| x |u_p|), Phi (|u_c| x |s_c|), IA (|u_c|^2), U = IA Phi,
    // D = Phi^T U + My_s (|s_c|^2), G = D^-1 U^T (|s_c| x |u_c|).
    std::vector<GiNaC::ex> T, Phi, IA, U, D, G;
    std::vector<Substitution> substitutions;
  };
  std::vector<Body> bodies;
  std::vector<int> order;  // roots first, each body after its parent
};

/// The rates q1' of the system above for `columns` right-hand sides: forces[s][j] on
/// speed s and rows[r][j] on row r (zeros cost nothing). Appends the steps that compute
/// them to `steps`; returns rates[s][j] (named intermediates or zeros).
std::vector<std::vector<GiNaC::ex>> solve_columns(const TreeFactors& tree, const std::vector<std::vector<GiNaC::ex>>& forces,
                                                  const std::vector<std::vector<GiNaC::ex>>& rows, int columns,
                                                  std::vector<ir::Step>& steps);

}  // namespace mbsc::sym
