// SPDX-License-Identifier: GPL-2.0-or-later
// The shipped planar mechanisms of thesis §5.3 (Whitworth quick-return, 3RRR): assembly
// from the thesis's partial initial data recovers its full configuration, and the
// complement and multipliers formulations give the same accelerations there.
#include <catch2/catch.hpp>
#include <cmath>

#include "mbsc/runtime/assemble.hpp"
#include "test_support.hpp"
#include "three_rrr/three_rrr.hpp"
#include "three_rrr_mult/three_rrr_mult.hpp"
#include "three_rrr_platform/three_rrr_platform.hpp"
#include "whitworth/whitworth.hpp"
#include "whitworth_mult/whitworth_mult.hpp"

using mbsc::runtime::AssemblyModel;
using mbsc_test::index_of;

namespace {

using Fn = int (*)(double, const double*, const double*, const double*, double*);

void same_accelerations(Fn complement, Fn multipliers, const std::vector<double>& x, const double* u, const double* p_c,
                        int np, int nx) {
  std::vector<double> pm(p_c, p_c + np);
  pm.push_back(10.0);
  pm.push_back(10.0);
  std::vector<double> a(static_cast<std::size_t>(nx)), b(static_cast<std::size_t>(nx));
  REQUIRE(complement(0.0, x.data(), u, p_c, a.data()) == 0);
  REQUIRE(multipliers(0.0, x.data(), u, pm.data(), b.data()) == 0);
  double scale = 1.0;
  for (double e : a) scale = std::max(scale, std::abs(e));
  for (int i = 0; i < nx; ++i) CHECK(std::abs(a[static_cast<std::size_t>(i)] - b[static_cast<std::size_t>(i)]) < 1e-9 * scale);
}

}  // namespace

TEST_CASE("Whitworth: assembly from the crank angle gives the thesis's configuration", "[numeric][shipped]") {
  namespace W = mbsc_gen::whitworth;
  REQUIRE(W::kNdof == 1);  // Gruebler: 3 (5 - 1) - 2 * 5 - 1 (pin in slot) = 1
  const auto model = MBSC_TEST_ASSEMBLY_MODEL(W);
  auto ix = [](const char* n) { return static_cast<std::size_t>(index_of(W::kStateNames, W::kNx, n)); };
  std::vector<double> x(W::kNx, 0.0);
  // Given: the crank at 45 degrees (pin at (0.1, 0.4)) turning at pi/2 rad/s; rough guesses
  // for the rest (the thesis's values, rounded).
  x[ix("crank.theta")] = M_PI / 4;
  x[ix("crank.w")] = M_PI / 2;
  x[ix("slider.x")] = 0.7;
  x[ix("slider.y")] = 0.8;
  x[ix("rocker.theta")] = 1.3;
  x[ix("rocker.x")] = 0.1;
  x[ix("rocker.y")] = 0.3;
  x[ix("rod.theta")] = 3.4;
  x[ix("rod.x")] = 0.5;
  x[ix("rod.y")] = 0.7;
  x[ix("crank.y")] = 0.3;
  std::vector<bool> gq(W::kNq, false), gu(W::kNu, false);
  gq[ix("crank.theta")] = true;
  gu[ix("crank.w") - W::kNq] = true;
  const double u[1] = {0.02};
  const auto r = mbsc::runtime::assemble(model, 0.0, x, gq, gu, u, W::kParamDefaults);
  INFO(r.message);
  REQUIRE(r.ok());
  CHECK(x[ix("slider.x")] == Approx(0.8).margin(1e-9));
  CHECK(x[ix("slider.y")] == Approx(0.8).margin(1e-12));
  CHECK(x[ix("rocker.theta")] == Approx(std::atan2(0.6, 0.15)).margin(1e-9));
  CHECK(x[ix("crank.x")] == Approx(0.0).margin(1e-12));
  CHECK(x[ix("crank.y")] == Approx(0.3).margin(1e-12));
  same_accelerations(W::rhs, mbsc_gen::whitworth_mult::rhs, x, u, W::kParamDefaults, W::kNp, W::kNx);
}

TEST_CASE("3RRR: assembly from the platform pose gives the thesis's elbows", "[numeric][shipped]") {
  namespace R = mbsc_gen::three_rrr;
  REQUIRE(R::kNdof == 3);  // Gruebler: 3 (8 - 1) - 2 * 9 = 3
  const auto model = MBSC_TEST_ASSEMBLY_MODEL(R);
  auto ix = [](const char* n) { return static_cast<std::size_t>(index_of(R::kStateNames, R::kNx, n)); };
  std::vector<double> x(R::kNx, 0.0);
  // Given: the platform at the origin, not turned, moving (the thesis's prescribed motion
  // at t = 0: x' = -pi/2, y' = pi/4); rough guesses for the legs.
  std::vector<bool> gq(R::kNq, false), gu(R::kNu, false);
  for (const char* n : {"platform.x", "platform.y", "platform.theta"}) gq[ix(n)] = true;
  x[ix("platform.u")] = -M_PI / 2;
  x[ix("platform.v")] = M_PI / 4;
  for (const char* n : {"platform.u", "platform.v", "platform.w"}) gu[ix(n) - R::kNq] = true;
  const double guess_prox[3] = {2.0, 3.8, 6.0}, guess_dist[3] = {1.0, 3.1, 5.2};
  const char* legs[3] = {"HA", "HB", "HC"};
  const double bx[3] = {3.0, -1.5, -1.5}, by[3] = {0.0, 1.5 * std::sqrt(3.0), -1.5 * std::sqrt(3.0)};
  for (int k = 0; k < 3; ++k) {
    const std::string L = legs[k];
    x[ix((L + ".proximal.theta").c_str())] = guess_prox[k];
    x[ix((L + ".proximal.x").c_str())] = bx[k];
    x[ix((L + ".proximal.y").c_str())] = by[k];
    x[ix((L + ".distal.theta").c_str())] = guess_dist[k];
  }
  const double u[3] = {0.1, -0.2, 0.3};
  const auto r = mbsc::runtime::assemble(model, 0.0, x, gq, gu, u, R::kParamDefaults);
  INFO(r.message);
  REQUIRE(r.ok());
  // The thesis's elbows: (2, sqrt3), (-5/2, sqrt3/2), (1/2, -3 sqrt3/2).
  const double ex[3] = {2.0, -2.5, 0.5}, ey[3] = {std::sqrt(3.0), std::sqrt(3.0) / 2, -1.5 * std::sqrt(3.0)};
  for (int k = 0; k < 3; ++k) {
    const std::string L = legs[k];
    const double th = x[ix((L + ".proximal.theta").c_str())];
    CHECK(bx[k] + 2 * std::cos(th) == Approx(ex[k]).margin(1e-9));
    CHECK(by[k] + 2 * std::sin(th) == Approx(ey[k]).margin(1e-9));
  }
  same_accelerations(R::rhs, mbsc_gen::three_rrr_mult::rhs, x, u, R::kParamDefaults, R::kNp, R::kNx);

  // The platform partition (tests/data/planar/three_rrr_platform.mbs, the same model
  // with one `alternative`): the same state derivative, its block split per leg.
  namespace P = mbsc_gen::three_rrr_platform;
  REQUIRE(P::kNpartitions == 2);
  REQUIRE(P::kNx == R::kNx);
  CHECK(std::string(P::kPartitionNames[1]) == "platform.u, platform.v, platform.w");
  std::vector<double> a(R::kNx), b(R::kNx);
  REQUIRE(R::rhs(0.0, x.data(), u, R::kParamDefaults, a.data()) == 0);
  REQUIRE(P::rhs_partition(1, 0.0, x.data(), u, R::kParamDefaults, b.data()) == 0);
  double scale = 1.0;
  for (double e : a) scale = std::max(scale, std::abs(e));
  for (int i = 0; i < R::kNx; ++i) CHECK(std::abs(a[static_cast<std::size_t>(i)] - b[static_cast<std::size_t>(i)]) < 1e-9 * scale);
  double rc0 = 0.0, rc1 = 0.0;
  REQUIRE(P::conditioning_partition(0, 0.0, x.data(), u, R::kParamDefaults, &rc0) == 0);
  REQUIRE(P::conditioning_partition(1, 0.0, x.data(), u, R::kParamDefaults, &rc1) == 0);
  CHECK(rc0 > 1e-3);
  CHECK(rc1 > 1e-3);
}
