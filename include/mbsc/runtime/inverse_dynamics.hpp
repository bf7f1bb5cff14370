// SPDX-License-Identifier: GPL-2.0-or-later WITH mbsc-runtime-exception
// (see LICENSE: this header may be included in applications under any terms)
#pragma once
/// Inverse dynamics through a ModelTable (full state only, either formulation): kNdof
/// coordinates move as prescribed functions of time; at each time the solver finds
///   1. the positions: assembly (assemble.hpp) with the prescribed coordinates given, the
///      others starting from the previous solution (so the run stays on its branch);
///   2. the speeds: the velocity constraints A v + b = 0 together with the prescribed
///      rates, one least-squares solve that must be of full column rank;
///   3. the inputs: where the generated rhs is affine in the inputs, the speed rates are
///      v'(u) = a + B u exactly (up to rounding), with a = rhs at the base inputs and the
///      columns of B from one more rhs call per unknown input; the unknowns are the u that
///      make the prescribed coordinates' rates equal their prescribed accelerations. The
///      constraints at acceleration level are the rhs's own business, so no new generated
///      code is needed, and the prescribed coordinates need not be the independent set.
///      Where the rhs closes Coulomb friction itself (a joint's `friction mu`), the
///      friction force reads the normal reaction, which the inputs move: v'(u) is then
///      smooth but not affine at a given state (the friction's direction is fixed by the
///      state's slide rates), and Newton steps from that first solve, with columns by
///      differences, solve the inputs and the friction law together.
///   4. the multipliers form's reaction forces (A^T lambda along each speed) at that state.
/// A prescribed coordinate's rate must be one speed (q' = v, as for the planar library's
/// absolute coordinates and for particles); the constructor checks it.
///
///   InverseDynamics inv(table, {{index_of_q, motion}}, {0}, p);   // motion(t, q, q', q'')
///   std::vector<double> x = guess;                                // picks the branch
///   InverseSample s;
///   if (!inv.solve(t, x, s)) report(s.message);
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "mbsc/runtime/assemble.hpp"
#include "mbsc/runtime/least_squares.hpp"
#include "mbsc/runtime/model_table.hpp"

namespace mbsc::runtime {

/// One prescribed coordinate: its index in the state (0 <= coord < nq) and its motion,
/// which writes q(t), q'(t), q''(t).
struct Prescription {
  int coord = -1;
  std::function<void(double t, double& q, double& qd, double& qdd)> motion;
};

/// What the solver found at one time.
struct InverseSample {
  double t = 0.0;
  std::vector<double> x;          // nx: every coordinate and speed
  std::vector<double> xdot;       // nx: rhs at (x, inputs): every rate, the prescribed ones included
  std::vector<double> inputs;     // nin: the solved unknowns and the fixed others
  std::vector<double> reactions;  // nu: A^T lambda (multipliers form), else empty
  int partition = 0;              // the rhs partition used (another when partition 0 was singular)
  double acceleration_residual = 0.0;  // largest |v'_p - q''_p| after the solve
  std::string message;            // why it failed, naming the quantity
};

struct InverseOptions {
  AssemblyOptions assembly;
  double rank_tolerance = 1e-10;  // relative pivot below which a least-squares solve is rank deficient
  double residual_tolerance = 1e-8;  // on the prescribed accelerations / rates, relative to their size
  /// Newton steps on the inputs after the affine solve, taken while the accelerations
  /// miss by more than rounding (an rhs that closes Coulomb friction is not affine in them).
  int input_iterations = 20;
  /// The model's unit quaternions, four state indices each (kQuaternionIndices): kept of
  /// unit length by the assembly of the positions.
  std::vector<int> quaternion_indices;
};

class InverseDynamics {
 public:
  /// unknowns: indices of the inputs to solve for; fixed_inputs: values of all nin inputs
  /// (the unknowns' entries are ignored; empty means zeros); p: the np parameters.
  InverseDynamics(const ModelTable& m, std::vector<Prescription> prescribed, std::vector<int> unknowns,
                  std::vector<double> p, std::vector<double> fixed_inputs = {}, InverseOptions opt = {})
      : m_(m), pres_(std::move(prescribed)), unknowns_(std::move(unknowns)), p_(std::move(p)), base_u_(std::move(fixed_inputs)),
        opt_(opt) {
    if (base_u_.empty()) base_u_.assign(static_cast<std::size_t>(std::max(m_.nin, 1)), 0.0);
    for (int k : unknowns_)
      if (k >= 0 && k < m_.nin) base_u_[static_cast<std::size_t>(k)] = 0.0;
    error_ = check_setup();
  }

  /// Empty when the setup is usable; otherwise why not (also returned by every solve).
  const std::string& setup_error() const { return error_; }
  /// The speed whose value is the rate of prescribed coordinate k (filled by the first solve).
  const std::vector<int>& prescribed_speeds() const { return speed_of_; }

  /// x: in, a full state whose coordinates guess the configuration (the previous
  /// solution along a run); out, the consistent state at t. Returns false with
  /// s.message set on failure.
  bool solve(double t, std::vector<double>& x, InverseSample& s) {
    s = InverseSample{};
    s.t = t;
    if (!error_.empty()) return fail(s, error_);
    const std::size_t nq = static_cast<std::size_t>(m_.nq), nu = static_cast<std::size_t>(m_.nu);
    x.resize(nq + nu, 0.0);
    std::vector<double> q(pres_.size()), qd(pres_.size()), qdd(pres_.size());
    for (std::size_t k = 0; k < pres_.size(); ++k) {
      pres_[k].motion(t, q[k], qd[k], qdd[k]);
      if (!std::isfinite(q[k]) || !std::isfinite(qd[k]) || !std::isfinite(qdd[k]))
        return fail(s, "the prescribed motion of '" + name_q(k) + "' is not finite at t = " + num(t));
      x[static_cast<std::size_t>(pres_[k].coord)] = q[k];
    }
    // 1. Positions (the velocity part of assembly is ours: nc = 0 there).
    const AssemblyModel positions{m_.nq, m_.nu, m_.nposc, 0, m_.position_constraints, m_.position_jacobian,
                                  m_.velocity_constraints, m_.constraint_jacobian, m_.position_constraint_names,
                                  m_.constraint_names, m_.state_names, opt_.quaternion_indices.data(),
                                  static_cast<int>(opt_.quaternion_indices.size() / 4)};
    std::vector<bool> given_q(nq, false), given_u(nu, true);
    for (const auto& pr : pres_) given_q[static_cast<std::size_t>(pr.coord)] = true;
    const AssemblyResult a = assemble(positions, t, x, given_q, given_u, base_u_.data(), p_.data(), opt_.assembly);
    if (!a.ok()) return fail(s, a.message + " at t = " + num(t));
    if (a.position_full_rank >= free_coordinates() && a.position_rank >= 0 && a.position_rank < free_coordinates())
      return fail(s, "the prescribed coordinates do not determine the configuration at t = " + num(t) + " (position Jacobian rank " +
                         std::to_string(a.position_rank) + " over " + std::to_string(free_coordinates()) +
                         " free coordinates): a singular pose, or coordinates that are not independent");
    if (speed_of_.empty()) {
      const std::string why = find_prescribed_speeds(t, x);
      if (!why.empty()) return fail(s, why);
    }
    // 2. Speeds: [A; S] v = [-b; q'] with S picking the prescribed speeds.
    if (!solve_speeds(t, x, qd, s)) return false;
    // 3. Inputs from v'(u) = a + B u.
    if (!solve_inputs(t, x, qdd, s)) return false;
    // 4. Reactions.
    if (m_.multipliers && m_.reaction_forces != nullptr && m_.nc > 0) {
      s.reactions.assign(nu, 0.0);
      if (m_.reaction_forces(t, x.data(), s.inputs.data(), p_.data(), s.reactions.data()) != 0)
        return fail(s, "the reaction forces could not be evaluated at t = " + num(t) + " (singular constraint set)");
    }
    s.x = x;
    return true;
  }

 private:
  static std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
  }
  std::string name_q(std::size_t k) const { return m_.state_names[pres_[k].coord]; }
  static bool fail(InverseSample& s, const std::string& why) {
    s.message = why;
    return false;
  }
  int free_coordinates() const { return m_.nq - static_cast<int>(pres_.size()); }

  std::string check_setup() const {
    if (!m_.full_state_layout()) return "inverse dynamics needs a model generated with the full state (--state full)";
    if (static_cast<int>(pres_.size()) != m_.ndof)
      return "the model has " + std::to_string(m_.ndof) + " degree(s) of freedom but " + std::to_string(pres_.size()) +
             " coordinate(s) are prescribed; prescribe exactly " + std::to_string(m_.ndof);
    for (std::size_t k = 0; k < pres_.size(); ++k) {
      if (pres_[k].coord < 0 || pres_[k].coord >= m_.nq) return "prescribed coordinate index out of range";
      if (!pres_[k].motion) return "prescribed coordinate '" + name_q(k) + "' has no motion";
      for (std::size_t j = 0; j < k; ++j)
        if (pres_[j].coord == pres_[k].coord) return "coordinate '" + name_q(k) + "' is prescribed twice";
    }
    if (unknowns_.empty() && m_.ndof > 0) return "no unknown inputs to solve for";
    for (std::size_t k = 0; k < unknowns_.size(); ++k) {
      if (unknowns_[k] < 0 || unknowns_[k] >= m_.nin) return "unknown input index out of range";
      for (std::size_t j = 0; j < k; ++j)
        if (unknowns_[j] == unknowns_[k]) return std::string("input '") + m_.input_names[unknowns_[k]] + "' is named twice";
    }
    if (static_cast<int>(unknowns_.size()) > m_.ndof)
      return "more unknown inputs (" + std::to_string(unknowns_.size()) + ") than prescribed coordinates (" +
             std::to_string(m_.ndof) + "): the inputs would not be unique";
    if (static_cast<int>(base_u_.size()) < m_.nin) return "fixed_inputs needs one value per input";
    if (static_cast<int>(p_.size()) < m_.np) return "p needs one value per parameter";
    return "";
  }

  // rhs at (x, u), falling back to the other partitions where partition 0's blocks are singular.
  int rhs(double t, const std::vector<double>& x, const std::vector<double>& u, std::vector<double>& xdot, int& partition) const {
    xdot.assign(x.size(), 0.0);
    const int s0 = m_.rhs(t, x.data(), u.data(), p_.data(), xdot.data());
    partition = 0;
    if (s0 == 0 || m_.rhs_partition == nullptr) return s0;
    for (int k = 1; k < m_.npartitions; ++k)
      if (m_.rhs_partition(k, t, x.data(), u.data(), p_.data(), xdot.data()) == 0) {
        partition = k;
        return 0;
      }
    return s0;
  }

  // Each prescribed coordinate's rate must be one speed with coefficient 1: the rates are
  // linear in the speeds, so rhs at unit speeds shows them.
  std::string find_prescribed_speeds(double t, const std::vector<double>& x) {
    const std::size_t nq = static_cast<std::size_t>(m_.nq);
    std::vector<double> probe = x, xdot;
    int part = 0;
    speed_of_.assign(pres_.size(), -1);
    for (int j = 0; j < m_.nu; ++j) {
      for (int i = 0; i < m_.nu; ++i) probe[nq + static_cast<std::size_t>(i)] = i == j ? 1.0 : 0.0;
      if (rhs(t, probe, base_u_, xdot, part) != 0) {
        speed_of_.clear();
        return "the rhs cannot be evaluated at the first configuration (t = " + num(t) + ")";
      }
      for (std::size_t k = 0; k < pres_.size(); ++k) {
        const double c = xdot[static_cast<std::size_t>(pres_[k].coord)];
        if (speed_of_[k] == -2 || std::fabs(c) <= 1e-12) continue;
        speed_of_[k] = speed_of_[k] == -1 && std::fabs(c - 1.0) < 1e-12 ? j : -2;  // a second speed, or a factor
      }
    }
    for (std::size_t k = 0; k < pres_.size(); ++k)
      if (speed_of_[k] < 0) {
        speed_of_.clear();
        return "the rate of prescribed coordinate '" + name_q(k) +
               "' is not a single speed; prescribe coordinates whose rate is a speed (q' = v)";
      }
    return "";
  }

  bool solve_speeds(double t, std::vector<double>& x, const std::vector<double>& qd, InverseSample& s) const {
    const std::size_t nq = static_cast<std::size_t>(m_.nq), nu = static_cast<std::size_t>(m_.nu), nc = static_cast<std::size_t>(m_.nc);
    const std::size_t np = pres_.size(), rows = nc + np;
    std::vector<double> A(nc * nu), b(nc), M(rows * nu, 0.0), r(rows, 0.0);
    for (std::size_t j = 0; j < nu; ++j) x[nq + j] = 0.0;
    if (nc > 0 && (m_.constraint_jacobian(t, x.data(), base_u_.data(), p_.data(), A.data()) != 0 ||
                   m_.velocity_constraints(t, x.data(), base_u_.data(), p_.data(), b.data()) != 0))
      return fail(s, "the velocity constraints could not be evaluated at t = " + num(t));
    for (std::size_t i = 0; i < nc; ++i) {
      for (std::size_t j = 0; j < nu; ++j) M[i * nu + j] = A[i * nu + j];
      r[i] = -b[i];
    }
    for (std::size_t k = 0; k < np; ++k) {
      M[(nc + k) * nu + static_cast<std::size_t>(speed_of_[k])] = 1.0;
      r[nc + k] = qd[k];
    }
    const LeastSquares v = solve_least_squares(M, r, static_cast<int>(rows), static_cast<int>(nu), opt_.rank_tolerance);
    if (v.rank < static_cast<int>(nu))
      return fail(s, "the prescribed rates do not determine the speeds at t = " + num(t) + " (rank " + std::to_string(v.rank) +
                         " of " + std::to_string(nu) + "): a singular pose for this choice of prescribed coordinates");
    for (std::size_t j = 0; j < nu; ++j) x[nq + j] = v.x[j];
    // The system is consistent (as many rows as needed, constraints independent): check.
    double worst = 0.0, scale = 1.0;
    for (std::size_t i = 0; i < rows; ++i) {
      double e = -r[i];
      for (std::size_t j = 0; j < nu; ++j) e += M[i * nu + j] * v.x[j];
      worst = std::max(worst, std::fabs(e));
      scale = std::max(scale, std::fabs(r[i]));
    }
    if (!(worst <= opt_.residual_tolerance * scale))
      return fail(s, "the prescribed rates contradict the velocity constraints at t = " + num(t) + " (residual " + num(worst) + ")");
    return true;
  }

  bool solve_inputs(double t, const std::vector<double>& x, const std::vector<double>& qdd, InverseSample& s) const {
    const std::size_t nq = static_cast<std::size_t>(m_.nq), np = pres_.size(), nk = unknowns_.size();
    std::vector<double> a;
    int part = 0;
    if (rhs(t, x, base_u_, a, part) != 0)
      return fail(s, "the rhs failed at t = " + num(t) + " (a singular block or mass matrix in every partition)");
    std::vector<double> B(np * nk), r(np);
    if (!input_columns(t, x, base_u_, a, /*unit=*/true, B)) return fail(s, "the rhs failed at t = " + num(t) + " with a unit input");
    for (std::size_t k = 0; k < np; ++k) r[k] = qdd[k] - a[nq + static_cast<std::size_t>(speed_of_[k])];
    s.inputs = base_u_;
    s.inputs.resize(static_cast<std::size_t>(std::max(m_.nin, 1)));
    if (nk > 0) {
      const LeastSquares sol = solve_least_squares(B, r, static_cast<int>(np), static_cast<int>(nk), opt_.rank_tolerance);
      if (sol.rank < static_cast<int>(nk))
        return fail(s, "the unknown inputs cannot move the prescribed coordinates independently at t = " + num(t) + " (rank " +
                           std::to_string(sol.rank) + " of " + std::to_string(nk) + ")");
      for (std::size_t c = 0; c < nk; ++c) s.inputs[static_cast<std::size_t>(unknowns_[c])] = sol.x[c];
    }
    if (rhs(t, x, s.inputs, s.xdot, s.partition) != 0) return fail(s, "the rhs failed at t = " + num(t) + " with the solved inputs");
    double scale = 1.0;
    for (std::size_t k = 0; k < np; ++k) scale = std::max(scale, std::fabs(qdd[k]));
    s.acceleration_residual = miss(s.xdot, qdd, r);
    // Newton on the inputs while the miss is above rounding: nothing to do for an rhs
    // affine in them; a few steps where the rhs closes friction on reactions they move.
    for (int it = 0; it < opt_.input_iterations && nk > 0 && s.acceleration_residual > 1e-13 * scale; ++it) {
      // No step without all its columns: the check below judges what we have.
      if (!input_columns(t, x, s.inputs, s.xdot, /*unit=*/false, B)) break;
      for (double& e : r) e = -e;
      const LeastSquares step = solve_least_squares(B, r, static_cast<int>(np), static_cast<int>(nk), opt_.rank_tolerance);
      if (step.rank < static_cast<int>(nk)) break;
      std::vector<double> u = s.inputs, xdot;
      for (std::size_t c = 0; c < nk; ++c) u[static_cast<std::size_t>(unknowns_[c])] += step.x[c];
      int pc = 0;
      if (rhs(t, x, u, xdot, pc) != 0) break;
      const double next = miss(xdot, qdd, r);
      if (!(next < 0.5 * s.acceleration_residual)) break;  // rounding reached, or a least-squares fit
      s.inputs = u;
      s.xdot = xdot;
      s.partition = pc;
      s.acceleration_residual = next;
    }
    if (!(s.acceleration_residual <= opt_.residual_tolerance * scale)) {
      std::string names;
      for (std::size_t c = 0; c < nk; ++c) names += std::string(c ? ", " : "") + m_.input_names[unknowns_[c]];
      return fail(s, "the inputs " + names + " cannot produce the prescribed accelerations at t = " + num(t) + " (residual " +
                         num(s.acceleration_residual) + "): fewer unknowns than prescribed coordinates, or inputs that do not act on them");
    }
    return true;
  }

  /// B (np x nk): the prescribed speeds' rates against each unknown input, by differences
  /// from (u, xdot = rhs at u): a unit step (exact where the rhs is affine in them), or a
  /// small one (1e-7 of the input, at least 1e-7) for Newton's columns. False where the rhs fails.
  bool input_columns(double t, const std::vector<double>& x, const std::vector<double>& u, const std::vector<double>& xdot,
                     bool unit, std::vector<double>& B) const {
    const std::size_t nq = static_cast<std::size_t>(m_.nq), np = pres_.size(), nk = unknowns_.size();
    std::vector<double> col;
    for (std::size_t c = 0; c < nk; ++c) {
      std::vector<double> shifted = u;
      const std::size_t k_in = static_cast<std::size_t>(unknowns_[c]);
      const double h = unit ? 1.0 : 1e-7 * std::max(1.0, std::fabs(u[k_in]));
      shifted[k_in] += h;
      int pc = 0;
      if (rhs(t, x, shifted, col, pc) != 0) return false;
      for (std::size_t k = 0; k < np; ++k) {
        const std::size_t row = nq + static_cast<std::size_t>(speed_of_[k]);
        B[k * nk + c] = (col[row] - xdot[row]) / h;
      }
    }
    return true;
  }

  /// The largest |v'_p - q''_p| of the rates xdot; r gets v'_p - q''_p.
  double miss(const std::vector<double>& xdot, const std::vector<double>& qdd, std::vector<double>& r) const {
    double worst = 0.0;
    for (std::size_t k = 0; k < pres_.size(); ++k) {
      r[k] = xdot[static_cast<std::size_t>(m_.nq) + static_cast<std::size_t>(speed_of_[k])] - qdd[k];
      if (!(std::fabs(r[k]) <= worst)) worst = std::fabs(r[k]);  // a NaN wins
    }
    return worst;
  }

  ModelTable m_;
  std::vector<Prescription> pres_;
  std::vector<int> unknowns_;
  std::vector<double> p_;
  std::vector<double> base_u_;
  InverseOptions opt_;
  std::string error_;
  std::vector<int> speed_of_;
};

}  // namespace mbsc::runtime
