// SPDX-License-Identifier: GPL-2.0-or-later WITH mbsc-runtime-exception
// (see LICENSE: this header may be included in applications under any terms)
#pragma once
/// Integration through configurations where the constraint set loses rank for an instant
/// (docs/formulation.md, "Rank loss: continuing on the branch"): a chain of parallelogram
/// four-bars passing its flat poses, where no choice of independent speeds is regular and
/// the multipliers' Schur complement is singular too. The generated rhs is exact on the
/// constraint manifold but near such a point its solves are ill-conditioned, so the
/// small constraint residuals of a Runge-Kutta stage are amplified, and at the point it
/// fails. This wrapper
///   * evaluates, near the singular point (conditioning below `near_below` times the
///     conditioning met away from it), the rhs at
///     the stage state projected onto the manifold (least-squares, minimum-norm Newton
///     steps on the positions, then on the velocities), so no residual is amplified;
///   * very near it (below `bridge_below`), where even that projection could fall onto
///     the other branch of the crossing, takes the mean of the rhs at two projected
///     states shifted along the motion, x(+eta) and x(-eta) with the coordinates moved by
///     +-eta times their rates: the acceleration is smooth along the physical branch, so
///     the mean is that acceleration to O(eta^2), and eta grows only until both points
///     are well conditioned.
/// The velocity carries the branch through the crossing (the parallelogram and the
/// anti-parallelogram meet there with different tangents), so a state at rest exactly
/// at a bifurcation point is refused (status 1). Works for both formulations (the
/// conditioning of the multipliers form reports its Schur complement). Coordinates must
/// be integrated as their own rates (q' = q1: bodies and particles in absolute
/// coordinates); otherwise a bridged evaluation returns 1.
///
///   mbsc::runtime::BranchContinuation bc(table, u, p);
///   Rhs f = bc.as_rhs();                       // give f to any Stepper / rk4_step
///   after each accepted step: bc.correct(t, x) (projects when a residual exceeds
///   drift_tol; optional, but it keeps the residuals the near-singular solves see small)
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <vector>

#include "least_squares.hpp"
#include "model_table.hpp"
#include "stepper.hpp"

namespace mbsc::runtime {

struct BranchSettings {
  /// Below this fraction of the reference conditioning (the largest conditioning_partition
  /// report met so far, first measured at states shifted 0.3 rad-ish along the motion) the
  /// rhs is evaluated at the projected stage state; 0: the default of the formulation.
  double near_below = 0.0;
  /// Below this fraction it is bridged by the mean of two shifted, projected states,
  /// which must reach 4 times it; 0: the default. Defaults: complement form 2e-2 and
  /// 2e-4 (its blocks' rcond falls like the distance to the singular point: on the
  /// 3-window parallelogram chain from 0.046 to 0.046 times the angle), multipliers
  /// form 1e-5 and 1e-9 (the Schur complement's rcond falls like its square).
  double bridge_below = 0.0;
  /// Residuals (max norm) a projection must reach.
  double position_tol = 1e-12;
  double velocity_tol = 1e-12;
  int max_newton = 25;
  /// correct() projects only above this residual.
  double drift_tol = 1e-10;
};

class BranchContinuation {
 public:
  BranchContinuation(const ModelTable& m, const double* u, const double* p, BranchSettings s = {})
      : m_(m), u_(u), p_(p), s_(s) {
    if (s_.near_below <= 0.0) s_.near_below = m.multipliers ? 1e-5 : 2e-2;
    if (s_.bridge_below <= 0.0) s_.bridge_below = m.multipliers ? 1e-9 : 2e-4;
  }

  /// The partition whose rhs and conditioning are used (a PartitionSelector's active one).
  void set_partition(int k) { partition_ = k; }

  /// The state derivative, robust near rank loss (see above). 0, or a non-zero status.
  int rhs(double t, const double* x, double* xdot) {
    const double rc = measured_conditioning(t, x);
    if (rc >= s_.near_below * reference_) return m_.rhs_partition(partition_, t, x, u_, p_, xdot);
    std::vector<double> y(x, x + m_.nx);
    if (rc >= s_.bridge_below * reference_ && project(t, y.data()) == 0 &&
        conditioning(t, y.data()) >= s_.bridge_below * reference_) {
      ++projected_;
      return m_.rhs_partition(partition_, t, y.data(), u_, p_, xdot);
    }
    return bridge(t, x, xdot);
  }

  Rhs as_rhs() {
    return [this](double t, const double* x, double* xdot) { return rhs(t, x, xdot); };
  }

  /// Projects x onto the position manifold, then its velocities onto the velocity
  /// constraints (minimum-norm corrections). 0, or 1 when Newton does not converge.
  int project(double t, double* x) {
    if (!m_.full_state_layout()) return 1;
    if (newton(t, x, /*velocity=*/false) != 0) return 1;
    return newton(t, x, /*velocity=*/true);
  }
  int project(double t, std::vector<double>& x) { return project(t, x.data()); }

  /// What the simulation loop calls after each accepted step: projects x (as `project`)
  /// only when a constraint residual exceeds `drift_tol`, so a large model pays for the
  /// least-squares solves only every so often. 0, or 1 when a projection fails.
  int correct(double t, std::vector<double>& x) {
    if (!m_.full_state_layout()) return 0;
    std::vector<double> r(static_cast<std::size_t>(std::max(m_.nposc, m_.nc)));
    double worst = 0.0;
    if (m_.nposc > 0 && m_.position_constraints(t, x.data(), u_, p_, r.data()) != 0) return 1;
    for (int i = 0; i < m_.nposc; ++i) worst = std::max(worst, std::abs(r[static_cast<std::size_t>(i)]));
    if (m_.nc > 0 && m_.velocity_constraints(t, x.data(), u_, p_, r.data()) != 0) return 1;
    for (int i = 0; i < m_.nc; ++i) worst = std::max(worst, std::abs(r[static_cast<std::size_t>(i)]));
    if (!(worst == worst)) return 1;
    return worst > s_.drift_tol ? project(t, x.data()) : 0;
  }

  /// The same to rounding (residuals 1e-15 of the state's size, accepting 1e-13): where the rhs is read for
  /// an extrapolation (singular_crossing.hpp), a residual left would be amplified.
  int project_tight(double t, double* x) {
    const BranchSettings kept = s_;
    double scale = 1.0;  // rounding of the residuals grows with the state's size
    for (int i = 0; i < m_.nx; ++i) scale = std::max(scale, std::abs(x[i]));
    s_.position_tol = s_.velocity_tol = 1e-15 * scale;
    s_.max_newton = std::max(s_.max_newton, 40);
    const int status = project(t, x);
    s_ = kept;
    return status;
  }

  /// The conditioning at x relative to the reference (1 well away from any rank loss,
  /// 0 at it).
  double relative_conditioning(double t, const double* x) {
    const double rc = measured_conditioning(t, x);
    return reference_ > 0.0 ? rc / reference_ : 0.0;
  }
  /// Below this relative conditioning the rhs is evaluated at a projected state.
  double near_threshold() const { return s_.near_below; }
  /// How the conditioning falls towards a rank loss at distance d: like d^power (the
  /// complement form's blocks: 1; the multipliers form's Schur complement: 2).
  int conditioning_power() const { return m_.multipliers ? 2 : 1; }

  /// How many rhs evaluations were made at a projected state, and how many bridged.
  long projected() const { return projected_; }
  long bridged() const { return bridged_; }
  /// The reference conditioning the thresholds are fractions of.
  double reference() const { return reference_; }

 private:
  // The reference conditioning, first from states well away along the motion (a run may
  // start exactly on the singular point, where the conditioning says nothing of scale).
  void seed(double t, const double* x) {
    seeded_ = true;
    const int nq = m_.nq;
    double vmax = 0.0;
    for (int i = 0; i < nq && nq <= m_.nu; ++i) vmax = std::max(vmax, std::abs(x[nq + i]));
    if (!(vmax > 0.0)) return;
    std::vector<double> y(x, x + m_.nx);
    for (double sign : {1.0, -1.0}) {
      for (int i = 0; i < nq; ++i) y[static_cast<std::size_t>(i)] = x[i] + sign * 0.3 / vmax * x[nq + i];
      reference_ = std::max(reference_, conditioning(t, y.data()));
    }
  }

  // The conditioning at x, raising the reference to it (seeded first).
  double measured_conditioning(double t, const double* x) {
    if (!seeded_) seed(t, x);
    const double rc = conditioning(t, x);
    reference_ = std::max(reference_, rc);
    return rc;
  }

  double conditioning(double t, const double* x) const {
    double rc = 0.0;
    return m_.conditioning_partition(partition_, t, x, u_, p_, &rc) == 0 ? rc : 0.0;
  }

  // Gauss-Newton with minimum-norm steps d = J^T y, (J J^T) y = -r solved by rank-revealing
  // QR: redundant rows (a rank loss) get no correction instead of a huge one.
  int newton(double t, double* x, bool velocity) {
    const int rows = velocity ? m_.nc : m_.nposc;
    const int cols = velocity ? m_.nu : m_.nq;
    if (rows == 0) return 0;
    double* v = velocity ? x + m_.nq : x;
    const double tol = velocity ? s_.velocity_tol : s_.position_tol;
    std::vector<double> r(static_cast<std::size_t>(rows)), J(static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols));
    std::vector<double> JJ(static_cast<std::size_t>(rows) * static_cast<std::size_t>(rows));
    double last = 0.0, previous = 0.0;
    for (int it = 0; it <= s_.max_newton; ++it) {
      const int st = velocity ? m_.velocity_constraints(t, x, u_, p_, r.data()) : m_.position_constraints(t, x, u_, p_, r.data());
      if (st != 0) return 1;
      last = 0.0;
      for (double e : r) last = std::max(last, std::abs(e));
      if (!(last == last)) return 1;
      // Done at the tolerance, or where rounding stops the progress within 100 times it.
      if (last <= tol || it == s_.max_newton || (it > 0 && last > 0.5 * previous && last <= 100.0 * tol)) break;
      previous = last;
      const int sj = velocity ? m_.constraint_jacobian(t, x, u_, p_, J.data()) : m_.position_jacobian(t, x, u_, p_, J.data());
      if (sj != 0) return 1;
      for (int i = 0; i < rows; ++i)
        for (int k = i; k < rows; ++k) {
          double s = 0.0;
          const double* a = &J[static_cast<std::size_t>(i) * static_cast<std::size_t>(cols)];
          const double* b = &J[static_cast<std::size_t>(k) * static_cast<std::size_t>(cols)];
          for (int j = 0; j < cols; ++j) s += a[j] * b[j];
          JJ[static_cast<std::size_t>(i * rows + k)] = JJ[static_cast<std::size_t>(k * rows + i)] = s;
        }
      std::vector<double> minus_r(r.size());
      for (std::size_t i = 0; i < r.size(); ++i) minus_r[i] = -r[i];
      const auto ls = solve_least_squares(JJ, minus_r, rows, rows, 1e-14);
      for (int j = 0; j < cols; ++j) {
        double s = 0.0;
        for (int i = 0; i < rows; ++i) s += J[static_cast<std::size_t>(i) * static_cast<std::size_t>(cols) + static_cast<std::size_t>(j)] * ls.x[static_cast<std::size_t>(i)];
        v[j] += s;
      }
    }
    // Rounding may stop a little above a very tight tolerance: accept 100x.
    return last <= 100.0 * tol ? 0 : 1;
  }

  // Mean of the rhs at two projected states shifted by +-eta along the motion.
  int bridge(double t, const double* x, double* xdot) {
    const int nq = m_.nq;
    if (!m_.full_state_layout() || m_.nq != m_.nu) return 1;
    double vmax = 0.0;
    for (int i = 0; i < nq; ++i) vmax = std::max(vmax, std::abs(x[nq + i]));
    if (!(vmax > 0.0)) return 1;  // at rest on a bifurcation point: no branch to follow
    std::vector<double> plus(x, x + m_.nx), minus(plus), dp(static_cast<std::size_t>(m_.nx)), dm(dp);
    // Start at a shift that moves some coordinate by 1e-8 and grow it fourfold.
    for (double eta = 1e-8 / vmax; eta * vmax < 0.1; eta *= 4.0) {
      for (int i = 0; i < nq; ++i) {
        plus[static_cast<std::size_t>(i)] = x[i] + eta * x[nq + i];
        minus[static_cast<std::size_t>(i)] = x[i] - eta * x[nq + i];
      }
      for (int i = nq; i < m_.nx; ++i) plus[static_cast<std::size_t>(i)] = minus[static_cast<std::size_t>(i)] = x[i];
      if (project(t, plus.data()) != 0 || project(t, minus.data()) != 0) continue;
      const double enough = 4.0 * s_.bridge_below * reference_;
      if (conditioning(t, plus.data()) < enough || conditioning(t, minus.data()) < enough) continue;
      if (m_.rhs_partition(partition_, t, plus.data(), u_, p_, dp.data()) != 0 ||
          m_.rhs_partition(partition_, t, minus.data(), u_, p_, dm.data()) != 0)
        continue;
      // The coordinates' rates must be their speeds (checked on the shifted states).
      for (int i = 0; i < nq; ++i)
        if (std::abs(dp[static_cast<std::size_t>(i)] - plus[static_cast<std::size_t>(nq + i)]) > 1e-12 * (1.0 + vmax)) return 1;
      for (int i = 0; i < nq; ++i) xdot[i] = x[nq + i];
      for (int i = nq; i < m_.nx; ++i) xdot[i] = 0.5 * (dp[static_cast<std::size_t>(i)] + dm[static_cast<std::size_t>(i)]);
      ++bridged_;
      return 0;
    }
    return 1;
  }

  ModelTable m_;  // a copy: plain data and function pointers
  const double* u_;
  const double* p_;
  BranchSettings s_;
  int partition_ = 0;
  long projected_ = 0;
  long bridged_ = 0;
  bool seeded_ = false;
  double reference_ = 0.0;
};

}  // namespace mbsc::runtime
