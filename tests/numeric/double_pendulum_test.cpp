// SPDX-License-Identifier: GPL-2.0-or-later
// Planar double pendulum (point masses): generated accelerations against the
// textbook closed form, and energy conservation of a fine RK4 run.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "double_pendulum/double_pendulum.hpp"
#include "mbsc/runtime/rk4.hpp"
#include "test_support.hpp"

namespace DP = mbsc_gen::double_pendulum;
using mbsc_test::index_of;

namespace {

int ix(const char* n) { return index_of(DP::kStateNames, DP::kNx, n); }
double par(const char* n) { return DP::kParamDefaults[index_of(DP::kParamNames, DP::kNp, n)]; }

/// A consistent state from the angles and their rates.
std::vector<double> state(double th1, double th2, double w1, double w2) {
  const double l1 = par("l1"), l2 = par("l2");
  std::vector<double> x(DP::kNx, 0.0);
  x[ix("th1")] = th1;
  x[ix("th2")] = th2;
  x[ix("w1")] = w1;
  x[ix("w2")] = w2;
  x[ix("b1.x")] = l1 * std::sin(th1);
  x[ix("b1.y")] = -l1 * std::cos(th1);
  x[ix("b2.x")] = l1 * std::sin(th1) + l2 * std::sin(th2);
  x[ix("b2.y")] = -l1 * std::cos(th1) - l2 * std::cos(th2);
  x[ix("b1.u")] = l1 * std::cos(th1) * w1;
  x[ix("b1.v")] = l1 * std::sin(th1) * w1;
  x[ix("b2.u")] = x[ix("b1.u")] + l2 * std::cos(th2) * w2;
  x[ix("b2.v")] = x[ix("b1.v")] + l2 * std::sin(th2) * w2;
  return x;
}

}  // namespace

TEST_CASE("double pendulum: accelerations equal the closed form", "[numeric][double_pendulum]") {
  const double m1 = par("m1"), m2 = par("m2"), l1 = par("l1"), l2 = par("l2"), g = par("g");
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(-3.0, 3.0), rate(-4.0, 4.0);
  for (int k = 0; k < 50; ++k) {
    const double t1 = angle(rng), t2 = angle(rng), w1 = rate(rng), w2 = rate(rng);
    auto x = state(t1, t2, w1, w2);
    std::vector<double> xd(DP::kNx);
    REQUIRE(DP::rhs(0.0, x.data(), nullptr, DP::kParamDefaults, xd.data()) == 0);
    const double d = t1 - t2, den = 2 * m1 + m2 - m2 * std::cos(2 * d);
    const double a1 = (-g * (2 * m1 + m2) * std::sin(t1) - m2 * g * std::sin(t1 - 2 * t2) -
                       2 * std::sin(d) * m2 * (w2 * w2 * l2 + w1 * w1 * l1 * std::cos(d))) /
                      (l1 * den);
    const double a2 = 2 * std::sin(d) * (w1 * w1 * l1 * (m1 + m2) + g * (m1 + m2) * std::cos(t1) + w2 * w2 * l2 * m2 * std::cos(d)) /
                      (l2 * den);
    CHECK(std::abs(xd[ix("w1")] - a1) < 1e-12 * std::max(1.0, std::abs(a1)));
    CHECK(std::abs(xd[ix("w2")] - a2) < 1e-12 * std::max(1.0, std::abs(a2)));
    CHECK(xd[ix("th1")] == Approx(w1).margin(1e-14));
  }
}

TEST_CASE("double pendulum: energy drift of a fine RK4 run over 10 s", "[numeric][double_pendulum]") {
  auto x = state(2.0, 2.5, 0.0, 0.0);
  auto rhs = [](double t, const double* s, double* sd) { return DP::rhs(t, s, nullptr, DP::kParamDefaults, sd); };
  double e0[3], e1[3];
  REQUIRE(DP::energy(0.0, x.data(), nullptr, DP::kParamDefaults, e0) == 0);
  double worst = 0.0;
  REQUIRE(mbsc::runtime::rk4_integrate(rhs, 0.0, 10.0, 40000, x, [&](double t, const std::vector<double>& s) {
            double e[3];
            DP::energy(t, s.data(), nullptr, DP::kParamDefaults, e);
            worst = std::max(worst, std::abs(e[2] - e0[2]) / std::abs(e0[2]));
          }) == 0);
  REQUIRE(DP::energy(10.0, x.data(), nullptr, DP::kParamDefaults, e1) == 0);
  INFO("worst relative energy drift: " << worst);
  CHECK(worst < 1e-9);
  // The motion is not trivial: the kinetic energy changed a lot along the way.
  CHECK(std::abs(e1[0] - e0[0]) > 1e-3);
}
