// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The articulated-body recursion on a tree of bodies placed by joint coordinates
/// (docs/formulation.md, "The tree recursion"), read off the sparse system of
/// sym/kkt_system.hpp without forming a multiplier:
///
///   every body c (a leaf's speeds u_c) is fixed by exactly |u_c| rows that tie it to one
///   parent body p (or to the ground) and to joint speeds s_c of its own,
///       u_c = T_c u_p + Phi_c s_c + ...,     u_c' = T_c u_p' + Phi_c s_c' + k_c,
///   a row's entries on u_c being numbers in a triangular pattern (a body's velocity
///   rows turn its angular speeds into the velocity of its mass centre);
///   a body with no rows at all is a free root (its own speeds are independent).
///
/// Leaves to root, each body's articulated inertia IA_c and force pA_c (its My block and
/// hy, plus what its children pass on) give beta = pA_c - IA_c k_c, U = IA_c Phi_c, the
/// joint pivot D = Phi_c^T U + My_s and the gains [G | g] = D^-1 [U^T | h_s + Phi_c^T beta];
/// the parent receives
///       IA_p += T_c^T (IA_c - U G) T_c,      pA_p += T_c^T (beta - U g).
/// Root to leaves: s_c' = g - G T_c u_p',  u_c' = T_c u_p' + Phi_c s_c' + k_c. Every entry
/// is a named intermediate, so the work per body is bounded and the code is O(N), with the
/// zeros and ones of exact axes and frozen parameters folded by the algebra.
///
/// Rows the tree does not need (loops closed on it: A_l u' = c_l) are closed with their
/// multipliers: the inward sweep also carries each loop row's unit force, the bodies the
/// loop rows read are swept outwards for u'_0 and X (u' = u'_0 + X lambda_l), the small
/// SPD system (A_l X) lambda_l = c_l - A_l u'_0 gives lambda_l, and the gains take it in
/// before the one sweep root to leaves. Letters as in docs/notation.md.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "mbsc/model/model.hpp"
#include "mbsc/sym/kkt_elimination.hpp"
#include "mbsc/sym/kkt_system.hpp"
#include "mbsc/sym/probe.hpp"

namespace mbsc::sym {

/// The recursion's steps (every m.speed_dots[j] defined after them, and with `lambda`
/// every row's multiplier: the loop rows' from their solve, the others leaves to root
/// from each body's own equations), or nullopt with `why` when the model is not such a
/// tree (a body that no rows place from the ground or a placed body, a joint speed
/// shared by two bodies, a joint pivot not definite or loop rows redundant at the probe
/// point). `forest` when no row closes a loop, else `speeds_first` (the loop pivot is a
/// Schur complement of A M^-1 A^T). `c` are the rows' right-hand sides at order 2 (A q1' = c); `fin` and `probe` as
/// for eliminate_kkt.
std::optional<KktElimination> tree_recursion(const model::Model& m, const KktSystem& sys, const std::vector<GiNaC::ex>& c,
                                             const std::function<GiNaC::ex(const GiNaC::ex&)>& fin, const Probe& probe,
                                             const std::vector<GiNaC::symbol>* lambda, std::string& why);

}  // namespace mbsc::sym
