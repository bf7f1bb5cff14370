// SPDX-License-Identifier: GPL-2.0-or-later
// The planar knife edge (docs/language.md, `joint knife_edge`): the Chaplygin sleigh
// (models/chaplygin_sleigh.mbs) and a skate (tests/data/planar/skate.mbs) against their
// closed forms. With V the mass centre's speed along the blade, w the yaw rate, the
// mass centre a ahead of the blade and J its inertia about the mass centre, the sleigh
// obeys V' = a w^2, w' = -m a V w / (J + m a^2); with the energy E = (m V^2 + (J + m a^2) w^2)/2
// this gives V(t) = c tanh(k c t + phi), w(t) = w0 cosh(phi) / cosh(k c t + phi), with
// c = sqrt(2E/m), k = m a / (J + m a^2), phi = atanh(V0/c): the yaw rate dies out and the
// speed tends to c. A skate (a = 0) keeps V and w: its mass centre runs round a circle.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "chaplygin_sleigh/chaplygin_sleigh.hpp"
#include "mbsc/runtime/rk4.hpp"
#include "skate/skate.hpp"
#include "test_support.hpp"

namespace CS = mbsc_gen::chaplygin_sleigh;
namespace SK = mbsc_gen::skate;
using mbsc_test::index_of;

namespace {

double par(const char* n) { return CS::kParamDefaults[index_of(CS::kParamNames, CS::kNp, n)]; }
int ix(const char* n) { return index_of(CS::kStateNames, CS::kNx, n); }
int sx(const char* n) { return index_of(SK::kStateNames, SK::kNx, n); }

/// A consistent sleigh state: heading th, forward speed V, yaw rate w (lateral speed a w).
std::vector<double> sleigh(double th, double V, double w) {
  const double W = par("a") * w;
  std::vector<double> x(CS::kNx, 0.0);
  x[ix("sleigh.theta")] = th;
  x[ix("sleigh.u")] = V * std::cos(th) - W * std::sin(th);
  x[ix("sleigh.v")] = V * std::sin(th) + W * std::cos(th);
  x[ix("sleigh.w")] = w;
  return x;
}

double forward(const std::vector<double>& x) {
  const double th = x[ix("sleigh.theta")];
  return x[ix("sleigh.u")] * std::cos(th) + x[ix("sleigh.v")] * std::sin(th);
}

}  // namespace

TEST_CASE("knife edge: the sleigh's accelerations are the reduced equations", "[numeric][knife_edge]") {
  const double m = par("m"), J = par("J"), a = par("a");
  CHECK(CS::kNdof == 2);
  CHECK(CS::kNc == 1);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> angle(-3.0, 3.0), rate(-2.0, 2.0);
  for (int k = 0; k < 30; ++k) {
    const double th = angle(rng), V = rate(rng), w = rate(rng);
    const auto x = sleigh(th, V, w);
    double c = 1.0;
    REQUIRE(CS::velocity_constraints(0.0, x.data(), nullptr, CS::kParamDefaults, &c) == 0);
    CHECK(c == Approx(0.0).margin(1e-14));
    std::vector<double> xd(CS::kNx);
    REQUIRE(CS::rhs(0.0, x.data(), nullptr, CS::kParamDefaults, xd.data()) == 0);
    // V' = u' cos th + v' sin th + w (-u sin th + v cos th) = u' cos th + v' sin th + a w^2.
    const double Vd = xd[ix("sleigh.u")] * std::cos(th) + xd[ix("sleigh.v")] * std::sin(th) + a * w * w;
    CHECK(Vd == Approx(a * w * w).margin(1e-12));
    CHECK(xd[ix("sleigh.w")] == Approx(-m * a * V * w / (J + m * a * a)).margin(1e-12));
  }
}

TEST_CASE("knife edge: the sleigh conserves energy, keeps its constraint and follows the closed form",
          "[numeric][knife_edge]") {
  const double m = par("m"), J = par("J"), a = par("a");
  const double V0 = 0.2, w0 = 2.0;
  auto x = sleigh(0.4, V0, w0);
  const double E = 0.5 * (m * V0 * V0 + (J + m * a * a) * w0 * w0);
  const double c = std::sqrt(2 * E / m), k = m * a / (J + m * a * a), phi = std::atanh(V0 / c);
  double e0[3];
  REQUIRE(CS::energy(0.0, x.data(), nullptr, CS::kParamDefaults, e0) == 0);
  CHECK(e0[2] == Approx(E).epsilon(1e-14));
  auto f = [](double t, const double* s, double* sd) { return CS::rhs(t, s, nullptr, CS::kParamDefaults, sd); };
  double drift = 0.0, lateral = 0.0, worst_V = 0.0, worst_w = 0.0;
  REQUIRE(mbsc::runtime::rk4_integrate(f, 0.0, 8.0, 16000, x, [&](double t, const std::vector<double>& s) {
            double e[3], g = 0.0;
            CS::energy(t, s.data(), nullptr, CS::kParamDefaults, e);
            CS::velocity_constraints(t, s.data(), nullptr, CS::kParamDefaults, &g);
            drift = std::max(drift, std::abs(e[2] - E) / E);
            lateral = std::max(lateral, std::abs(g));
            worst_V = std::max(worst_V, std::abs(forward(s) - c * std::tanh(k * c * t + phi)));
            worst_w = std::max(worst_w, std::abs(s[static_cast<std::size_t>(ix("sleigh.w"))] -
                                                 w0 * std::cosh(phi) / std::cosh(k * c * t + phi)));
          }) == 0);
  INFO("energy drift " << drift << ", constraint " << lateral << ", V error " << worst_V << ", w error " << worst_w);
  CHECK(drift < 1e-9);
  CHECK(lateral < 1e-9);
  CHECK(worst_V < 1e-8);
  CHECK(worst_w < 1e-8);
  // The known asymptote: the yaw has died out and the speed is the one the energy fixes.
  CHECK(std::abs(x[ix("sleigh.w")]) < 1e-4);
  CHECK(forward(x) == Approx(c).epsilon(1e-6));
  // The named expressions of the model file say the same.
  double out[2];
  REQUIRE(CS::outputs(8.0, x.data(), nullptr, CS::kParamDefaults, out) == 0);
  CHECK(out[index_of(CS::kOutputNames, 2, "forward_speed")] == Approx(forward(x)).epsilon(1e-14));
  CHECK(out[index_of(CS::kOutputNames, 2, "lateral_speed")] == Approx(a * x[ix("sleigh.w")]).margin(1e-12));
}

TEST_CASE("knife edge: a skate keeps its speed and yaw rate and runs round a circle", "[numeric][knife_edge]") {
  const double th0 = 0.2, V = 1.5, w = 0.5, T = 2.0;  // theta stays in [0.2, 1.2]: v = u tan(theta) is regular
  std::vector<double> x(SK::kNx, 0.0);
  x[sx("skate.theta")] = th0;
  x[sx("skate.u")] = V * std::cos(th0);
  x[sx("skate.v")] = V * std::sin(th0);
  x[sx("skate.w")] = w;
  auto f = [](double t, const double* s, double* sd) { return SK::rhs(t, s, nullptr, SK::kParamDefaults, sd); };
  double worst_speed = 0.0;
  REQUIRE(mbsc::runtime::rk4_integrate(f, 0.0, T, 4000, x, [&](double, const std::vector<double>& s) {
            const double th = s[static_cast<std::size_t>(sx("skate.theta"))];
            const double along = s[static_cast<std::size_t>(sx("skate.u"))] * std::cos(th) +
                                 s[static_cast<std::size_t>(sx("skate.v"))] * std::sin(th);
            worst_speed = std::max(worst_speed, std::abs(along - V));
          }) == 0);
  CHECK(worst_speed < 1e-10);
  CHECK(x[sx("skate.w")] == Approx(w).margin(1e-12));
  const double th = th0 + w * T;
  CHECK(x[sx("skate.theta")] == Approx(th).margin(1e-10));
  CHECK(x[sx("skate.x")] == Approx(V / w * (std::sin(th) - std::sin(th0))).margin(1e-9));
  CHECK(x[sx("skate.y")] == Approx(-V / w * (std::cos(th) - std::cos(th0))).margin(1e-9));
}
