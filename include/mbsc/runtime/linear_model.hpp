// SPDX-License-Identifier: GPL-2.0-or-later WITH mbsc-runtime-exception
// (see LICENSE: this header may be included in applications under any terms)
#pragma once
/// The linear model of a generated model about a reference state (thesis section 4.5;
/// docs/linearization.md), from the Taylor coefficients its linear_parts function writes:
///
///   d/dt dx = A dx + B du,   dx = x - x_ref (full layout: all q0, all q1), du = u - u_ref
///
/// Reference rates and multipliers first: q1' solves A_c q1' + b = 0 and the dynamic
/// equations projected on the null space N of the constraint Jacobian A_c (the
/// orthogonal complement), N^T (hy - My q1') = 0; lambda is the minimum-norm solution of
/// A_c^T lambda = My q1' - hy. Then the increments: the linearized invariants
/// A_c dq1' = -(Gq dq0 + Gv dq1) and the linearized projected dynamic equations
/// N^T (My dq1' - Fq dq0 - Fv dq1 - Fu du) = 0, where F contains d(A_c^T lambda)/dx: the
/// derivative of the complement (Prop 4.4's C_j) contracted with the reference forces.
/// Redundant constraints (A_c rank-deficient at the reference) are handled by the
/// rank-revealing factorization: N spans the true null space and the invariants are
/// solved, with the minimum norm, on the independent rows the pivoting chose (the others
/// follow where the redundancy is compatible; their residual is invariant_residual).
///
///   #include "four_bar/four_bar.hpp"   // generated with --outputs ...,linear_parts
///   #include "mbsc/runtime/linear_model.hpp"
///   mbsc::runtime::LinearModel lin;
///   std::string why;
///   mbsc::runtime::linear_model(MBSC_LINEAR_PARTS(mbsc_gen::four_bar), t, x, u, p, lin, why);
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numeric>
#include <string>
#include <vector>

#include "mbsc/runtime/dense_qr.hpp"

namespace mbsc::runtime {

/// A generated model's linear_parts and the sizes of its full layout.
struct LinearParts {
  using Fn = int (*)(double, const double*, const double*, const double*, double*);
  Fn parts = nullptr;
  int nq = 0, nu = 0, nc = 0, nposc = 0, nin = 0;  // kNqFull, kNuFull, kNc, kNposc, kNin
  int nquat = 0;                                    // kLinearQuaternions (their norms follow P's rows)
};

/// The LinearParts of the generated namespace NS (generated with linear_parts).
#define MBSC_LINEAR_PARTS(NS) \
  ::mbsc::runtime::LinearParts { &NS::linear_parts, NS::kNqFull, NS::kNuFull, NS::kNc, NS::kNposc, NS::kNin, NS::kLinearQuaternions }

struct LinearModel {
  int n = 0, nin = 0;               // n = nq + nu (full layout)
  std::vector<double> A, B;         // n x n and n x nin, row-major
  /// n x nq: x' per unit generalized force conjugate to each coordinate (a force T on
  /// coordinate k does the power T q_k'; what the second-order form's M is read from).
  std::vector<double> Bq;
  std::vector<double> rates;        // q1' at the reference (nu)
  std::vector<double> multipliers;  // lambda at the reference (nc), minimum norm
  int constraint_rank = 0;          // rank of A_c at the reference (< nc: redundant constraints)
  double invariant_residual = 0.0;  // max |A_c q1' + b| at the reference rates (redundant, incompatible rows show here)
  /// The increments the linearized invariants allow (position rows P dq0 = 0 with every
  /// unit quaternion's norm, a first integral that is no motion when it changes; velocity
  /// rows Wq dq0 + A_c dq1 = 0): an orthonormal basis, n x m row-major. A maps it into
  /// itself; the model's own motion lives there.
  std::vector<double> tangent;
  int m = 0;
};

namespace detail {

inline void gemm(const std::vector<double>& X, const std::vector<double>& Y, std::vector<double>& Z, int a, int b, int c,
                 bool transpose_x = false) {
  // Z (a x c) = X (a x b) Y (b x c), or X^T Y with X stored b x a.
  Z.assign(static_cast<std::size_t>(a) * static_cast<std::size_t>(c), 0.0);
  for (int i = 0; i < a; ++i)
    for (int k = 0; k < b; ++k) {
      const double x = transpose_x ? X[static_cast<std::size_t>(k) * static_cast<std::size_t>(a) + static_cast<std::size_t>(i)]
                                   : X[static_cast<std::size_t>(i) * static_cast<std::size_t>(b) + static_cast<std::size_t>(k)];
      if (x == 0.0) continue;
      for (int j = 0; j < c; ++j)
        Z[static_cast<std::size_t>(i) * static_cast<std::size_t>(c) + static_cast<std::size_t>(j)] +=
            x * Y[static_cast<std::size_t>(k) * static_cast<std::size_t>(c) + static_cast<std::size_t>(j)];
    }
}

// The blocks of linear_parts' output, in its order (driver/linear_parts.cpp).
struct PartBlocks {
  std::vector<double> Kq, Kv, Ac, Wq, P, Gq, Gv, My, Fq, Fv, Fu, r, c;
  PartBlocks(const std::vector<double>& out, const LinearParts& s) {
    std::size_t at = 0;
    auto take = [&](std::vector<double>& b, int rows, int cols) {
      const std::size_t k = static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols);
      b.assign(out.begin() + static_cast<long>(at), out.begin() + static_cast<long>(at + k));
      at += k;
    };
    take(Kq, s.nq, s.nq), take(Kv, s.nq, s.nu), take(Ac, s.nc, s.nu), take(Wq, s.nc, s.nq), take(P, s.nposc + s.nquat, s.nq);
    take(Gq, s.nc, s.nq), take(Gv, s.nc, s.nu), take(My, s.nu, s.nu), take(Fq, s.nu, s.nq), take(Fv, s.nu, s.nu);
    take(Fu, s.nu, s.nin), take(r, s.nu, 1), take(c, s.nc, 1);
  }
  static std::size_t size(const LinearParts& s) {
    const std::size_t nq = static_cast<std::size_t>(s.nq), nu = static_cast<std::size_t>(s.nu),
                      nc = static_cast<std::size_t>(s.nc), np = static_cast<std::size_t>(s.nposc + s.nquat),
                      ni = static_cast<std::size_t>(s.nin);
    return nq * nq + nq * nu + nc * nu + nc * nq + np * nq + nc * nq + nc * nu + nu * nu + nu * nq + nu * nu + nu * ni + nu + nc;
  }
};

}  // namespace detail

/// The linear model at (t, x, u) with parameters p: x is the generated model's own state
/// (a --state minimal model's linear_parts rebuilds the rest); A, B are over the full layout. Returns 0, or
/// 1 with `why` set: linear_parts failed (its status), the mass matrix is singular on the
/// constraints' null space, or a value is not finite.
inline int linear_model(const LinearParts& s, double t, const double* x, const double* u, const double* p, LinearModel& out,
                        std::string& why) {
  using detail::gemm;
  const int nq = s.nq, nu = s.nu, nc = s.nc, nin = s.nin, n = nq + nu;
  const std::size_t NU = static_cast<std::size_t>(nu), NC = static_cast<std::size_t>(nc), N = static_cast<std::size_t>(n);
  std::vector<double> w(static_cast<std::size_t>(nin) + NU + NC, 0.0);
  for (int k = 0; k < nin; ++k) w[static_cast<std::size_t>(k)] = u[k];
  std::vector<double> raw(detail::PartBlocks::size(s));
  auto call = [&]() {
    const int status = s.parts(t, x, w.data(), p, raw.data());
    if (status != 0) why = "linear_parts returned status " + std::to_string(status) + (status == 4 ? " (not defined for this model)" : "");
    return status == 0;
  };
  if (!call()) return 1;
  detail::PartBlocks b0(raw, s);

  // ---- reference rates: A_c q1' = -b, N^T My N z = N^T (hy - My q1p) ----
  const RowSpaceSolver rows(b0.Ac, nc, nu);
  out.constraint_rank = rows.rank();
  const int k = nu - rows.rank();  // degrees of freedom of the speeds
  const std::vector<double> Nb = rows.null_space();  // nu x k
  std::vector<double> minus_b(NC);
  for (std::size_t i = 0; i < NC; ++i) minus_b[i] = -b0.c[i];
  const std::vector<double> q1p = rows.solve(minus_b);
  std::vector<double> MyN, NtMyN, rhs(static_cast<std::size_t>(k), 0.0);
  gemm(b0.My, Nb, MyN, nu, nu, k);
  gemm(Nb, MyN, NtMyN, k, nu, k, true);
  {
    std::vector<double> Myq1p;
    gemm(b0.My, q1p, Myq1p, nu, nu, 1);
    std::vector<double> g(NU);
    for (std::size_t i = 0; i < NU; ++i) g[i] = b0.r[i] - Myq1p[i];
    gemm(Nb, g, rhs, k, nu, 1, true);
  }
  if (k > 0 && !lu_solve_dense(NtMyN, rhs, k, 1)) {
    why = "the mass matrix is singular on the motions the constraints allow, at the reference";
    return 1;
  }
  out.rates = q1p;
  for (std::size_t i = 0; i < NU; ++i)
    for (int j = 0; j < k; ++j) out.rates[i] += Nb[i * static_cast<std::size_t>(k) + static_cast<std::size_t>(j)] * rhs[static_cast<std::size_t>(j)];
  // ---- multipliers: A_c^T lambda = My q1' - hy, minimum norm ----
  {
    std::vector<double> g;
    gemm(b0.My, out.rates, g, nu, nu, 1);
    for (std::size_t i = 0; i < NU; ++i) g[i] -= b0.r[i];
    std::vector<double> AcT(NU * NC);
    for (std::size_t i = 0; i < NC; ++i)
      for (std::size_t j = 0; j < NU; ++j) AcT[j * NC + i] = b0.Ac[i * NU + j];
    out.multipliers = RowSpaceSolver(AcT, nu, nc).solve(g);
  }
  // ---- the coefficients at the reference rates and multipliers ----
  for (std::size_t j = 0; j < NU; ++j) w[static_cast<std::size_t>(nin) + j] = out.rates[j];
  for (std::size_t r = 0; r < NC; ++r) w[static_cast<std::size_t>(nin) + NU + r] = out.multipliers[r];
  if (!call()) return 1;
  const detail::PartBlocks b(raw, s);
  out.invariant_residual = 0.0;
  for (double e : b.c) out.invariant_residual = std::max(out.invariant_residual, std::fabs(e));

  // ---- increments: dq1' = dp + N dz, A_c dp = -(Gq dq0 + Gv dq1) ----
  // D: the linearized invariants' right-hand side per column of (dq0, dq1, du).
  const int cols = n + nin + nq;  // dx, du, then a generalized force on each coordinate
  const std::size_t C = static_cast<std::size_t>(cols);
  std::vector<double> dp(NU * C, 0.0), E(NU * C, 0.0);  // dp; E = Fq dq0 + Fv dq1 + Fu du
  std::vector<double> col(NC);
  for (int j = 0; j < n; ++j) {
    for (std::size_t r = 0; r < NC; ++r)
      col[r] = -(j < nq ? b.Gq[r * static_cast<std::size_t>(nq) + static_cast<std::size_t>(j)] : b.Gv[r * NU + static_cast<std::size_t>(j - nq)]);
    const std::vector<double> d = rows.solve(col);
    for (std::size_t i = 0; i < NU; ++i) dp[i * C + static_cast<std::size_t>(j)] = d[i];
  }
  for (std::size_t i = 0; i < NU; ++i) {
    for (int j = 0; j < nq; ++j) E[i * C + static_cast<std::size_t>(j)] = b.Fq[i * static_cast<std::size_t>(nq) + static_cast<std::size_t>(j)];
    for (int j = 0; j < nu; ++j) E[i * C + static_cast<std::size_t>(nq + j)] = b.Fv[i * NU + static_cast<std::size_t>(j)];
    for (int j = 0; j < nin; ++j) E[i * C + static_cast<std::size_t>(n + j)] = b.Fu[i * static_cast<std::size_t>(nin) + static_cast<std::size_t>(j)];
    // T q_k' = T (Kq_k dq0 + Kv_k q1): the force on the speeds is Kv_k^T T.
    for (int j = 0; j < nq; ++j) E[i * C + static_cast<std::size_t>(n + nin + j)] = b.Kv[static_cast<std::size_t>(j) * NU + i];
  }
  // N^T My N dz = N^T (E - My dp)
  std::vector<double> Mydp, dz;
  gemm(b.My, dp, Mydp, nu, nu, cols);
  for (std::size_t i = 0; i < E.size(); ++i) E[i] -= Mydp[i];
  gemm(Nb, E, dz, k, nu, cols, true);
  gemm(b.My, Nb, MyN, nu, nu, k);
  gemm(Nb, MyN, NtMyN, k, nu, k, true);
  if (k > 0 && !lu_solve_dense(NtMyN, dz, k, cols)) {
    why = "the mass matrix is singular on the motions the constraints allow, at the reference";
    return 1;
  }
  std::vector<double> dq1dot = dp;
  if (k > 0) {
    std::vector<double> Ndz;
    gemm(Nb, dz, Ndz, nu, k, cols);
    for (std::size_t i = 0; i < dq1dot.size(); ++i) dq1dot[i] += Ndz[i];
  }
  // ---- assemble A and B ----
  out.n = n, out.nin = nin;
  out.A.assign(N * N, 0.0);
  out.B.assign(N * static_cast<std::size_t>(nin), 0.0);
  out.Bq.assign(N * static_cast<std::size_t>(nq), 0.0);
  for (int i = 0; i < nq; ++i) {
    for (int j = 0; j < nq; ++j) out.A[static_cast<std::size_t>(i) * N + static_cast<std::size_t>(j)] = b.Kq[static_cast<std::size_t>(i * nq + j)];
    for (int j = 0; j < nu; ++j)
      out.A[static_cast<std::size_t>(i) * N + static_cast<std::size_t>(nq + j)] = b.Kv[static_cast<std::size_t>(i) * NU + static_cast<std::size_t>(j)];
  }
  for (std::size_t i = 0; i < NU; ++i) {
    const std::size_t row = static_cast<std::size_t>(nq) + i;
    for (std::size_t j = 0; j < N; ++j) out.A[row * N + j] = dq1dot[i * C + j];
    for (int j = 0; j < nin; ++j) out.B[row * static_cast<std::size_t>(nin) + static_cast<std::size_t>(j)] = dq1dot[i * C + N + static_cast<std::size_t>(j)];
    for (int j = 0; j < nq; ++j)
      out.Bq[row * static_cast<std::size_t>(nq) + static_cast<std::size_t>(j)] = dq1dot[i * C + N + static_cast<std::size_t>(nin + j)];
  }
  // ---- the tangent space: null([P 0; Wq A_c]) ----
  const int np = s.nposc + s.nquat, nr = np + nc;
  std::vector<double> J(static_cast<std::size_t>(nr) * N, 0.0);
  for (int r = 0; r < np; ++r)
    for (int j = 0; j < nq; ++j) J[static_cast<std::size_t>(r) * N + static_cast<std::size_t>(j)] = b.P[static_cast<std::size_t>(r * nq + j)];
  for (int r = 0; r < nc; ++r) {
    const std::size_t row = static_cast<std::size_t>(np + r);
    for (int j = 0; j < nq; ++j) J[row * N + static_cast<std::size_t>(j)] = b.Wq[static_cast<std::size_t>(r * nq + j)];
    for (int j = 0; j < nu; ++j) J[row * N + static_cast<std::size_t>(nq + j)] = b.Ac[static_cast<std::size_t>(r) * NU + static_cast<std::size_t>(j)];
  }
  const RowSpaceSolver tangent(J, nr, n);
  out.tangent = tangent.null_space();
  out.m = n - tangent.rank();
  for (double e : out.A)
    if (!std::isfinite(e)) {
      why = "the linear model has a value that is not finite at the reference";
      return 1;
    }
  for (const auto* v : {&out.B, &out.Bq, &out.tangent})
    for (double e : *v)
      if (!std::isfinite(e)) {
        why = "the linear model has a value that is not finite at the reference";
        return 1;
      }
  for (double e : out.B)
    if (!std::isfinite(e)) {
      why = "the linear model has a value that is not finite at the reference";
      return 1;
    }
  return 0;
}

/// A state of m of the n full-layout components that parametrizes the tangent space:
/// taken greedily in `preferred` order (then every other component in layout order),
/// a component joining when its row of the tangent basis is independent of those taken.
inline std::vector<int> minimal_components(const LinearModel& lin, const std::vector<int>& preferred) {
  std::vector<int> order = preferred;
  for (int i = 0; i < lin.n; ++i)
    if (std::find(order.begin(), order.end(), i) == order.end()) order.push_back(i);
  std::vector<std::vector<double>> basis;  // orthonormal rows taken
  std::vector<int> taken;
  const std::size_t m = static_cast<std::size_t>(lin.m);
  for (int i : order) {
    if (static_cast<int>(taken.size()) == lin.m) break;
    std::vector<double> v(lin.tangent.begin() + static_cast<long>(static_cast<std::size_t>(i) * m),
                          lin.tangent.begin() + static_cast<long>(static_cast<std::size_t>(i + 1) * m));
    const double before = std::sqrt(std::inner_product(v.begin(), v.end(), v.begin(), 0.0));
    for (int pass = 0; pass < 2; ++pass)
      for (const auto& e : basis) {
        const double d = std::inner_product(v.begin(), v.end(), e.begin(), 0.0);
        for (std::size_t j = 0; j < m; ++j) v[j] -= d * e[j];
      }
    const double after = std::sqrt(std::inner_product(v.begin(), v.end(), v.begin(), 0.0));
    if (!(after > 1e-8) || !(after > 1e-6 * before)) continue;
    for (double& e : v) e /= after;
    basis.push_back(std::move(v));
    taken.push_back(i);
  }
  return taken;
}

/// The linear model in the components `sel` (minimal_components): x_sel' = Am x_sel + Bm du,
/// the other components following from the tangent space. False when `sel` does not
/// parametrize it.
inline bool restrict_to(const LinearModel& lin, const std::vector<int>& sel, std::vector<double>& Am, std::vector<double>& Bm) {
  const int m = lin.m, n = lin.n;
  if (static_cast<int>(sel.size()) != m) return false;
  const std::size_t M = static_cast<std::size_t>(m), N = static_cast<std::size_t>(n);
  // T = V (S V)^-1: n x m, computed as the transpose solve (S V)^T T^T = V^T.
  std::vector<double> SVt(M * M), Tt(M * N);
  for (std::size_t a = 0; a < M; ++a)
    for (std::size_t c = 0; c < M; ++c) SVt[c * M + a] = lin.tangent[static_cast<std::size_t>(sel[a]) * M + c];
  for (std::size_t c = 0; c < M; ++c)
    for (std::size_t i = 0; i < N; ++i) Tt[c * N + i] = lin.tangent[i * M + c];
  if (m > 0 && !lu_solve_dense(SVt, Tt, m, n)) return false;
  Am.assign(M * M, 0.0);
  for (std::size_t a = 0; a < M; ++a) {
    const std::size_t row = static_cast<std::size_t>(sel[a]);
    for (std::size_t c = 0; c < M; ++c) {
      double s = 0.0;
      for (std::size_t i = 0; i < N; ++i) s += lin.A[row * N + i] * Tt[c * N + i];
      Am[a * M + c] = s;
    }
  }
  const std::size_t NI = static_cast<std::size_t>(lin.nin);
  Bm.assign(M * NI, 0.0);
  for (std::size_t a = 0; a < M; ++a)
    for (std::size_t j = 0; j < NI; ++j) Bm[a * NI + j] = lin.B[static_cast<std::size_t>(sel[a]) * NI + j];
  return true;
}

/// The components of an m x m state matrix that nothing depends on (cyclic coordinates:
/// a vehicle's position and heading, a wheel's angle), found repeatedly: a component whose
/// column is zero (below rel_tol times the largest entry) adds an exact zero eigenvalue
/// and leaves the others to the rest of the matrix, and once it is dropped another column
/// may vanish (the heading, whose only reader was the lateral position). Dropping them
/// before an eigenvalue solve avoids the Jordan blocks of those zeros, which rounding
/// splits into eigenvalues of size eps^(1/k) (1e-5 for a chain of three) that hide the
/// real eigenvalues near zero. Returned ascending.
inline std::vector<int> cyclic_components(const std::vector<double>& A, int m, double rel_tol = 1e-12) {
  double scale = 0.0;
  for (double e : A) scale = std::max(scale, std::fabs(e));
  std::vector<bool> dropped(static_cast<std::size_t>(m), false);
  for (bool changed = true; changed;) {
    changed = false;
    for (int j = 0; j < m; ++j) {
      if (dropped[static_cast<std::size_t>(j)]) continue;
      double col = 0.0;
      for (int i = 0; i < m; ++i)
        if (!dropped[static_cast<std::size_t>(i)] && i != j) col = std::max(col, std::fabs(A[static_cast<std::size_t>(i * m + j)]));
      col = std::max(col, std::fabs(A[static_cast<std::size_t>(j * m + j)]));
      if (col <= rel_tol * scale) dropped[static_cast<std::size_t>(j)] = true, changed = true;
    }
  }
  std::vector<int> out;
  for (int j = 0; j < m; ++j)
    if (dropped[static_cast<std::size_t>(j)]) out.push_back(j);
  return out;
}

}  // namespace mbsc::runtime
