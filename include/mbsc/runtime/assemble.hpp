// SPDX-License-Identifier: GPL-2.0-or-later WITH mbsc-runtime-exception
// (see LICENSE: this header may be included in applications under any terms)
#pragma once
/// Assembly: a consistent state from partial data, for a model generated with the full
/// state (x = (q0, q1)). The caller marks which coordinates and speeds are given; the
/// others start from the caller's guesses.
///   1. Newton on the position constraints over the free coordinates, each step the
///      least-squares solution of J_free dq = -g (column-pivoted QR, so redundant
///      constraints and extra free coordinates are fine: the surplus keeps its guess);
///   2. the velocity constraints, affine in the speeds (A v + b = 0), solved once for the
///      free speeds.
/// Failure says which constraint is left unsatisfied; a final Jacobian whose pivots
/// span more than `singular_ratio` is reported as near a singular configuration.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "mbsc/runtime/least_squares.hpp"
#include "mbsc/runtime/model_table.hpp"

namespace mbsc::runtime {

/// The generated functions assembly needs, filled from the generated header:
///   {F::kNq, F::kNu, F::kNposc, F::kNc, F::position_constraints, F::position_jacobian,
///    F::velocity_constraints, F::constraint_jacobian, F::kPositionConstraintNames,
///    F::kConstraintNames}
/// (a model without position constraints passes nullptr for the first two functions).
struct AssemblyModel {
  using Fn = int (*)(double, const double*, const double*, const double*, double*);
  int nq, nu, nposc, nc;
  Fn position_constraints;               // kNposc residuals
  Fn position_jacobian;                  // kNposc x kNq
  Fn velocity_constraints;               // kNc residuals, affine in the speeds
  Fn constraint_jacobian;                // kNc x kNu
  const char* const* position_names;     // kNposc names
  const char* const* constraint_names;   // kNc names
  /// Optional: kStateNames (for the names of the coordinates a failed assembly could not
  /// place) and kQuaternionIndices / kNquaternions: a quaternion with no guess, all four
  /// entries 0 and none given, starts at the identity, and one that assembly moves stays
  /// of unit length (|e|^2 = 1 joins the position rows: a quaternion off the unit sphere
  /// would scale its body).
  const char* const* state_names = nullptr;
  const int* quaternion_indices = nullptr;
  int nquaternions = 0;
};

/// The AssemblyModel of a model seen through its ModelTable (its full state), with the
/// state's unit quaternions (4 indices each, e0 first; `quaternion_indices` must outlive
/// the result).
inline AssemblyModel assembly_model_of(const ModelTable& t, const int* quaternion_indices, int nquaternions) {
  return {t.nq,
          t.nu,
          t.nposc,
          t.nc,
          t.nposc > 0 ? t.position_constraints : nullptr,
          t.nposc > 0 ? t.position_jacobian : nullptr,
          t.velocity_constraints,
          t.constraint_jacobian,
          t.position_constraint_names,
          t.constraint_names,
          t.state_names,
          quaternion_indices,
          nquaternions};
}

struct AssemblyOptions {
  double tolerance = 1e-12;     // on the largest residual, scaled by max(1, |x|)
  int max_iterations = 50;
  double singular_ratio = 1e8;  // largest / smallest pivot of the final Jacobian
};

struct AssemblyResult {
  enum class Status { Ok, PositionNotSolved, VelocityNotSolved, EvaluationFailed };
  Status status = Status::Ok;
  int iterations = 0;
  double position_residual = 0.0;  // largest |g| at the end
  double velocity_residual = 0.0;  // largest |A v + b| at the end
  int worst_constraint = -1;       // index into the position (or all) residuals when not solved
  bool near_singular = false;      // the last Jacobian's pivots span more than singular_ratio
  double pivot_ratio = 0.0;
  int position_rank = -1;          // numerical rank of the final Jacobian over the free coordinates
  int position_full_rank = 0;      // what it has at a regular point: min(kNposc, free coordinates)
  std::string message;             // what happened, naming the constraint on failure
  bool ok() const { return status == Status::Ok; }
};

/// The columns `cols` of a rows x ncols row-major matrix, row-major.
inline std::vector<double> select_columns(const std::vector<double>& M, int rows, int ncols, const std::vector<int>& cols) {
  std::vector<double> out(static_cast<std::size_t>(rows) * cols.size());
  for (int i = 0; i < rows; ++i)
    for (std::size_t k = 0; k < cols.size(); ++k)
      out[static_cast<std::size_t>(i) * cols.size() + k] =
          M[static_cast<std::size_t>(i) * static_cast<std::size_t>(ncols) + static_cast<std::size_t>(cols[k])];
  return out;
}

/// x: the full state (kNq + kNu), given entries set, the rest guessed. given_q[i] / given_u[j]
/// mark the coordinates / speeds that must not change.
inline AssemblyResult assemble(const AssemblyModel& m, double t, std::vector<double>& x, const std::vector<bool>& given_q,
                               const std::vector<bool>& given_u, const double* u, const double* p,
                               const AssemblyOptions& opt = {}) {
  AssemblyResult res;
  auto scale = [&]() {
    double s = 1.0;
    for (double e : x) s = std::max(s, std::fabs(e));
    return s;
  };
  auto worst = [](const std::vector<double>& r, int& at) {
    double w = 0.0;
    at = -1;
    for (std::size_t i = 0; i < r.size(); ++i)
      if (!(std::fabs(r[i]) <= w)) w = std::fabs(r[i]), at = static_cast<int>(i);
    return w;
  };
  // A quaternion with no guess starts at the identity (at zero it is no rotation at all).
  for (int k = 0; m.quaternion_indices && k < m.nquaternions; ++k) {
    const int* e = m.quaternion_indices + 4 * k;
    bool unset = true;
    for (int c = 0; c < 4; ++c) unset = unset && x[static_cast<std::size_t>(e[c])] == 0.0 && !given_q[static_cast<std::size_t>(e[c])];
    if (unset) x[static_cast<std::size_t>(e[0])] = 1.0;
  }
  // ---- positions ----
  std::vector<int> free_q;
  for (int i = 0; i < m.nq; ++i)
    if (!given_q[static_cast<std::size_t>(i)]) free_q.push_back(i);
  // The unit quaternions assembly may move: each adds the row |e|^2 - 1 after the model's.
  std::vector<const int*> moved_quaternions;
  for (int k = 0; m.quaternion_indices && k < m.nquaternions; ++k) {
    const int* e = m.quaternion_indices + 4 * k;
    bool free = false;
    for (int c = 0; c < 4; ++c) free = free || !given_q[static_cast<std::size_t>(e[c])];
    if (free) moved_quaternions.push_back(e);
  }
  const int nrows = m.nposc + static_cast<int>(moved_quaternions.size());
  // g and J with the unit rows below the model's (residual and gradient 2 e).
  auto unit_rows = [&](std::vector<double>& g, std::vector<double>* J) {
    for (std::size_t k = 0; k < moved_quaternions.size(); ++k) {
      const std::size_t row = static_cast<std::size_t>(m.nposc) + k;
      double norm2 = 0.0;
      for (int c = 0; c < 4; ++c) {
        const std::size_t at = static_cast<std::size_t>(moved_quaternions[k][c]);
        norm2 += x[at] * x[at];
        if (J) (*J)[row * static_cast<std::size_t>(m.nq) + at] = 2.0 * x[at];
      }
      g[row] = norm2 - 1.0;
    }
  };
  if (m.nposc > 0) {
    std::vector<double> g(static_cast<std::size_t>(nrows)), J(static_cast<std::size_t>(nrows) * static_cast<std::size_t>(m.nq), 0.0);
    for (;;) {
      if (m.position_constraints(t, x.data(), u, p, g.data()) != 0) {
        res.status = AssemblyResult::Status::EvaluationFailed;
        res.message = "the position constraints could not be evaluated (non-finite value) at the current guess";
        return res;
      }
      unit_rows(g, nullptr);
      res.position_residual = worst(g, res.worst_constraint);
      if (res.position_residual <= opt.tolerance * scale()) break;
      if (res.iterations == opt.max_iterations || free_q.empty()) {
        res.status = AssemblyResult::Status::PositionNotSolved;
        const std::string name = res.worst_constraint < 0           ? "?"
                                 : res.worst_constraint < m.nposc ? m.position_names[res.worst_constraint]
                                 : m.state_names ? std::string("|") + m.state_names[moved_quaternions[static_cast<std::size_t>(res.worst_constraint - m.nposc)][0]] + "...| = 1"
                                                 : "a unit quaternion";
        res.message = "position constraint '" + name + "' cannot be satisfied from the given data (residual " +
                      std::to_string(res.position_residual) + " after " + std::to_string(res.iterations) + " Newton steps)";
        // Which coordinates it could move: the free ones its row reads.
        if (m.state_names && res.worst_constraint >= 0 && !free_q.empty() &&
            m.position_jacobian(t, x.data(), u, p, J.data()) == 0) {
          std::string reads;
          for (int c : free_q)
            if (J[static_cast<std::size_t>(res.worst_constraint) * static_cast<std::size_t>(m.nq) + static_cast<std::size_t>(c)] != 0.0)
              reads += (reads.empty() ? "" : ", ") + std::string(m.state_names[c]);
          res.message += reads.empty() ? "; it reads no coordinate that assembly may move: give one of its coordinates a guess "
                                         "instead of a fixed value"
                                       : "; the coordinates it could not place: " + reads +
                                             " (a guess nearer the mechanism for them, `initial guess` or --init, may help)";
        } else if (free_q.empty()) {
          res.message += "; every coordinate is given, so nothing can move: give guesses instead of fixed values";
        }
        return res;
      }
      if (m.position_jacobian(t, x.data(), u, p, J.data()) != 0) {
        res.status = AssemblyResult::Status::EvaluationFailed;
        res.message = "the position Jacobian could not be evaluated (non-finite value)";
        return res;
      }
      unit_rows(g, &J);
      std::vector<double> rhs(static_cast<std::size_t>(nrows));
      for (int i = 0; i < nrows; ++i) rhs[static_cast<std::size_t>(i)] = -g[static_cast<std::size_t>(i)];
      const LeastSquares step =
          solve_least_squares(select_columns(J, nrows, m.nq, free_q), rhs, nrows, static_cast<int>(free_q.size()));
      for (std::size_t k = 0; k < free_q.size(); ++k) x[static_cast<std::size_t>(free_q[k])] += step.x[k];
      res.pivot_ratio = step.smallest_pivot > 0 ? step.largest_pivot / step.smallest_pivot : INFINITY;
      ++res.iterations;
    }
    // Conditioning where we ended (also when the guess was already consistent).
    // (The unit rows count: they fix each moved quaternion's length.)
    if (!free_q.empty() && m.position_jacobian(t, x.data(), u, p, J.data()) == 0) {
      unit_rows(g, &J);
      const LeastSquares at_end = solve_least_squares(select_columns(J, nrows, m.nq, free_q),
                                                      std::vector<double>(static_cast<std::size_t>(nrows), 0.0), nrows,
                                                      static_cast<int>(free_q.size()));
      res.pivot_ratio = at_end.smallest_pivot > 0 ? at_end.largest_pivot / at_end.smallest_pivot : INFINITY;
      res.position_rank = at_end.rank;
      res.position_full_rank = std::min(nrows, static_cast<int>(free_q.size()));
    }
  }
  // ---- speeds: A v + b = 0 for the free ones ----
  if (m.nc > 0) {
    const std::size_t nq = static_cast<std::size_t>(m.nq);
    std::vector<int> free_u;
    for (int j = 0; j < m.nu; ++j)
      if (!given_u[static_cast<std::size_t>(j)]) {
        free_u.push_back(j);
        x[nq + static_cast<std::size_t>(j)] = 0.0;
      }
    std::vector<double> A(static_cast<std::size_t>(m.nc) * static_cast<std::size_t>(m.nu)), r(static_cast<std::size_t>(m.nc));
    if (m.constraint_jacobian(t, x.data(), u, p, A.data()) != 0 || m.velocity_constraints(t, x.data(), u, p, r.data()) != 0) {
      res.status = AssemblyResult::Status::EvaluationFailed;
      res.message = "the velocity constraints could not be evaluated (non-finite value)";
      return res;
    }
    std::vector<double> rhs(static_cast<std::size_t>(m.nc));
    for (int i = 0; i < m.nc; ++i) rhs[static_cast<std::size_t>(i)] = -r[static_cast<std::size_t>(i)];
    const LeastSquares v = solve_least_squares(select_columns(A, m.nc, m.nu, free_u), rhs, m.nc, static_cast<int>(free_u.size()));
    for (std::size_t k = 0; k < free_u.size(); ++k) x[nq + static_cast<std::size_t>(free_u[k])] = v.x[k];
    m.velocity_constraints(t, x.data(), u, p, r.data());
    int at = -1;
    res.velocity_residual = worst(r, at);
    if (!(res.velocity_residual <= opt.tolerance * scale())) {
      res.status = AssemblyResult::Status::VelocityNotSolved;
      res.worst_constraint = at;
      res.message = std::string("velocity constraint '") + (at >= 0 ? m.constraint_names[at] : "?") +
                    "' cannot be satisfied with the given speeds (residual " + std::to_string(res.velocity_residual) + ")";
      return res;
    }
  }
  const bool rank_drop = res.position_rank >= 0 && res.position_rank < res.position_full_rank;
  res.near_singular = res.pivot_ratio > opt.singular_ratio || rank_drop;
  res.message = res.near_singular ? "assembled, but near a singular configuration (Jacobian pivots span " +
                                        std::to_string(res.pivot_ratio) +
                                        (rank_drop ? "; Jacobian rank " + std::to_string(res.position_rank) + " instead of " +
                                                         std::to_string(res.position_full_rank)
                                                   : std::string()) +
                                        ")"
                                  : "assembled";
  return res;
}

}  // namespace mbsc::runtime
