// SPDX-License-Identifier: GPL-2.0-or-later
// Thesis Ex 4.2 twice: models/ring_disc.mbs (rolling written by hand at velocity level,
// with the extra coordinate theta of the line between the centres) and
// models/ring_disc_joints.mbs (a `rolling` and a `rolling_inside` joint). A state of
// the joint model maps onto the invariant model's by
//   D - R = (r1 - r2) (sin(xi - theta), -cos(xi - theta)),
// and at such states both give the same accelerations of the six body speeds and the
// same energy; along a run the joint model keeps its contacts. The multipliers form of
// the joint model agrees with its complement form.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "mbsc/runtime/rk4.hpp"
#include "ring_disc/ring_disc.hpp"
#include "ring_disc_joints/ring_disc_joints.hpp"
#include "ring_disc_joints_mult/ring_disc_joints_mult.hpp"
#include "test_support.hpp"

namespace RD = mbsc_gen::ring_disc;
namespace RJ = mbsc_gen::ring_disc_joints;
namespace RM = mbsc_gen::ring_disc_joints_mult;
using mbsc_test::index_of;

namespace {

const char* const kBodySpeeds[] = {"R.u", "R.v", "R.w", "D.u", "D.v", "D.w"};

double param(const char* n) { return RJ::kParamDefaults[index_of(RJ::kParamNames, RJ::kNp, n)]; }

/// A consistent state of the joint model: ring at x0 turning at w1, disc at angle theta
/// of the centre line, turning at w2.
std::vector<double> joint_state(double x0, double theta, double w1, double w2, double phi1, double phi2) {
  const double r1 = param("r1"), r2 = param("r2"), xi = param("xi");
  std::vector<double> x(RJ::kNx, 0.0);
  auto set = [&](const char* n, double v) { x[static_cast<std::size_t>(index_of(RJ::kStateNames, RJ::kNx, n))] = v; };
  const double nx = std::sin(xi - theta), ny = -std::cos(xi - theta);  // from the ring's centre to the disc's
  const double tx = -ny, ty = nx;
  set("R.x", x0);
  set("R.y", r1);
  set("R.theta", phi1);
  set("D.x", x0 + (r1 - r2) * nx);
  set("D.y", r1 + (r1 - r2) * ny);
  set("D.theta", phi2);
  const double ru = -r1 * w1;
  set("R.u", ru);
  set("R.w", w1);
  set("D.u", ru + (r1 * w1 - r2 * w2) * tx);
  set("D.v", (r1 * w1 - r2 * w2) * ty);
  set("D.w", w2);
  return x;
}

/// The same state in the invariant model's layout (theta, dtheta added).
std::vector<double> invariant_state(const std::vector<double>& xj) {
  const double r1 = param("r1"), r2 = param("r2"), xi = param("xi");
  auto get = [&](const char* n) { return xj[static_cast<std::size_t>(index_of(RJ::kStateNames, RJ::kNx, n))]; };
  std::vector<double> x(RD::kNx, 0.0);
  for (int i = 0; i < RJ::kNx; ++i)
    x[static_cast<std::size_t>(index_of(RD::kStateNames, RD::kNx, RJ::kStateNames[i]))] = xj[static_cast<std::size_t>(i)];
  const double dx = get("D.x") - get("R.x"), dy = get("D.y") - get("R.y");
  const double theta = xi - std::atan2(dx, -dy);
  // d/dt (D - R) = -(r1 - r2) (cos(xi - theta), sin(xi - theta)) theta'
  const double du = get("D.u") - get("R.u"), dv = get("D.v") - get("R.v");
  const double dtheta = -(du * std::cos(xi - theta) + dv * std::sin(xi - theta)) / (r1 - r2);
  x[static_cast<std::size_t>(index_of(RD::kStateNames, RD::kNx, "theta"))] = theta;
  x[static_cast<std::size_t>(index_of(RD::kStateNames, RD::kNx, "dtheta"))] = dtheta;
  return x;
}

}  // namespace

TEST_CASE("ring and disc: the joint model equals the invariant-level model", "[numeric][ring_disc]") {
  REQUIRE(RJ::kNdof == RD::kNdof);
  REQUIRE(RJ::kNp == RD::kNp);
  for (int k = 0; k < RJ::kNp; ++k) REQUIRE(std::string(RJ::kParamNames[k]) == RD::kParamNames[k]);
  std::mt19937 gen(11);
  std::uniform_real_distribution<double> angle(-3.0, 3.0), speed(-4.0, 4.0);
  for (int trial = 0; trial < 25; ++trial) {
    const auto xj = joint_state(angle(gen), angle(gen), speed(gen), speed(gen), angle(gen), angle(gen));
    const auto xd = invariant_state(xj);
    // Both states satisfy their own constraints.
    std::vector<double> rj(RJ::kNc), rd(RD::kNc);
    REQUIRE(RJ::velocity_constraints(0.0, xj.data(), nullptr, RJ::kParamDefaults, rj.data()) == 0);
    REQUIRE(RD::velocity_constraints(0.0, xd.data(), nullptr, RD::kParamDefaults, rd.data()) == 0);
    for (double e : rj) REQUIRE(std::abs(e) < 1e-12);
    for (double e : rd) REQUIRE(std::abs(e) < 1e-12);
    std::vector<double> aj(RJ::kNx), ad(RD::kNx);
    REQUIRE(RJ::rhs(0.0, xj.data(), nullptr, RJ::kParamDefaults, aj.data()) == 0);
    REQUIRE(RD::rhs(0.0, xd.data(), nullptr, RD::kParamDefaults, ad.data()) == 0);
    double scale = 1.0;
    for (double e : ad) scale = std::max(scale, std::abs(e));
    for (const char* s : kBodySpeeds) {
      INFO(s);
      const double a = aj[static_cast<std::size_t>(index_of(RJ::kStateNames, RJ::kNx, s))];
      const double b = ad[static_cast<std::size_t>(index_of(RD::kStateNames, RD::kNx, s))];
      CHECK(std::abs(a - b) < 1e-10 * scale);
    }
    double ej[3], ed[3];
    REQUIRE(RJ::energy(0.0, xj.data(), nullptr, RJ::kParamDefaults, ej) == 0);
    REQUIRE(RD::energy(0.0, xd.data(), nullptr, RD::kParamDefaults, ed) == 0);
    CHECK(std::abs(ej[0] - ed[0]) < 1e-12 * std::max(1.0, std::abs(ed[0])));
  }
}

TEST_CASE("ring and disc joints: contacts hold along a run; multipliers agree", "[numeric][ring_disc]") {
  auto x = joint_state(0.0, 0.4, 0.0, 0.0, 0.0, 0.0);
  auto xm = x;
  std::vector<double> pm(RJ::kParamDefaults, RJ::kParamDefaults + RJ::kNp);
  pm.push_back(10.0);
  pm.push_back(10.0);
  double e0[3];
  REQUIRE(RJ::energy(0.0, x.data(), nullptr, RJ::kParamDefaults, e0) == 0);
  auto f = [&](double t, const double* s, double* sd) { return RJ::rhs(t, s, nullptr, RJ::kParamDefaults, sd); };
  auto fm = [&](double t, const double* s, double* sd) { return RM::rhs(t, s, nullptr, pm.data(), sd); };
  double diff = 0.0, closure = 0.0, energy = 0.0;
  std::vector<double> g(RJ::kNposc);
  for (int step = 0; step < 2000; ++step) {
    REQUIRE(mbsc::runtime::rk4_step(f, step * 5e-4, 5e-4, x) == 0);
    REQUIRE(mbsc::runtime::rk4_step(fm, step * 5e-4, 5e-4, xm) == 0);
    for (std::size_t i = 0; i < x.size(); ++i) diff = std::max(diff, std::abs(x[i] - xm[i]));
    REQUIRE(RJ::position_constraints(0.0, x.data(), nullptr, RJ::kParamDefaults, g.data()) == 0);
    for (double e : g) closure = std::max(closure, std::abs(e));
    double e[3];
    REQUIRE(RJ::energy(0.0, x.data(), nullptr, RJ::kParamDefaults, e) == 0);
    energy = std::max(energy, std::abs(e[2] - e0[2]));
  }
  INFO("max difference " << diff << ", closure " << closure << ", energy " << energy);
  CHECK(diff < 1e-7);
  CHECK(closure < 1e-9);
  CHECK(energy < 1e-8 * std::abs(e0[1]) + 1e-9);  // rolling without slip does no work
  CHECK(x[static_cast<std::size_t>(index_of(RJ::kStateNames, RJ::kNx, "R.x"))] > 0.1);  // it rolled down
}
