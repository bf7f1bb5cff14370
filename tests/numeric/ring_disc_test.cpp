// SPDX-License-Identifier: GPL-2.0-or-later
// Thesis Ex 4.2(h): steady motion of the ring rolling down the incline with the disc
// inside it. At theta = thetabar, with every speed zero, theta'' = 0 exactly when
//   m2/m1 = sin(thetabar) / (2 sin(xi) cos(thetabar - xi) - 3 sin(thetabar) + sin(xi)) - 1,
// and then u1' = u2' = 2 g sin(thetabar) / (2 cos(thetabar - xi) + 1), w1' = -u1'/r1, w2' = -u2'/r2.
#include <catch2/catch.hpp>
#include <cmath>

#include "ring_disc/ring_disc.hpp"
#include "test_support.hpp"

namespace RD = mbsc_gen::ring_disc;
using mbsc_test::index_of;

namespace {

double mass_ratio(double xi, double th) {
  return std::sin(th) / (2 * std::sin(xi) * std::cos(th - xi) - 3 * std::sin(th) + std::sin(xi)) - 1;
}

struct Accel {
  std::vector<double> xd;
  double get(const char* n) const { return xd[index_of(RD::kStateNames, RD::kNx, n)]; }
};

Accel accelerations(double xi, double th, double ratio) {
  std::vector<double> p(RD::kParamDefaults, RD::kParamDefaults + RD::kNp);
  const double m1 = p[index_of(RD::kParamNames, RD::kNp, "m1")];
  p[index_of(RD::kParamNames, RD::kNp, "m2")] = ratio * m1;
  p[index_of(RD::kParamNames, RD::kNp, "xi")] = xi;
  std::vector<double> x(RD::kNx, 0.0);
  x[index_of(RD::kStateNames, RD::kNx, "theta")] = th;
  Accel a{std::vector<double>(RD::kNx)};
  REQUIRE(RD::rhs(0.0, x.data(), nullptr, p.data(), a.xd.data()) == 0);
  return a;
}

}  // namespace

TEST_CASE("Ex 4.2(h): steady motion relation between m2/m1, thetabar and xi", "[numeric][ring_disc]") {
  REQUIRE(RD::kNdof == 2);
  const double g = RD::kParamDefaults[index_of(RD::kParamNames, RD::kNp, "g")];
  const double r1 = RD::kParamDefaults[index_of(RD::kParamNames, RD::kNp, "r1")];
  const double r2 = RD::kParamDefaults[index_of(RD::kParamNames, RD::kNp, "r2")];
  // (xi, thetabar): the thesis pair (asin 4/5, asin 3/5), ratio 8/67, and three more.
  const double pairs[][2] = {{std::asin(0.8), std::asin(0.6)}, {0.3, 0.25}, {0.5, 0.45}, {1.0, 0.9}};
  for (const auto& pr : pairs) {
    const double xi = pr[0], th = pr[1];
    const double ratio = mass_ratio(xi, th);
    INFO("xi = " << xi << ", thetabar = " << th << ", m2/m1 = " << ratio);
    REQUIRE(ratio > 0.0);
    Accel a = accelerations(xi, th, ratio);
    const double udot = 2 * g * std::sin(th) / (2 * std::cos(th - xi) + 1);
    CHECK(std::abs(a.get("dtheta")) < 1e-10);
    CHECK(std::abs(a.get("R.u") - udot) < 1e-10);
    CHECK(std::abs(a.get("D.u") - udot) < 1e-10);
    CHECK(std::abs(a.get("R.v")) < 1e-10);
    CHECK(std::abs(a.get("D.v")) < 1e-10);
    CHECK(std::abs(a.get("R.w") + udot / r1) < 1e-10);
    CHECK(std::abs(a.get("D.w") + udot / r2) < 1e-10);
    // Any other mass ratio is not a steady motion: theta'' moves away from zero.
    Accel off = accelerations(xi, th, ratio * 1.1 + 0.01);
    CHECK(std::abs(off.get("dtheta")) > 1e-6);
  }
  CHECK(mass_ratio(std::asin(0.8), std::asin(0.6)) == Approx(8.0 / 67.0).epsilon(1e-12));
}
