// SPDX-License-Identifier: GPL-2.0-or-later
// The conditioning report must cover every solve a partition's rhs makes. A particle on
// a rod in Cartesian coordinates (tests/data/partition/circle_particle.mbs) has 1x1
// dependent blocks: 2y when u is independent, 2x when v is. A 1x1 block's plain rcond is
// 1 however small it is; what goes wrong as y -> 0 is the gain v = -(x/y) u and the
// reduced mass matrix m (1 + x^2/y^2) built from it. Checked here:
//   - near the horizontal the u partition reports about |y/x| (closed form) and the v
//     partition about 1, and both give the closed-form acceleration where regular;
//   - so close to it that the u partition's mass matrix overflows, its report is 0 while
//     its rhs returns garbage or fails;
//   - the selector then leaves the u partition, and a run over full revolutions switches
//     four times per turn and keeps energy and the rod length.
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "circle_particle/circle_particle.hpp"
#include "mbsc/runtime/partition_selector.hpp"
#include "mbsc/runtime/rk4.hpp"

namespace P = mbsc_gen::circle_particle;

namespace {

/// The particle at angle phi from the x axis, turning at w (radius r = 1).
std::vector<double> at(double phi, double w) {
  return {std::cos(phi), std::sin(phi), -std::sin(phi) * w, std::cos(phi) * w};
}

double report(int k, const std::vector<double>& x) {
  double rc = -1.0;
  REQUIRE(P::conditioning_partition(k, 0.0, x.data(), nullptr, P::kParamDefaults, &rc) == 0);
  return rc;
}

}  // namespace

TEST_CASE("1x1 dependent block: the conditioning sees its gain", "[numeric][partition]") {
  REQUIRE(P::kNpartitions == 2);
  const double g = P::kParamDefaults[2];
  for (double eps : {1e-1, 1e-3, 1e-6}) {
    INFO("angle " << eps << " from the horizontal");
    const auto x = at(eps, 0.7);
    // u independent: block 2y, gain 2x: rcond = |y| / |x| = tan(eps).
    CHECK(report(0, x) == Approx(std::tan(eps)).epsilon(1e-12));
    CHECK(report(1, x) == Approx(1.0));
    // Where regular both give the closed-form tangential acceleration -g cos(phi) (and
    // the centripetal w^2 inwards).
    std::vector<double> xd(4);
    REQUIRE(P::rhs_partition(1, 0.0, x.data(), nullptr, P::kParamDefaults, xd.data()) == 0);
    const double at_ = -g * std::cos(eps), ac = 0.49;
    CHECK(xd[2] == Approx(-std::sin(eps) * at_ - std::cos(eps) * ac).margin(1e-12));
    CHECK(xd[3] == Approx(std::cos(eps) * at_ - std::sin(eps) * ac).margin(1e-12));
  }
  // Exactly vertical it is the v partition whose block vanishes.
  CHECK(report(1, at(M_PI / 2, 1.0)) < 1e-15);
  CHECK(report(0, at(M_PI / 2, 1.0)) == Approx(1.0));
}

TEST_CASE("1x1 dependent block: where the rhs breaks down the report is 0", "[numeric][partition]") {
  // y = 1e-170: the gain x/y = 1e170 squares to infinity in the reduced mass matrix, so
  // the u partition's rhs fails or returns a wrong acceleration; the report says so.
  auto x = at(0.0, 0.3);
  x[1] = 1e-170;
  std::vector<double> xd0(4), xd1(4);
  REQUIRE(P::rhs_partition(1, 0.0, x.data(), nullptr, P::kParamDefaults, xd1.data()) == 0);
  const int s0 = P::rhs_partition(0, 0.0, x.data(), nullptr, P::kParamDefaults, xd0.data());
  CHECK((s0 != 0 || std::abs(xd0[3] - xd1[3]) > 1.0));  // broken: the v partition is right
  CHECK(report(0, x) < 1e-150);
  CHECK(report(1, x) == Approx(1.0));
  mbsc::runtime::PartitionSelector sel({P::kNpartitions, &P::rhs_partition, &P::conditioning_partition});
  REQUIRE(sel.update(0.0, x.data(), nullptr, P::kParamDefaults) == 0);
  CHECK(sel.active() == 1);
}

TEST_CASE("1x1 dependent block: a run over full turns switches at every axis crossing", "[numeric][partition]") {
  // Enough energy to go over the top; RK4 on the full state with the selector.
  auto x = at(-M_PI / 2, 8.0);
  const double* p = P::kParamDefaults;
  double e0[3];
  REQUIRE(P::energy(0.0, x.data(), nullptr, p, e0) == 0);
  mbsc::runtime::PartitionSelector sel({P::kNpartitions, &P::rhs_partition, &P::conditioning_partition});
  auto f = [&](double t, const double* s, double* sd) { return sel.rhs(t, s, nullptr, p, sd); };
  const double h = 1e-3;
  double angle = -M_PI / 2, drift = 0.0, closure = 0.0;
  for (int step = 0; step < 3000; ++step) {
    REQUIRE(sel.update(step * h, x.data(), nullptr, p) == 0);
    REQUIRE(mbsc::runtime::rk4_step(f, step * h, h, x) == 0);
    double e[3];
    REQUIRE(P::energy(0.0, x.data(), nullptr, p, e) == 0);
    drift = std::max(drift, std::abs(e[2] - e0[2]) / std::abs(e0[2]));
    closure = std::max(closure, std::abs(x[0] * x[0] + x[1] * x[1] - 1.0));
    const double phi = std::atan2(x[1], x[0]);
    angle += std::remainder(phi - angle, 2 * M_PI);
  }
  const double turns = (angle + M_PI / 2) / (2 * M_PI);
  INFO("turns " << turns << ", switches " << sel.switches() << ", energy drift " << drift << ", closure " << closure);
  REQUIRE(turns > 2.0);
  // Four axis crossings per turn, each a switch (hysteresis keeps it to one).
  CHECK(sel.switches() >= 4 * static_cast<int>(turns) - 1);
  CHECK(sel.switches() <= 4 * static_cast<int>(turns) + 4);
  CHECK(drift < 1e-6);
  CHECK(closure < 1e-6);
}
