// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Helpers of linear_model_test.cpp: a generated model seen through function pointers,
// consistent references by assembly, and the central-difference Jacobian of the
// generated (nonlinear) rhs that the linear model is compared with.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "mbsc/runtime/assemble.hpp"
#include "mbsc/runtime/linear_model.hpp"
#include "test_support.hpp"

namespace lin_test {

using Fn = int (*)(double, const double*, const double*, const double*, double*);

/// One generated model (full or minimal state, either formulation).
struct Gen {
  const char* name;
  mbsc::runtime::LinearParts parts;
  Fn rhs, position_constraints, position_jacobian, velocity_constraints, constraint_jacobian, full_state;
  int nq, nu, nx, nin, np, nc, nposc;
  const char* const* state_names;
  const char* const* full_state_names;
  const char* const* position_names;
  const char* const* constraint_names;
  const double* params;
  int nx_full() const { return parts.nq + parts.nu; }
  int index(const std::string& n) const { return mbsc_test::index_of(state_names, nx, n); }
  int full_index(const std::string& n) const { return mbsc_test::index_of(full_state_names, nx_full(), n); }
};

#define LIN_GEN(NS)                                                                                                 \
  ::lin_test::Gen {                                                                                                 \
    #NS, MBSC_LINEAR_PARTS(NS), &NS::rhs, &NS::position_constraints, &NS::position_jacobian,                       \
        &NS::velocity_constraints, &NS::constraint_jacobian, &NS::full_state, NS::kNq, NS::kNu, NS::kNx, NS::kNin, \
        NS::kNp, NS::kNc, NS::kNposc, NS::kStateNames, NS::kFullStateNames, NS::kPositionConstraintNames,          \
        NS::kConstraintNames, NS::kParamDefaults                                                                    \
  }

/// A value of the reference: `given` values stay, the others are the assembly's first guess.
struct Value {
  std::string name;
  double value;
  bool given;
};

/// A consistent full state of a full-state model: every coordinate and speed starts at
/// a small deterministic value unless listed, then assembly solves the position and
/// velocity constraints for the entries not given.
inline std::vector<double> assemble_reference(const Gen& g, const std::vector<Value>& values, const std::vector<double>& u,
                                              const std::vector<double>& p) {
  REQUIRE(g.nx == g.nx_full());
  std::vector<double> x(static_cast<std::size_t>(g.nx));
  for (int i = 0; i < g.nx; ++i) x[static_cast<std::size_t>(i)] = 0.05 * static_cast<double>((i * 7) % 11) - 0.2;
  std::vector<bool> given_q(static_cast<std::size_t>(g.nq), false), given_u(static_cast<std::size_t>(g.nu), false);
  for (const Value& v : values) {
    const int i = g.index(v.name);
    x[static_cast<std::size_t>(i)] = v.value;
    if (i < g.nq)
      given_q[static_cast<std::size_t>(i)] = v.given;
    else
      given_u[static_cast<std::size_t>(i - g.nq)] = v.given;
  }
  const mbsc::runtime::AssemblyModel am{g.nq,           g.nu,
                                        g.nposc,        g.nc,
                                        g.position_constraints, g.position_jacobian,
                                        g.velocity_constraints, g.constraint_jacobian,
                                        g.position_names, g.constraint_names};
  const auto r = mbsc::runtime::assemble(am, 0.0, x, given_q, given_u, u.data(), p.data());
  INFO(g.name << ": " << r.message);
  REQUIRE(r.ok());
  return x;
}

inline double norm2(const std::vector<double>& v) {
  double s = 0.0;
  for (double e : v) s += e * e;
  return std::sqrt(s);
}

/// Column j of a rows x cols row-major matrix.
inline std::vector<double> column(const std::vector<double>& M, int rows, int cols, int j) {
  std::vector<double> c(static_cast<std::size_t>(rows));
  for (int i = 0; i < rows; ++i) c[static_cast<std::size_t>(i)] = M[static_cast<std::size_t>(i * cols + j)];
  return c;
}

/// M (rows x cols) times v.
inline std::vector<double> times(const std::vector<double>& M, int rows, int cols, const std::vector<double>& v) {
  std::vector<double> r(static_cast<std::size_t>(rows), 0.0);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) r[static_cast<std::size_t>(i)] += M[static_cast<std::size_t>(i * cols + j)] * v[static_cast<std::size_t>(j)];
  return r;
}

/// Central difference of the rhs of `g` at (x, u) along (dx, du): (f(+h) - f(-h)) / 2h,
/// h = 1e-6 times the state's scale over the direction's size.
inline std::vector<double> rhs_derivative(const Gen& g, const std::vector<double>& x, const std::vector<double>& u,
                                          const std::vector<double>& p, const std::vector<double>& dx,
                                          const std::vector<double>& du) {
  double scale = 1.0;
  for (double e : x) scale = std::max(scale, std::fabs(e));
  const double size = std::max(norm2(dx), norm2(du));
  const double h = 1e-6 * scale / size;
  std::vector<double> xp = x, xm = x, up = u, um = u, fp(static_cast<std::size_t>(g.nx)), fm(static_cast<std::size_t>(g.nx));
  for (std::size_t i = 0; i < x.size(); ++i) xp[i] += h * dx[i], xm[i] -= h * dx[i];
  for (std::size_t i = 0; i < du.size(); ++i) up[i] += h * du[i], um[i] -= h * du[i];
  REQUIRE(g.rhs(0.0, xp.data(), up.data(), p.data(), fp.data()) == 0);
  REQUIRE(g.rhs(0.0, xm.data(), um.data(), p.data(), fm.data()) == 0);
  std::vector<double> d(fp.size());
  for (std::size_t i = 0; i < d.size(); ++i) d[i] = (fp[i] - fm[i]) / (2.0 * h);
  return d;
}

/// Norm-wise relative error of each column: |a_k - b_k| / max(|b_k|, floor), with the
/// floor 1e-3 of the largest column (so that columns that vanish in both are not
/// compared digit by digit). Returns the largest over the columns.
inline double worst_column_error(const std::vector<std::vector<double>>& a, const std::vector<std::vector<double>>& b) {
  double largest = 0.0;
  for (const auto& c : b) largest = std::max(largest, norm2(c));
  double worst = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    std::vector<double> d(a[k].size());
    for (std::size_t i = 0; i < d.size(); ++i) d[i] = a[k][i] - b[k][i];
    worst = std::max(worst, norm2(d) / std::max({norm2(b[k]), 1e-3 * largest, 1e-300}));
  }
  return worst;
}

/// The linear model of `g` at (x, u), required to succeed.
inline mbsc::runtime::LinearModel linear(const Gen& g, const std::vector<double>& x_full, const std::vector<double>& u,
                                         const std::vector<double>& p) {
  mbsc::runtime::LinearModel lin;
  std::string why;
  const int status = mbsc::runtime::linear_model(g.parts, 0.0, x_full.data(), u.data(), p.data(), lin, why);
  INFO(g.name << ": " << why);
  REQUIRE(status == 0);
  return lin;
}

/// What the comparison of A (and B) with the finite differences measured.
struct FdReport {
  double tangent = 0.0;  // A V against J V, V = lin.tangent
  double full = 0.0;     // A e_j against J e_j, every full-layout direction
  double inputs = 0.0;   // B against J_u
};

/// A and B of `lin` against central differences of g's rhs (g in the full layout).
inline FdReport compare_with_rhs(const Gen& g, const mbsc::runtime::LinearModel& lin, const std::vector<double>& x,
                                 const std::vector<double>& u, const std::vector<double>& p) {
  REQUIRE(g.nx == lin.n);
  FdReport rep;
  const int n = lin.n;
  const std::vector<double> no_du(u.size(), 0.0), no_dx(static_cast<std::size_t>(n), 0.0);
  std::vector<std::vector<double>> lin_cols, fd_cols;
  for (int k = 0; k < lin.m; ++k) {
    const std::vector<double> v = column(lin.tangent, n, lin.m, k);
    lin_cols.push_back(times(lin.A, n, n, v));
    fd_cols.push_back(rhs_derivative(g, x, u, p, v, no_du));
  }
  rep.tangent = worst_column_error(lin_cols, fd_cols);
  lin_cols.clear(), fd_cols.clear();
  for (int j = 0; j < n; ++j) {
    std::vector<double> e(static_cast<std::size_t>(n), 0.0);
    e[static_cast<std::size_t>(j)] = 1.0;
    lin_cols.push_back(column(lin.A, n, n, j));
    fd_cols.push_back(rhs_derivative(g, x, u, p, e, no_du));
  }
  rep.full = worst_column_error(lin_cols, fd_cols);
  lin_cols.clear(), fd_cols.clear();
  for (int j = 0; j < lin.nin; ++j) {
    std::vector<double> e(u.size(), 0.0);
    e[static_cast<std::size_t>(j)] = 1.0;
    lin_cols.push_back(column(lin.B, n, lin.nin, j));
    fd_cols.push_back(rhs_derivative(g, x, u, p, no_dx, e));
  }
  rep.inputs = worst_column_error(lin_cols, fd_cols);
  return rep;
}

/// The minimal-state model `gm` (same model, --state minimal) against the linear model
/// of the full layout at x_full: the minimal state's components sel (kStateNames in
/// kFullStateNames); along the tangent directions, (A V)[sel] must equal the
/// finite-difference derivative of the minimal rhs along V[sel]; where sel has exactly
/// m components, restrict_to's Am must equal the minimal rhs's Jacobian. Returns the
/// largest relative error.
inline double compare_minimal(const Gen& gm, const mbsc::runtime::LinearModel& lin, const std::vector<double>& x_full,
                              const std::vector<double>& u, const std::vector<double>& p) {
  const int n = lin.n;
  std::vector<int> sel;
  std::vector<double> xm;
  for (int i = 0; i < gm.nx; ++i) {
    sel.push_back(gm.full_index(gm.state_names[i]));
    xm.push_back(x_full[static_cast<std::size_t>(sel.back())]);
  }
  // The minimal model rebuilds the same full state (same branch of the closures).
  std::vector<double> rebuilt(static_cast<std::size_t>(n));
  REQUIRE(gm.full_state(0.0, xm.data(), u.data(), p.data(), rebuilt.data()) == 0);
  for (int i = 0; i < n; ++i)
    REQUIRE(std::fabs(rebuilt[static_cast<std::size_t>(i)] - x_full[static_cast<std::size_t>(i)]) <
            1e-9 * std::max(1.0, std::fabs(x_full[static_cast<std::size_t>(i)])));
  const std::vector<double> no_du(u.size(), 0.0);
  std::vector<std::vector<double>> lin_cols, fd_cols;
  for (int k = 0; k < lin.m; ++k) {
    const std::vector<double> v = column(lin.tangent, n, lin.m, k);
    const std::vector<double> Av = times(lin.A, n, n, v);
    std::vector<double> vs, Avs;
    for (int i : sel) vs.push_back(v[static_cast<std::size_t>(i)]), Avs.push_back(Av[static_cast<std::size_t>(i)]);
    lin_cols.push_back(Avs);
    fd_cols.push_back(rhs_derivative(gm, xm, u, p, vs, no_du));
  }
  double worst = worst_column_error(lin_cols, fd_cols);
  if (static_cast<int>(sel.size()) == lin.m) {
    std::vector<double> Am, Bm;
    REQUIRE(mbsc::runtime::restrict_to(lin, sel, Am, Bm));
    lin_cols.clear(), fd_cols.clear();
    for (int j = 0; j < lin.m; ++j) {
      std::vector<double> e(static_cast<std::size_t>(lin.m), 0.0);
      e[static_cast<std::size_t>(j)] = 1.0;
      lin_cols.push_back(column(Am, lin.m, lin.m, j));
      fd_cols.push_back(rhs_derivative(gm, xm, u, p, e, no_du));
    }
    worst = std::max(worst, worst_column_error(lin_cols, fd_cols));
  }
  return worst;
}

}  // namespace lin_test
