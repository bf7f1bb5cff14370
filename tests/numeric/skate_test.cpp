// SPDX-License-Identifier: GPL-2.0-or-later
// The skate (tests/data/planar/skate_invariants.mbs): a planar blade with the knife-edge
// condition -sin(theta) u + cos(theta) v = 0 at its mass centre, no forces. Its automatic
// independent set is chosen at the reference configuration theta = 0, so the generated
// rhs works where the skate starts. Free of forces it keeps its forward speed s and its
// yaw rate w, and its mass centre runs on a circle of radius s / w:
//   theta = theta0 + w t,  x = x0 + (s / w) (sin theta - sin theta0),
//   y = y0 - (s / w) (cos theta - cos theta0).
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "mbsc/runtime/rk4.hpp"
#include "skate_invariants/skate_invariants.hpp"
#include "test_support.hpp"

namespace SK = mbsc_gen::skate_invariants;
using mbsc_test::index_of;

namespace {
int at(const char* name) { return index_of(SK::kStateNames, SK::kNx, name); }
}  // namespace

TEST_CASE("skate: the automatic independent set works at theta = 0", "[numeric][skate]") {
  REQUIRE(SK::kNdof == 2);
  // The sideways speed is the dependent one at theta = 0: the set is {u, w}.
  CHECK(std::string(SK::kDofNames[0]) == "b.u");
  CHECK(std::string(SK::kDofNames[1]) == "b.w");
  std::vector<double> p(SK::kParamDefaults, SK::kParamDefaults + SK::kNp);
  std::vector<double> x(SK::kNx, 0.0), xd(SK::kNx, 0.0);
  x[at("b.u")] = 1.5;
  x[at("b.w")] = 0.4;
  REQUIRE(SK::rhs(0.0, x.data(), nullptr, p.data(), xd.data()) == 0);
  // At theta = 0 the blade points along x: x' = u, y' = v = 0, theta' = w, and the
  // constraint force (sideways, along y) turns the velocity: v' = u w, u' = 0, w' = 0.
  CHECK(xd[at("b.x")] == Approx(1.5).margin(1e-14));
  CHECK(xd[at("b.y")] == Approx(0.0).margin(1e-14));
  CHECK(xd[at("b.theta")] == Approx(0.4).margin(1e-14));
  CHECK(xd[at("b.u")] == Approx(0.0).margin(1e-12));
  CHECK(xd[at("b.v")] == Approx(1.5 * 0.4).margin(1e-12));
  CHECK(xd[at("b.w")] == Approx(0.0).margin(1e-12));
}

TEST_CASE("skate: free motion is a circle at constant speed and yaw rate", "[numeric][skate]") {
  std::vector<double> p(SK::kParamDefaults, SK::kParamDefaults + SK::kNp);
  const double s = 1.2, w = 0.5, x0 = 0.3, y0 = -0.2, th0 = 0.0;
  std::vector<double> x(SK::kNx, 0.0);
  x[at("b.x")] = x0;
  x[at("b.y")] = y0;
  x[at("b.theta")] = th0;
  x[at("b.u")] = s * std::cos(th0);
  x[at("b.v")] = s * std::sin(th0);
  x[at("b.w")] = w;
  auto rhs = [&](double t, const double* state, double* out) { return SK::rhs(t, state, nullptr, p.data(), out); };
  double e0[3];
  REQUIRE(SK::energy(0.0, x.data(), nullptr, p.data(), e0) == 0);
  double worst_position = 0, worst_energy = 0, worst_constraint = 0;
  // Two seconds: theta runs from 0 to 1 rad, away from theta = pi/2 where this set fails.
  REQUIRE(mbsc::runtime::rk4_integrate(rhs, 0.0, 2.0, 2000, x, [&](double t, const std::vector<double>& st) {
            const double th = th0 + w * t;
            const double r = s / w;
            worst_position = std::max({worst_position, std::abs(st[at("b.theta")] - th),
                                       std::abs(st[at("b.x")] - (x0 + r * (std::sin(th) - std::sin(th0)))),
                                       std::abs(st[at("b.y")] - (y0 - r * (std::cos(th) - std::cos(th0))))});
            double e[3], c[1];
            REQUIRE(SK::energy(t, st.data(), nullptr, p.data(), e) == 0);
            REQUIRE(SK::velocity_constraints(t, st.data(), nullptr, p.data(), c) == 0);
            worst_energy = std::max(worst_energy, std::abs(e[2] - e0[2]));
            worst_constraint = std::max(worst_constraint, std::abs(c[0]));
          }) == 0);
  CHECK(worst_position < 1e-9);
  CHECK(worst_energy < 1e-9);
  CHECK(worst_constraint < 1e-9);
  // The forward speed and the yaw rate are where they started.
  const double th = x[at("b.theta")];
  CHECK(x[at("b.u")] * std::cos(th) + x[at("b.v")] * std::sin(th) == Approx(s).epsilon(1e-10));
  CHECK(x[at("b.w")] == Approx(w).epsilon(1e-10));
}
