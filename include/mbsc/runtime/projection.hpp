// SPDX-License-Identifier: GPL-2.0-or-later WITH mbsc-runtime-exception
// (see LICENSE: this header may be included in applications under any terms)
#pragma once
/// Projection of a full state x = (q, v) back onto the constraint manifold, for use after
/// an accepted integration step (the integrator only keeps the constraints to its
/// tolerance, and errors add up over a long run):
///   1. positions: Newton on g(q) = 0 with the position Jacobian J, each correction the
///      minimum-norm solution of J dq = -g, so the point moves the shortest way onto the
///      manifold (redundant constraints are fine: dependent rows are dropped);
///   2. speeds: one minimum-norm correction of v onto A v + b = 0 at the new positions
///      (the velocity constraints are affine in v).
/// Works through a ModelTable whose state is the full one (nq == nq_full); a model
/// without constraints is left alone. Coordinates and speeds can be held (not moved):
/// the correction is then the shortest one in the others (e.g. keep the independent
/// coordinates of the complement form, whose own integration error is smallest, and let
/// the dependent ones absorb the drift).
///
///   ProjectionReport r = project(model, t, x, u, p);
///   if (!r.ok()) ... r.message ...
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "mbsc/runtime/model_table.hpp"

namespace mbsc::runtime {

/// The minimum-norm solution of A dx = r (A m x n row-major): Gram-Schmidt on the rows
/// with pivoting (the row of largest remaining norm first, orthogonalized twice), rows
/// whose remaining norm falls below rel_tol times the largest are dependent and dropped.
/// dx lies in the row space of A, which makes it the shortest correction. Returns the
/// rank found.
inline int minimum_norm_solve(const std::vector<double>& A, const std::vector<double>& r, int m, int n,
                              std::vector<double>& dx, double rel_tol = 1e-10) {
  const std::size_t M = static_cast<std::size_t>(m), N = static_cast<std::size_t>(n);
  std::vector<double> W(A);  // rows, orthogonalized in place against the basis so far
  std::vector<std::vector<double>> basis;
  std::vector<double> z;                          // dx = sum z_k basis_k
  std::vector<std::vector<double>> coef(M);       // coef[i][k] = <row i, basis_k>
  std::vector<bool> used(M, false);
  dx.assign(N, 0.0);
  auto row = [&](std::size_t i) { return &W[i * N]; };
  auto norm = [&](std::size_t i) {
    double s = 0.0;
    for (std::size_t j = 0; j < N; ++j) s += row(i)[j] * row(i)[j];
    return std::sqrt(s);
  };
  double first = 0.0;
  for (std::size_t k = 0; k < std::min(M, N); ++k) {
    std::size_t best = M;
    double best_norm = -1.0;
    for (std::size_t i = 0; i < M; ++i)
      if (!used[i]) {
        const double nr = norm(i);
        if (nr > best_norm) best_norm = nr, best = i;
      }
    if (best == M) break;
    if (k == 0) first = best_norm;
    if (!(best_norm > rel_tol * first) || best_norm == 0.0) break;
    used[best] = true;
    std::vector<double> q(row(best), row(best) + N);
    for (double& e : q) e /= best_norm;
    // The chosen row is sum_j coef[best][j] basis_j + best_norm q: solve for z_k.
    double s = r[best];
    for (std::size_t j = 0; j < basis.size(); ++j) s -= coef[best][j] * z[j];
    z.push_back(s / best_norm);
    coef[best].push_back(best_norm);
    // Remove q from the other rows (twice, for orthogonality in finite precision).
    for (std::size_t i = 0; i < M; ++i) {
      if (used[i]) continue;
      double c = 0.0;
      for (int pass = 0; pass < 2; ++pass) {
        double d = 0.0;
        for (std::size_t j = 0; j < N; ++j) d += row(i)[j] * q[j];
        for (std::size_t j = 0; j < N; ++j) row(i)[j] -= d * q[j];
        c += d;
      }
      coef[i].push_back(c);
    }
    basis.push_back(std::move(q));
  }
  for (std::size_t k = 0; k < basis.size(); ++k)
    for (std::size_t j = 0; j < N; ++j) dx[j] += z[k] * basis[k][j];
  return static_cast<int>(basis.size());
}

struct ProjectionOptions {
  double position_tolerance = 1e-13;  // Newton stops when the largest |g| is below this times max(1, |q|)
  int max_iterations = 10;
  double rank_tolerance = 1e-10;      // relative: rows of J (or A) below this are treated as dependent
  bool velocities = true;             // also project the speeds
  std::vector<bool> hold_q;           // coordinates kept as they are (empty: none)
  std::vector<bool> hold_u;           // speeds kept as they are (empty: none)
};

/// The columns of a rows x cols row-major matrix that `hold` does not mark, and their indices.
inline std::vector<double> free_columns(const std::vector<double>& M, int rows, int cols, const std::vector<bool>& hold,
                                        std::vector<std::size_t>& index) {
  index.clear();
  for (int j = 0; j < cols; ++j)
    if (hold.empty() || !hold[static_cast<std::size_t>(j)]) index.push_back(static_cast<std::size_t>(j));
  std::vector<double> out(static_cast<std::size_t>(rows) * index.size());
  for (std::size_t i = 0; i < static_cast<std::size_t>(rows); ++i)
    for (std::size_t k = 0; k < index.size(); ++k) out[i * index.size() + k] = M[i * static_cast<std::size_t>(cols) + index[k]];
  return out;
}

struct ProjectionReport {
  enum class Status { Ok, NotConverged, EvaluationFailed, NotFullState };
  Status status = Status::Ok;
  double position_before = 0.0, position_after = 0.0;  // largest |g|
  double velocity_before = 0.0, velocity_after = 0.0;  // largest |A v + b|
  int iterations = 0;
  int position_rank = -1;  // rank of J at the last Newton step (-1: none taken)
  std::string message;
  bool ok() const { return status == Status::Ok; }
};

/// Largest |g| and |A v + b| at (t, x); false when the functions fail.
inline bool constraint_residuals(const ModelTable& m, double t, const double* x, const double* u, const double* p,
                                 double& position, double& velocity) {
  position = velocity = 0.0;
  std::vector<double> r(static_cast<std::size_t>(std::max(m.nposc, m.nc)));
  if (m.nposc > 0) {
    if (m.position_constraints(t, x, u, p, r.data()) != 0) return false;
    for (int i = 0; i < m.nposc; ++i) position = std::max(position, std::fabs(r[static_cast<std::size_t>(i)]));
  }
  if (m.nc > 0) {
    if (m.velocity_constraints(t, x, u, p, r.data()) != 0) return false;
    for (int i = 0; i < m.nc; ++i) velocity = std::max(velocity, std::fabs(r[static_cast<std::size_t>(i)]));
  }
  return std::isfinite(position) && std::isfinite(velocity);
}

/// Projects x (the full state, kNx entries) in place. The residuals before and after are
/// in the report; on failure x keeps the last good iterate and the message says why.
inline ProjectionReport project(const ModelTable& m, double t, std::vector<double>& x, const double* u, const double* p,
                                const ProjectionOptions& o = {}) {
  ProjectionReport rep;
  if (!m.full_state_layout()) {
    rep.status = ProjectionReport::Status::NotFullState;
    rep.message = "projection needs the full state (the model was generated with --state minimal)";
    return rep;
  }
  if (!constraint_residuals(m, t, x.data(), u, p, rep.position_before, rep.velocity_before)) {
    rep.status = ProjectionReport::Status::EvaluationFailed;
    rep.message = "the constraints could not be evaluated (non-finite value) at t = " + std::to_string(t);
    return rep;
  }
  const std::size_t nq = static_cast<std::size_t>(m.nq), nu = static_cast<std::size_t>(m.nu);
  // ---- positions ----
  if (m.nposc > 0) {
    const std::size_t nposc = static_cast<std::size_t>(m.nposc);
    std::vector<double> g(nposc), J(nposc * nq), dq;
    double scale = 1.0;
    for (std::size_t i = 0; i < nq; ++i) scale = std::max(scale, std::fabs(x[i]));
    double worst = rep.position_before;
    while (worst > o.position_tolerance * scale) {
      if (rep.iterations == o.max_iterations) {
        rep.status = ProjectionReport::Status::NotConverged;
        rep.message = "position projection did not converge at t = " + std::to_string(t) + " (largest residual " +
                      std::to_string(worst) + " after " + std::to_string(rep.iterations) + " Newton steps)";
        break;
      }
      if (m.position_constraints(t, x.data(), u, p, g.data()) != 0 || m.position_jacobian(t, x.data(), u, p, J.data()) != 0) {
        rep.status = ProjectionReport::Status::EvaluationFailed;
        rep.message = "the position constraints or their Jacobian failed at t = " + std::to_string(t);
        return rep;
      }
      for (double& e : g) e = -e;
      std::vector<std::size_t> cols;
      const std::vector<double> Jf = free_columns(J, m.nposc, m.nq, o.hold_q, cols);
      rep.position_rank = minimum_norm_solve(Jf, g, m.nposc, static_cast<int>(cols.size()), dq, o.rank_tolerance);
      for (std::size_t k = 0; k < cols.size(); ++k) x[cols[k]] += dq[k];
      ++rep.iterations;
      if (m.position_constraints(t, x.data(), u, p, g.data()) != 0) {
        rep.status = ProjectionReport::Status::EvaluationFailed;
        rep.message = "the position constraints failed at t = " + std::to_string(t);
        return rep;
      }
      const double before = worst;
      worst = 0.0;
      for (double e : g) worst = std::max(worst, std::fabs(e));
      if (!std::isfinite(worst)) {
        rep.status = ProjectionReport::Status::EvaluationFailed;
        rep.message = "position projection produced a non-finite residual at t = " + std::to_string(t);
        return rep;
      }
      // Stalled at rounding level (an inconsistent redundant row): stop, keep what we have.
      if (worst >= 0.5 * before && worst < 1e3 * o.position_tolerance * scale) break;
    }
  }
  // ---- speeds ----
  if (o.velocities && m.nc > 0) {
    const std::size_t nc = static_cast<std::size_t>(m.nc);
    std::vector<double> r(nc), A(nc * nu), dv;
    if (m.velocity_constraints(t, x.data(), u, p, r.data()) != 0 || m.constraint_jacobian(t, x.data(), u, p, A.data()) != 0) {
      rep.status = ProjectionReport::Status::EvaluationFailed;
      rep.message = "the velocity constraints or their Jacobian failed at t = " + std::to_string(t);
      return rep;
    }
    for (double& e : r) e = -e;
    std::vector<std::size_t> cols;
    const std::vector<double> Af = free_columns(A, m.nc, m.nu, o.hold_u, cols);
    minimum_norm_solve(Af, r, m.nc, static_cast<int>(cols.size()), dv, o.rank_tolerance);
    for (std::size_t k = 0; k < cols.size(); ++k) x[nq + cols[k]] += dv[k];
  }
  if (!constraint_residuals(m, t, x.data(), u, p, rep.position_after, rep.velocity_after)) {
    rep.status = ProjectionReport::Status::EvaluationFailed;
    rep.message = "the constraints could not be evaluated after the projection at t = " + std::to_string(t);
  }
  return rep;
}

}  // namespace mbsc::runtime
