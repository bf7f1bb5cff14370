// SPDX-License-Identifier: GPL-2.0-or-later
// include/mbsc/runtime/rhs_jacobian.hpp against exact derivatives:
//  - a nonlinear field with a hand-derived Jacobian (dx and du), to the accuracy forward
//    differences promise (about sqrt(eps) relative);
//  - the directional derivative J v against the exact J v;
//  - the generated rhs of the stiff shipped model: its 8 x 8 Jacobian is the line's
//    matrix A (from the parameters) in the u rows, identity couplings in the x rows and
//    zero elsewhere;
//  - the increment: relative to the value, never below sqrt(eps) times the scale, and
//    exactly representable; a failing f passes its status through.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "mbsc/runtime/rhs_jacobian.hpp"
#include "stiff_spring_damper/stiff_spring_damper.hpp"
#include "test_support.hpp"

using mbsc::runtime::difference_increment;
using mbsc::runtime::rhs_directional;
using mbsc::runtime::rhs_jacobian_u;
using mbsc::runtime::rhs_jacobian_x;

namespace {

// xdot = (x1 sin x0 + u0, exp(0.5 x1) - x0^2 u1, x0 x1 x2 + 1e3 x2)
int field(double t, const double* x, const double* u, double* xd) {
  xd[0] = x[1] * std::sin(x[0]) + u[0];
  xd[1] = std::exp(0.5 * x[1]) - x[0] * x[0] * u[1] + t;
  xd[2] = x[0] * x[1] * x[2] + 1e3 * x[2];
  return 0;
}

}  // namespace

TEST_CASE("rhs_jacobian_x / _u / directional: a nonlinear field against its exact derivatives", "[numeric][jacobian]") {
  const double x[3] = {0.7, -1.3, 2.1}, u[2] = {0.4, -0.9};
  auto f = [&](double t, const double* xs, double* xd) { return field(t, xs, u, xd); };
  double J[9];
  REQUIRE(rhs_jacobian_x(f, 0.3, x, nullptr, 3, J) == 0);
  const double exact[9] = {// column-major
                           x[1] * std::cos(x[0]), -2.0 * x[0] * u[1], x[1] * x[2],
                           std::sin(x[0]),        0.5 * std::exp(0.5 * x[1]), x[0] * x[2],
                           0.0,                   0.0,                   x[0] * x[1] + 1e3};
  // Forward differences are good to about sqrt(eps) = 1.5e-8 times the row's size (the
  // rounding error eps |f| / h over the increment h ~ sqrt(eps) |x|): 1e-7 of it is asked.
  auto row_size = [&](int i) {
    return std::max({1.0, std::abs(exact[i]), std::abs(exact[i + 3]), std::abs(exact[i + 6])});
  };
  for (int i = 0; i < 9; ++i) {
    INFO("entry " << i);
    CHECK(J[i] == Approx(exact[i]).margin(1e-7 * row_size(i % 3)));
  }
  double B[6];
  auto g = [](double t, const double* xs, const double* us, double* xd) { return field(t, xs, us, xd); };
  REQUIRE(rhs_jacobian_u(g, 0.3, x, u, nullptr, 3, 2, B) == 0);
  const double exact_b[6] = {1.0, 0.0, 0.0, 0.0, -x[0] * x[0], 0.0};
  for (int i = 0; i < 6; ++i) CHECK(B[i] == Approx(exact_b[i]).margin(1e-7));
  const double v[3] = {0.3, -0.2, 0.5};
  double Jv[3];
  REQUIRE(rhs_directional(f, 0.3, x, nullptr, v, 3, Jv) == 0);
  for (int i = 0; i < 3; ++i) {
    const double e = exact[i] * v[0] + exact[i + 3] * v[1] + exact[i + 6] * v[2];
    CHECK(Jv[i] == Approx(e).margin(1e-7 * row_size(i) * 3.0));
  }
  const double zero[3] = {0.0, 0.0, 0.0};
  int calls = 0;
  auto counted = [&](double t, const double* xs, double* xd) { ++calls; return f(t, xs, xd); };
  REQUIRE(rhs_directional(counted, 0.3, x, nullptr, zero, 3, Jv) == 0);
  CHECK(calls == 0);
  CHECK(Jv[0] == 0.0);
}

TEST_CASE("rhs_jacobian_x on the stiff shipped model equals the line's matrix", "[numeric][jacobian][stiff]") {
  namespace M = mbsc_gen::stiff_spring_damper;
  using mbsc_test::index_of;
  auto s = [](const char* n) { return index_of(M::kStateNames, M::kNx, n); };
  auto p = [](const char* n) { return M::kParamDefaults[index_of(M::kParamNames, M::kNp, n)]; };
  const double m1 = p("m1"), m2 = p("m2"), k0 = p("k0"), k = p("k"), c = p("c");
  const int x1 = s("b1.x"), y1 = s("b1.y"), x2 = s("b2.x"), y2 = s("b2.y");
  const int u1 = s("b1.u"), v1 = s("b1.v"), u2 = s("b2.u"), v2 = s("b2.v");
  const int n = M::kNx;
  std::vector<double> x(n, 0.0), E(n * n, 0.0), J(n * n);
  x[x1] = 0.62;
  x[x2] = 0.93;
  x[u1] = 0.4;
  x[u2] = -0.7;
  auto e = [&](int i, int j) -> double& { return E[i + j * n]; };
  e(x1, u1) = e(x2, u2) = e(y1, v1) = e(y2, v2) = 1.0;
  e(u1, x1) = -(k0 + k) / m1;
  e(u1, x2) = k / m1;
  e(u1, u1) = -c / m1;
  e(u1, u2) = c / m1;
  e(u2, x1) = k / m2;
  e(u2, x2) = -k / m2;
  e(u2, u1) = c / m2;
  e(u2, u2) = -c / m2;
  auto f = [](double t, const double* xs, double* xd) { return M::rhs(t, xs, nullptr, M::kParamDefaults, xd); };
  REQUIRE(rhs_jacobian_x(f, 0.0, x.data(), nullptr, n, J.data()) == 0);
  // The largest entry is k (1/m) = 4e5: the forward difference's rounding error is about
  // sqrt(eps) |f| / |x| relative, far below 1e-6 of it.
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      INFO(M::kStateNames[i] << "' by " << M::kStateNames[j]);
      CHECK(J[i + j * n] == Approx(E[i + j * n]).margin(1e-6 * 4e5).epsilon(1e-6));
    }
}

TEST_CASE("difference_increment: relative, floored by the scale, representable; statuses pass through",
          "[numeric][jacobian]") {
  const double r = std::sqrt(std::numeric_limits<double>::epsilon());
  CHECK(difference_increment(1e3) == Approx(r * 1e3).epsilon(1e-6));
  CHECK(difference_increment(1e-9) == Approx(r).epsilon(1e-6));            // default scale 1
  CHECK(difference_increment(1e-9, 1e-6) == Approx(r * 1e-6).epsilon(1e-6));  // a small typical size
  for (double v : {0.1, 1.0 / 3.0, 123.456, -7.77}) {
    const double h = difference_increment(v);
    CHECK((v + h) - v == h);
  }
  auto failing = [](double, const double*, double*) { return 3; };
  const double x[2] = {1.0, 2.0};
  double J[4];
  CHECK(rhs_jacobian_x(failing, 0.0, x, nullptr, 2, J) == 3);
}
