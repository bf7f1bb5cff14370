// SPDX-License-Identifier: GPL-2.0-or-later WITH mbsc-runtime-exception
// (see LICENSE: this header may be included in applications under any terms)
#pragma once
/// Jacobians of a right-hand side by forward differences, for implicit integrators
/// (Newton's matrix I - gamma J) and for control users (linearization about a state).
///
///   rhs_jacobian_x:  J = dxdot/dx  (n x n),   column j from f(t, x + h_j e_j) - f(t, x)
///   rhs_jacobian_u:  B = dxdot/du  (n x m),   column j from g(t, x, u + h_j e_j) - g(t, x, u)
///   rhs_directional: J v           (n),       one difference along v (matrix-free Newton)
///
/// Matrices are column-major (entry (i, j) at [i + j n]), the layout SUNDIALS' dense
/// matrices and most LAPACK-style solvers use. Each column costs one call of f.
///
/// The increment of variable j is h_j = sqrt(eps) max(|x_j|, s_j): relative to the value,
/// but never below sqrt(eps) times the variable's typical size s_j (default 1; an
/// integrator passes rtol |x_j| + atol, the size its error test resolves). That balances
/// the truncation error (h f'') against the rounding error (eps |f| / h) for variables
/// of size s_j. The step is then rounded so that x_j + h_j is exactly representable
/// (h_j = (x_j + h_j) - x_j), which removes the representation error of the increment.
///
/// f(t, x, xdot) and g(t, x, u, xdot) return 0 on success; a non-zero status aborts and
/// is returned (J is then partly written).
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace mbsc::runtime {

/// The forward-difference increment for a variable of value v and typical size s (> 0).
inline double difference_increment(double v, double s = 1.0) {
  const double root_eps = std::sqrt(std::numeric_limits<double>::epsilon());
  double h = root_eps * std::max(std::fabs(v), s > 0.0 ? s : 1.0);
  const volatile double moved = v + h;  // volatile: keep the rounding the next line measures
  h = moved - v;
  return h;
}

/// J = dxdot/dx at (t, x), column-major n x n. fx = f(t, x) if the caller has it (an
/// integrator always does), else null and it is computed here. scale: the typical size
/// of each variable (null: 1 for all).
template <class F>
int rhs_jacobian_x(F&& f, double t, const double* x, const double* fx, int n, double* J,
                   const double* scale = nullptr) {
  std::vector<double> xp(x, x + n), f0, fp(n);
  if (fx == nullptr) {
    f0.resize(n);
    if (int s = f(t, x, f0.data()); s != 0) return s;
    fx = f0.data();
  }
  for (int j = 0; j < n; ++j) {
    const double h = difference_increment(x[j], scale ? scale[j] : 1.0);
    xp[j] = x[j] + h;
    if (int s = f(t, xp.data(), fp.data()); s != 0) return s;
    xp[j] = x[j];
    double* col = J + static_cast<long>(j) * n;
    for (int i = 0; i < n; ++i) col[i] = (fp[i] - fx[i]) / h;
  }
  return 0;
}

/// B = dxdot/du at (t, x, u), column-major n x m, for g(t, x, u, xdot) (the generated
/// rhs with its parameters bound). fx = g(t, x, u) or null. scale: typical input sizes.
template <class G>
int rhs_jacobian_u(G&& g, double t, const double* x, const double* u, const double* fx, int n, int m,
                   double* B, const double* scale = nullptr) {
  std::vector<double> up(u, u + m), f0, fp(n);
  if (fx == nullptr) {
    f0.resize(n);
    if (int s = g(t, x, u, f0.data()); s != 0) return s;
    fx = f0.data();
  }
  for (int j = 0; j < m; ++j) {
    const double h = difference_increment(u[j], scale ? scale[j] : 1.0);
    up[j] = u[j] + h;
    if (int s = g(t, x, up.data(), fp.data()); s != 0) return s;
    up[j] = u[j];
    double* col = B + static_cast<long>(j) * n;
    for (int i = 0; i < n; ++i) col[i] = (fp[i] - fx[i]) / h;
  }
  return 0;
}

/// Jv = (dxdot/dx) v at (t, x) by one difference along v: sigma = sqrt(eps) max(1, |x|) / |v|
/// (Euclidean norms). fx = f(t, x) or null. A zero v gives Jv = 0 without calling f.
template <class F>
int rhs_directional(F&& f, double t, const double* x, const double* fx, const double* v, int n, double* Jv) {
  double xnorm = 0.0, vnorm = 0.0;
  for (int i = 0; i < n; ++i) {
    xnorm += x[i] * x[i];
    vnorm += v[i] * v[i];
  }
  if (vnorm == 0.0) {
    std::fill(Jv, Jv + n, 0.0);
    return 0;
  }
  std::vector<double> f0, xp(n);
  if (fx == nullptr) {
    f0.resize(n);
    if (int s = f(t, x, f0.data()); s != 0) return s;
    fx = f0.data();
  }
  const double sigma =
      std::sqrt(std::numeric_limits<double>::epsilon()) * std::max(1.0, std::sqrt(xnorm)) / std::sqrt(vnorm);
  for (int i = 0; i < n; ++i) xp[i] = x[i] + sigma * v[i];
  if (int s = f(t, xp.data(), Jv); s != 0) return s;
  for (int i = 0; i < n; ++i) Jv[i] = (Jv[i] - fx[i]) / sigma;
  return 0;
}

}  // namespace mbsc::runtime
