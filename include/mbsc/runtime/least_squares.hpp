// SPDX-License-Identifier: GPL-2.0-or-later WITH mbsc-runtime-exception
// (see LICENSE: this header may be included in applications under any terms)
#pragma once
/// Minimum-effort dense least squares for the runtime (no Eigen in applications):
/// Householder QR with column pivoting of an m x n matrix, its numerical rank, and the
/// basic solution of min |A x - b| (free variables beyond the rank set to zero).
/// Enough for assembly-sized systems (tens of unknowns).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace mbsc::runtime {

/// Result of solve_least_squares: x (size n), the rank found, and |R(k,k)| of the first
/// and last pivot within that rank (their ratio estimates the conditioning).
struct LeastSquares {
  std::vector<double> x;
  int rank = 0;
  double largest_pivot = 0.0;
  double smallest_pivot = 0.0;
};

/// A is m x n row-major (copied), b has m entries. Pivots below rel_tol * largest are
/// treated as zero (rank deficiency: redundant constraints or a singular configuration).
inline LeastSquares solve_least_squares(std::vector<double> A, std::vector<double> b, int m, int n, double rel_tol = 1e-12) {
  LeastSquares out;
  out.x.assign(static_cast<std::size_t>(n), 0.0);
  std::vector<int> perm(static_cast<std::size_t>(n));
  std::vector<double> colnorm(static_cast<std::size_t>(n), 0.0);
  for (int j = 0; j < n; ++j) perm[static_cast<std::size_t>(j)] = j;
  auto at = [&](int i, int j) -> double& { return A[static_cast<std::size_t>(i) * static_cast<std::size_t>(n) + static_cast<std::size_t>(j)]; };
  const int steps = std::min(m, n);
  for (int k = 0; k < steps; ++k) {
    // Pivot: the remaining column of largest norm (rows k..m-1).
    int best = k;
    double best_norm = -1.0;
    for (int j = k; j < n; ++j) {
      double s = 0.0;
      for (int i = k; i < m; ++i) s += at(i, j) * at(i, j);
      colnorm[static_cast<std::size_t>(j)] = s;
      if (s > best_norm) best_norm = s, best = j;
    }
    if (best != k) {
      for (int i = 0; i < m; ++i) std::swap(at(i, k), at(i, best));
      std::swap(perm[static_cast<std::size_t>(k)], perm[static_cast<std::size_t>(best)]);
    }
    const double norm = std::sqrt(std::max(best_norm, 0.0));
    if (k == 0) out.largest_pivot = norm;
    if (norm <= rel_tol * out.largest_pivot || norm == 0.0) break;
    out.rank = k + 1;
    out.smallest_pivot = norm;
    // Householder reflection H = I - 2 v v^T / (v^T v) taking column k to (alpha, 0, ...).
    const double alpha = at(k, k) > 0 ? -norm : norm;
    std::vector<double> v(static_cast<std::size_t>(m - k));
    for (int i = k; i < m; ++i) v[static_cast<std::size_t>(i - k)] = at(i, k);
    v[0] -= alpha;
    double vv = 0.0;
    for (double e : v) vv += e * e;
    if (vv > 0.0) {
      for (int j = k; j < n; ++j) {
        double s = 0.0;
        for (int i = k; i < m; ++i) s += v[static_cast<std::size_t>(i - k)] * at(i, j);
        s *= 2.0 / vv;
        for (int i = k; i < m; ++i) at(i, j) -= s * v[static_cast<std::size_t>(i - k)];
      }
      double s = 0.0;
      for (int i = k; i < m; ++i) s += v[static_cast<std::size_t>(i - k)] * b[static_cast<std::size_t>(i)];
      s *= 2.0 / vv;
      for (int i = k; i < m; ++i) b[static_cast<std::size_t>(i)] -= s * v[static_cast<std::size_t>(i - k)];
    }
  }
  // Back substitution on the leading rank x rank block of R.
  std::vector<double> y(static_cast<std::size_t>(n), 0.0);
  for (int i = out.rank - 1; i >= 0; --i) {
    double s = b[static_cast<std::size_t>(i)];
    for (int j = i + 1; j < out.rank; ++j) s -= at(i, j) * y[static_cast<std::size_t>(j)];
    y[static_cast<std::size_t>(i)] = s / at(i, i);
  }
  for (int j = 0; j < n; ++j) out.x[static_cast<std::size_t>(perm[static_cast<std::size_t>(j)])] = y[static_cast<std::size_t>(j)];
  return out;
}

}  // namespace mbsc::runtime
