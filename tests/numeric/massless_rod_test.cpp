// SPDX-License-Identifier: GPL-2.0-or-later
// Massless links (docs/language.md "Massless links"): the IFToMM simple pendulum, a point
// mass on a rod with mass 0 and inertia 0 (models/massless_rod_pendulum.mbs), against
// the closed form (theta'' = -(g/l) cos theta, the small-amplitude period 2 pi sqrt(l/g)),
// energy conservation over an RK4 run, the same pendulum written at the invariant level
// with no rod, and the multipliers formulation (whose KKT system takes the massless rod).
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "massless_rod_pendulum/massless_rod_pendulum.hpp"
#include "massless_rod_pendulum_mult/massless_rod_pendulum_mult.hpp"
#include "mbsc/runtime/rk4.hpp"
#include "point_pendulum_invariants/point_pendulum_invariants.hpp"
#include "test_support.hpp"

namespace MR = mbsc_gen::massless_rod_pendulum;
namespace MM = mbsc_gen::massless_rod_pendulum_mult;
namespace PP = mbsc_gen::point_pendulum_invariants;
using mbsc_test::index_of;

namespace {

const double kPi = std::acos(-1.0);
double par(const char* n) { return MR::kParamDefaults[index_of(MR::kParamNames, MR::kNp, n)]; }

/// A consistent state of a rod model (MR or its multipliers twin: the same state names).
template <int Nx>
std::vector<double> rod_state(const char* const* names, double th, double w) {
  const double l = par("l");
  auto ix = [&](const char* n) { return index_of(names, Nx, n); };
  std::vector<double> x(Nx, 0.0);
  x[ix("rod.theta")] = th;
  x[ix("rod.w")] = w;
  x[ix("bob.x")] = l * std::cos(th);
  x[ix("bob.y")] = l * std::sin(th);
  x[ix("bob.u")] = -l * std::sin(th) * w;
  x[ix("bob.v")] = l * std::cos(th) * w;
  return x;
}

std::vector<double> point_state(double th, double w) {
  const double l = par("l");
  auto ix = [](const char* n) { return index_of(PP::kStateNames, PP::kNx, n); };
  std::vector<double> x(PP::kNx, 0.0);
  x[ix("th")] = th;
  x[ix("w")] = w;
  x[ix("bob.x")] = l * std::cos(th);
  x[ix("bob.y")] = l * std::sin(th);
  x[ix("bob.u")] = -l * std::sin(th) * w;
  x[ix("bob.v")] = l * std::cos(th) * w;
  return x;
}

int mr(const char* n) { return index_of(MR::kStateNames, MR::kNx, n); }

}  // namespace

TEST_CASE("massless rod pendulum: one degree of freedom, the bob's inertia alone", "[numeric][massless]") {
  CHECK(MR::kNdof == 1);
  // M = m l^2: the rod adds nothing.
  const auto x = rod_state<MR::kNx>(MR::kStateNames, 0.3, 0.7);
  double M = 0.0;
  REQUIRE(MR::mass_matrix(0.0, x.data(), nullptr, MR::kParamDefaults, &M) == 0);
  CHECK(M == Approx(par("m") * par("l") * par("l")).epsilon(1e-14));
}

TEST_CASE("massless rod pendulum: accelerations equal the closed form and the rod-free model", "[numeric][massless]") {
  const double g = par("g"), l = par("l");
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> angle(-3.0, 3.0), rate(-4.0, 4.0);
  for (int k = 0; k < 30; ++k) {
    const double th = angle(rng), w = rate(rng);
    const auto x = rod_state<MR::kNx>(MR::kStateNames, th, w);
    std::vector<double> xd(MR::kNx), xp(PP::kNx), xm(MM::kNx);
    REQUIRE(MR::rhs(0.0, x.data(), nullptr, MR::kParamDefaults, xd.data()) == 0);
    const double closed = -g / l * std::cos(th);
    CHECK(xd[mr("rod.w")] == Approx(closed).margin(1e-12));
    const auto y = point_state(th, w);
    REQUIRE(PP::rhs(0.0, y.data(), nullptr, PP::kParamDefaults, xp.data()) == 0);
    CHECK(xd[mr("rod.w")] == Approx(xp[index_of(PP::kStateNames, PP::kNx, "w")]).margin(1e-12));
    CHECK(xd[mr("bob.u")] == Approx(xp[index_of(PP::kStateNames, PP::kNx, "bob.u")]).margin(1e-12));
    CHECK(xd[mr("bob.v")] == Approx(xp[index_of(PP::kStateNames, PP::kNx, "bob.v")]).margin(1e-12));
    const auto z = rod_state<MM::kNx>(MM::kStateNames, th, w);
    REQUIRE(MM::rhs(0.0, z.data(), nullptr, MM::kParamDefaults, xm.data()) == 0);
    CHECK(xm[index_of(MM::kStateNames, MM::kNx, "rod.w")] == Approx(closed).margin(1e-9));
  }
}

TEST_CASE("massless rod pendulum: small-amplitude period 2 pi sqrt(l/g)", "[numeric][massless]") {
  const double g = par("g"), l = par("l"), period = 2 * kPi * std::sqrt(l / g);
  auto x = rod_state<MR::kNx>(MR::kStateNames, -kPi / 2 + 0.01, 0.0);  // 0.01 rad from hanging straight down
  auto rhs = [](double t, const double* s, double* sd) { return MR::rhs(t, s, nullptr, MR::kParamDefaults, sd); };
  // Times where the rate turns from positive to negative (the swing's far ends), by
  // linear interpolation between steps: one period apart.
  std::vector<double> turns;
  double prev_t = 0.0, prev_w = 0.0;
  REQUIRE(mbsc::runtime::rk4_integrate(rhs, 0.0, 3.5 * period, 20000, x, [&](double t, const std::vector<double>& s) {
            const double w = s[static_cast<std::size_t>(mr("rod.w"))];
            if (prev_w > 0.0 && w <= 0.0) turns.push_back(prev_t + (t - prev_t) * prev_w / (prev_w - w));
            prev_t = t;
            prev_w = w;
          }) == 0);
  REQUIRE(turns.size() >= 3);
  // The finite amplitude lengthens the period by about theta0^2/16 (6e-6 here).
  CHECK((turns[2] - turns[1]) == Approx(period).epsilon(2e-5));
}

TEST_CASE("massless rod pendulum: energy is conserved and the motion equals the rod-free model", "[numeric][massless]") {
  // The IFToMM benchmark's start: released from the horizontal.
  auto x = rod_state<MR::kNx>(MR::kStateNames, 0.0, 0.0);
  auto y = point_state(0.0, 0.0);
  auto f = [](double t, const double* s, double* sd) { return MR::rhs(t, s, nullptr, MR::kParamDefaults, sd); };
  auto fp = [](double t, const double* s, double* sd) { return PP::rhs(t, s, nullptr, PP::kParamDefaults, sd); };
  double e0[3];
  REQUIRE(MR::energy(0.0, x.data(), nullptr, MR::kParamDefaults, e0) == 0);
  const double scale = par("m") * par("g") * par("l");
  double worst = 0.0, lowest = 0.0;
  REQUIRE(mbsc::runtime::rk4_integrate(f, 0.0, 10.0, 40000, x, [&](double t, const std::vector<double>& s) {
            double e[3];
            MR::energy(t, s.data(), nullptr, MR::kParamDefaults, e);
            worst = std::max(worst, std::abs(e[2] - e0[2]) / scale);
            lowest = std::min(lowest, s[static_cast<std::size_t>(mr("bob.y"))]);
          }) == 0);
  REQUIRE(mbsc::runtime::rk4_integrate(fp, 0.0, 10.0, 40000, y, [](double, const std::vector<double>&) {}) == 0);
  INFO("worst energy drift / (m g l): " << worst);
  CHECK(worst < 1e-9);
  CHECK(lowest == Approx(-par("l")).margin(1e-6));  // it swings through the bottom
  CHECK(x[static_cast<std::size_t>(mr("rod.theta"))] ==
        Approx(y[static_cast<std::size_t>(index_of(PP::kStateNames, PP::kNx, "th"))]).margin(1e-9));
}
