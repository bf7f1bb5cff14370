// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// A generated derivative (rhs_jacobian, inverse_dynamics_jacobian) against central
// differences of the function it differentiates, extrapolated (Richardson) from
// h = 2e-5 max(1, |v|) and h/2: truncation ~h^4, rounding ~1e-11 of the values. Every
// entry must agree to 1e-7 of its row's size. A function that is not defined for the
// model (status 4) has a derivative that is not defined either.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

namespace mbsc_test {

/// f(x, w, out): the differentiated function at x (the state) and w (the inputs, or zdot).
using Differentiable = std::function<int(const std::vector<double>& x, const std::vector<double>& w, double* out)>;

/// `jac`: the generated values (rows x |x| then rows x |w|, row-major), `status` its status.
inline void check_jacobian(const Differentiable& f, int rows, const std::vector<double>& x, const std::vector<double>& w,
                           int status, const std::vector<double>& jac, const char* what) {
  INFO(what);
  std::vector<double> f0(static_cast<std::size_t>(rows) + 1);
  const int s0 = f(x, w, f0.data());
  if (s0 == 4) {
    REQUIRE(status == 4);
    return;
  }
  REQUIRE(s0 == 0);
  REQUIRE(status == 0);
  const int nx = static_cast<int>(x.size()), nw = static_cast<int>(w.size()), cols = nx + nw;
  REQUIRE(jac.size() == static_cast<std::size_t>(rows * cols));
  for (double v : jac) REQUIRE(std::isfinite(v));
  std::vector<double> diff(static_cast<std::size_t>(rows * cols));
  for (int j = 0; j < cols; ++j) {
    std::vector<double> xp = x, xm = x, wp = w, wm = w;
    double& vp = j < nx ? xp[static_cast<std::size_t>(j)] : wp[static_cast<std::size_t>(j - nx)];
    double& vm = j < nx ? xm[static_cast<std::size_t>(j)] : wm[static_cast<std::size_t>(j - nx)];
    const double v = vp, h = 2e-5 * std::max(1.0, std::abs(v));
    std::vector<double> central[2];
    for (int level = 0; level < 2; ++level) {
      const double step = level == 0 ? h : h / 2;
      vp = v + step;
      vm = v - step;
      std::vector<double> fp(static_cast<std::size_t>(rows) + 1), fm(static_cast<std::size_t>(rows) + 1);
      REQUIRE(f(xp, wp, fp.data()) == 0);
      REQUIRE(f(xm, wm, fm.data()) == 0);
      for (int i = 0; i < rows; ++i)
        central[level].push_back((fp[static_cast<std::size_t>(i)] - fm[static_cast<std::size_t>(i)]) / (2 * step));
    }
    for (int i = 0; i < rows; ++i)
      diff[static_cast<std::size_t>(i * cols + j)] =
          (4 * central[1][static_cast<std::size_t>(i)] - central[0][static_cast<std::size_t>(i)]) / 3;
  }
  double all = 1.0;
  for (double e : diff) all = std::max(all, std::abs(e));
  for (int i = 0; i < rows; ++i) {
    double row = 1e-3 * all;
    for (int j = 0; j < cols; ++j) row = std::max(row, std::abs(diff[static_cast<std::size_t>(i * cols + j)]));
    for (int j = 0; j < cols; ++j) {
      const double got = j < nx ? jac[static_cast<std::size_t>(i * nx + j)]
                                : jac[static_cast<std::size_t>(rows * nx + i * nw + (j - nx))];
      INFO("row " << i << ", column " << j << " (of " << nx << " state and " << nw << " other)");
      REQUIRE(std::abs(got - diff[static_cast<std::size_t>(i * cols + j)]) <= 1e-7 * row);
    }
  }
}

/// A model generated with --derivatives, as check_derivatives sees it.
struct DerivativeModel {
  using Fn = int (*)(double, const double*, const double*, const double*, double*);
  const char* name;
  int nx, nin, ndof, np;
  const double* defaults;
  Fn rhs, rhs_jacobian, inverse_dynamics, inverse_dynamics_jacobian;
};

#define MBSC_DERIVATIVE_MODEL(NS)                                                                                       \
  ::mbsc_test::DerivativeModel {                                                                                        \
    #NS, mbsc_gen::NS::kNx, mbsc_gen::NS::kNin, mbsc_gen::NS::kNdof, mbsc_gen::NS::kNp, mbsc_gen::NS::kParamDefaults,   \
        mbsc_gen::NS::rhs, mbsc_gen::NS::rhs_jacobian, mbsc_gen::NS::inverse_dynamics,                                  \
        mbsc_gen::NS::inverse_dynamics_jacobian                                                                         \
  }

/// Both derivatives of `m` against differences at one random state, inputs and zdot.
inline void check_derivatives(const DerivativeModel& m, std::mt19937& rng) {
  INFO("model " << m.name);
  std::uniform_real_distribution<double> d(-0.8, 0.8);
  const std::vector<double> p(m.defaults, m.defaults + m.np);
  const double* pp = p.empty() ? nullptr : p.data();
  std::vector<double> x(static_cast<std::size_t>(m.nx)), u(static_cast<std::size_t>(m.nin)), zdot(static_cast<std::size_t>(m.ndof));
  for (auto* v : {&x, &u, &zdot})
    for (double& e : *v) e = d(rng);
  auto ptr = [](const std::vector<double>& v) { return v.empty() ? nullptr : v.data(); };
  std::vector<double> j(static_cast<std::size_t>(m.nx * (m.nx + m.nin)));
  const int sj = m.rhs_jacobian(0.3, x.data(), ptr(u), pp, j.data());
  check_jacobian([&](const std::vector<double>& xs, const std::vector<double>& us,
                     double* out) { return m.rhs(0.3, xs.data(), ptr(us), pp, out); },
                 m.nx, x, u, sj, j, "rhs_jacobian");
  std::vector<double> k(static_cast<std::size_t>(m.nin * (m.nx + m.ndof)));
  const int sk = m.inverse_dynamics_jacobian(0.3, x.data(), ptr(zdot), pp, k.data());
  check_jacobian([&](const std::vector<double>& xs, const std::vector<double>& zs,
                     double* out) { return m.inverse_dynamics(0.3, xs.data(), ptr(zs), pp, out); },
                 m.nin, x, zdot, sk, k, "inverse_dynamics_jacobian");
}

}  // namespace mbsc_test
