// SPDX-License-Identifier: GPL-2.0-or-later
// Gravity, ground points and ground axes may depend on t (docs/language.md, "Ground" and
// `gravity`): a bead in a slot turning at a constant rate (r'' = w^2 r, so
// r(t) = r0 cosh(w t) + (r0'/w) sinh(w t)), a ball pinned to an oscillating ground point
// (it moves exactly with the point), and a free particle under gravity (c t, -g).
#include <catch2/catch.hpp>
#include <cmath>

#include "growing_gravity/growing_gravity.hpp"
#include "mbsc/runtime/rk4.hpp"
#include "moving_ground/moving_ground.hpp"
#include "test_support.hpp"

namespace MG = mbsc_gen::moving_ground;
namespace GG = mbsc_gen::growing_gravity;
using mbsc_test::index_of;

namespace {
int mx(const char* n) { return index_of(MG::kStateNames, MG::kNx, n); }
int gx(const char* n) { return index_of(GG::kStateNames, GG::kNx, n); }
double mpar(const char* n) { return MG::kParamDefaults[index_of(MG::kParamNames, MG::kNp, n)]; }
double gpar(const char* n) { return GG::kParamDefaults[index_of(GG::kParamNames, GG::kNp, n)]; }
}  // namespace

TEST_CASE("time-dependent ground: a bead in a turning slot and a ball on a moving point", "[numeric][time_dependent]") {
  const double w = mpar("w"), A = mpar("A"), r0 = 0.3, r0d = 0.1, T = 0.8;  // w T < pi/2: u stays independent
  std::vector<double> x(MG::kNx, 0.0);
  x[mx("bead.x")] = r0;  // the slot lies along x at t = 0
  x[mx("bead.u")] = r0d;
  x[mx("bead.v")] = r0 * w;
  x[mx("ball.y")] = 1.0;
  x[mx("ball.u")] = A * w;
  // The ball's acceleration is the point's, at any time.
  std::vector<double> xd(MG::kNx);
  REQUIRE(MG::rhs(0.5, x.data(), nullptr, MG::kParamDefaults, xd.data()) == 0);
  CHECK(xd[mx("ball.u")] == Approx(-A * w * w * std::sin(w * 0.5)).margin(1e-12));
  CHECK(xd[mx("ball.v")] == Approx(0.0).margin(1e-12));
  auto f = [](double t, const double* s, double* sd) { return MG::rhs(t, s, nullptr, MG::kParamDefaults, sd); };
  REQUIRE(mbsc::runtime::rk4_integrate(f, 0.0, T, 4000, x, [](double, const std::vector<double>&) {}) == 0);
  const double bx = x[mx("bead.x")], by = x[mx("bead.y")];
  CHECK(std::hypot(bx, by) == Approx(r0 * std::cosh(w * T) + r0d / w * std::sinh(w * T)).epsilon(1e-10));
  CHECK(std::atan2(by, bx) == Approx(w * T).epsilon(1e-10));
  CHECK(x[mx("ball.x")] == Approx(A * std::sin(w * T)).margin(1e-10));
  CHECK(x[mx("ball.y")] == Approx(1.0).margin(1e-10));
}

TEST_CASE("time-dependent gravity: a free particle under (c t, -g)", "[numeric][time_dependent]") {
  const double c = gpar("c"), g = gpar("g"), u0 = 0.4, v0 = 2.0, T = 2.0;
  std::vector<double> x(GG::kNx, 0.0);
  x[gx("ball.u")] = u0;
  x[gx("ball.v")] = v0;
  auto f = [](double t, const double* s, double* sd) { return GG::rhs(t, s, nullptr, GG::kParamDefaults, sd); };
  REQUIRE(mbsc::runtime::rk4_integrate(f, 0.0, T, 200, x, [](double, const std::vector<double>&) {}) == 0);
  // RK4 integrates these polynomials in t exactly.
  CHECK(x[gx("ball.u")] == Approx(u0 + c * T * T / 2).margin(1e-12));
  CHECK(x[gx("ball.x")] == Approx(u0 * T + c * T * T * T / 6).margin(1e-12));
  CHECK(x[gx("ball.v")] == Approx(v0 - g * T).margin(1e-12));
  CHECK(x[gx("ball.y")] == Approx(v0 * T - g * T * T / 2).margin(1e-12));
}
