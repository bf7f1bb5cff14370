// SPDX-License-Identifier: GPL-2.0-or-later WITH mbsc-runtime-exception
// (see LICENSE: this header may be included in applications under any terms)
#pragma once
/// Householder QR with column pivoting that keeps Q, for the linear model
/// (runtime/linear_model.hpp): orthonormal bases of a matrix's range and null space,
/// and minimum-norm solutions of consistent, possibly rank-deficient systems. Dense,
/// row-major, standard library only; sized for models (tens to a few hundred unknowns).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace mbsc::runtime {

/// M P = Q R for an m x n matrix M: Q m x m orthogonal, R m x n upper trapezoidal, P the
/// column permutation (perm[k] = the column of M in position k), rank = the pivots above
/// rel_tol times the largest.
struct PivotedQR {
  int m = 0, n = 0, rank = 0;
  std::vector<double> Q, R;  // row-major
  std::vector<int> perm;
  double q(int i, int j) const { return Q[static_cast<std::size_t>(i) * static_cast<std::size_t>(m) + static_cast<std::size_t>(j)]; }
  double r(int i, int j) const { return R[static_cast<std::size_t>(i) * static_cast<std::size_t>(n) + static_cast<std::size_t>(j)]; }
};

inline PivotedQR pivoted_qr(const std::vector<double>& M, int m, int n, double rel_tol = 1e-10) {
  PivotedQR f;
  f.m = m, f.n = n;
  f.R = M;
  f.Q.assign(static_cast<std::size_t>(m) * static_cast<std::size_t>(m), 0.0);
  for (int i = 0; i < m; ++i) f.Q[static_cast<std::size_t>(i) * static_cast<std::size_t>(m) + static_cast<std::size_t>(i)] = 1.0;
  f.perm.resize(static_cast<std::size_t>(n));
  for (int j = 0; j < n; ++j) f.perm[static_cast<std::size_t>(j)] = j;
  auto R = [&](int i, int j) -> double& { return f.R[static_cast<std::size_t>(i) * static_cast<std::size_t>(n) + static_cast<std::size_t>(j)]; };
  auto Q = [&](int i, int j) -> double& { return f.Q[static_cast<std::size_t>(i) * static_cast<std::size_t>(m) + static_cast<std::size_t>(j)]; };
  double largest = 0.0;
  std::vector<double> v(static_cast<std::size_t>(m));
  for (int k = 0; k < std::min(m, n); ++k) {
    // The remaining column of largest norm first (rows k..m-1).
    int best = k;
    double best_sq = -1.0;
    for (int j = k; j < n; ++j) {
      double s = 0.0;
      for (int i = k; i < m; ++i) s += R(i, j) * R(i, j);
      if (s > best_sq) best_sq = s, best = j;
    }
    const double norm = std::sqrt(std::max(best_sq, 0.0));
    if (k == 0) largest = norm;
    if (norm == 0.0 || norm <= rel_tol * largest) break;
    if (best != k) {
      for (int i = 0; i < m; ++i) std::swap(R(i, k), R(i, best));
      std::swap(f.perm[static_cast<std::size_t>(k)], f.perm[static_cast<std::size_t>(best)]);
    }
    f.rank = k + 1;
    // H = I - 2 v v^T / v^T v maps column k (rows k..) to (alpha, 0, ..., 0).
    const double alpha = R(k, k) > 0 ? -norm : norm;
    double vv = 0.0;
    for (int i = k; i < m; ++i) v[static_cast<std::size_t>(i)] = R(i, k);
    v[static_cast<std::size_t>(k)] -= alpha;
    for (int i = k; i < m; ++i) vv += v[static_cast<std::size_t>(i)] * v[static_cast<std::size_t>(i)];
    if (vv == 0.0) continue;
    for (int j = k; j < n; ++j) {
      double s = 0.0;
      for (int i = k; i < m; ++i) s += v[static_cast<std::size_t>(i)] * R(i, j);
      s *= 2.0 / vv;
      for (int i = k; i < m; ++i) R(i, j) -= s * v[static_cast<std::size_t>(i)];
    }
    for (int i = k + 1; i < m; ++i) R(i, k) = 0.0;
    // Q := Q H (Q accumulates the reflections: M P = Q R).
    for (int i = 0; i < m; ++i) {
      double s = 0.0;
      for (int l = k; l < m; ++l) s += Q(i, l) * v[static_cast<std::size_t>(l)];
      s *= 2.0 / vv;
      for (int l = k; l < m; ++l) Q(i, l) -= s * v[static_cast<std::size_t>(l)];
    }
  }
  return f;
}

/// The factorization of M^T (M: rows x cols) that solves M x = c with the minimum norm
/// and gives M's null space: with M^T P = Q R, M = P R^T Q^T.
struct RowSpaceSolver {
  PivotedQR f;  // of M^T (cols x rows)
  RowSpaceSolver(const std::vector<double>& M, int rows, int cols, double rel_tol = 1e-10) {
    std::vector<double> T(static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols));
    for (int i = 0; i < rows; ++i)
      for (int j = 0; j < cols; ++j)
        T[static_cast<std::size_t>(j) * static_cast<std::size_t>(rows) + static_cast<std::size_t>(i)] =
            M[static_cast<std::size_t>(i) * static_cast<std::size_t>(cols) + static_cast<std::size_t>(j)];
    f = pivoted_qr(T, cols, rows, rel_tol);
  }
  int rank() const { return f.rank; }
  int cols() const { return f.m; }
  /// x (cols) with M x = c on the rank equations the pivoting chose (all of them when
  /// the system is consistent), of minimum norm.
  std::vector<double> solve(const std::vector<double>& c) const {
    const int r = f.rank;
    std::vector<double> y(static_cast<std::size_t>(r));
    // R11^T y = (P^T c)[0..r): forward substitution.
    for (int i = 0; i < r; ++i) {
      double s = c[static_cast<std::size_t>(f.perm[static_cast<std::size_t>(i)])];
      for (int k = 0; k < i; ++k) s -= f.r(k, i) * y[static_cast<std::size_t>(k)];
      y[static_cast<std::size_t>(i)] = s / f.r(i, i);
    }
    std::vector<double> x(static_cast<std::size_t>(f.m), 0.0);
    for (int i = 0; i < f.m; ++i)
      for (int k = 0; k < r; ++k) x[static_cast<std::size_t>(i)] += f.q(i, k) * y[static_cast<std::size_t>(k)];
    return x;
  }
  /// An orthonormal basis of M's null space: cols x (cols - rank), row-major.
  std::vector<double> null_space() const {
    const int k = f.m - f.rank;
    std::vector<double> N(static_cast<std::size_t>(f.m) * static_cast<std::size_t>(k));
    for (int i = 0; i < f.m; ++i)
      for (int j = 0; j < k; ++j)
        N[static_cast<std::size_t>(i) * static_cast<std::size_t>(k) + static_cast<std::size_t>(j)] = f.q(i, f.rank + j);
    return N;
  }
};

/// Solves the n x n system A X = B (B: n x k, overwritten by X) by LU with partial
/// pivoting; false when A is singular to working precision.
inline bool lu_solve_dense(std::vector<double> A, std::vector<double>& B, int n, int k) {
  auto a = [&](int i, int j) -> double& { return A[static_cast<std::size_t>(i) * static_cast<std::size_t>(n) + static_cast<std::size_t>(j)]; };
  auto b = [&](int i, int j) -> double& { return B[static_cast<std::size_t>(i) * static_cast<std::size_t>(k) + static_cast<std::size_t>(j)]; };
  double scale = 0.0;
  for (double e : A) scale = std::max(scale, std::fabs(e));
  for (int c = 0; c < n; ++c) {
    int p = c;
    for (int i = c + 1; i < n; ++i)
      if (std::fabs(a(i, c)) > std::fabs(a(p, c))) p = i;
    if (!(std::fabs(a(p, c)) > 1e-14 * scale)) return false;
    if (p != c) {
      for (int j = 0; j < n; ++j) std::swap(a(c, j), a(p, j));
      for (int j = 0; j < k; ++j) std::swap(b(c, j), b(p, j));
    }
    for (int i = c + 1; i < n; ++i) {
      const double l = a(i, c) / a(c, c);
      if (l == 0.0) continue;
      for (int j = c; j < n; ++j) a(i, j) -= l * a(c, j);
      for (int j = 0; j < k; ++j) b(i, j) -= l * b(c, j);
    }
  }
  for (int c = n - 1; c >= 0; --c)
    for (int j = 0; j < k; ++j) {
      double s = b(c, j);
      for (int l = c + 1; l < n; ++l) s -= a(c, l) * b(l, j);
      b(c, j) = s / a(c, c);
    }
  return true;
}

}  // namespace mbsc::runtime
