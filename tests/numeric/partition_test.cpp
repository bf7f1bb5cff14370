// SPDX-License-Identifier: GPL-2.0-or-later
// Run-time re-selection of the independent set on a four-bar that runs through toggle
// positions (models/four_bar_toggle.mbs, a non-Grashof linkage with three declared
// partitions: crank.w, rocker.w, coupler.w independent).
//   - every partition's rhs gives the same state derivative where its block is regular;
//   - at the crank's toggle (coupler and rocker collinear, built in closed form) the
//     crank partition's block is singular and the conditioning report says so, while
//     the multipliers formulation (no partition) still works and the selector's choice
//     agrees with it;
//   - a run along the whole closed path (no gravity: constant kinetic energy) passes
//     both links' toggles with the selector, keeps energy and closure, and follows the
//     multipliers formulation's trajectory.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "four_bar_toggle/four_bar_toggle.hpp"
#include "four_bar_toggle_mult/four_bar_toggle_mult.hpp"
#include "mbsc/runtime/assemble.hpp"
#include "mbsc/runtime/partition_selector.hpp"
#include "mbsc/runtime/rk4.hpp"
#include "test_support.hpp"

namespace F = mbsc_gen::four_bar_toggle;
namespace FM = mbsc_gen::four_bar_toggle_mult;
using mbsc_test::index_of;

namespace {

std::size_t ix(const char* name) { return static_cast<std::size_t>(index_of(F::kStateNames, F::kNx, name)); }

double p_of(const char* name) { return F::kParamDefaults[index_of(F::kParamNames, F::kNp, name)]; }

/// A consistent state with the crank at `theta` turning at `w`: pin B where the circles
/// about A (radius b) and Q (radius c) meet (the branch `side` = +1 or -1), then the
/// assembly completes the speeds and polishes the coordinates.
std::vector<double> state_at(double theta, double w, int side) {
  std::vector<double> x(F::kNx, 0.0);
  const double a = p_of("a"), b = p_of("b"), c = p_of("c"), d = p_of("d");
  const double ax = a * std::cos(theta), ay = a * std::sin(theta);
  const double ex = d - ax, ey = -ay, dist = std::hypot(ex, ey);  // A -> Q
  const double along = (dist * dist + b * b - c * c) / (2 * dist), across = std::sqrt(std::max(0.0, b * b - along * along));
  const double bx = ax + (along * ex - side * across * ey) / dist, by = ay + (along * ey + side * across * ex) / dist;
  x[ix("crank.theta")] = theta;
  x[ix("crank.x")] = ax / 2;
  x[ix("crank.y")] = ay / 2;
  x[ix("coupler.theta")] = std::atan2(by - ay, bx - ax);
  x[ix("coupler.x")] = (ax + bx) / 2;
  x[ix("coupler.y")] = (ay + by) / 2;
  x[ix("rocker.theta")] = std::atan2(by, bx - d);
  x[ix("rocker.x")] = (d + bx) / 2;
  x[ix("rocker.y")] = by / 2;
  x[ix("crank.w")] = w;
  std::vector<bool> gq(F::kNq, false), gu(F::kNu, false);
  gq[ix("crank.theta")] = true;
  gu[ix("crank.w") - F::kNq] = true;
  const auto r = mbsc::runtime::assemble(MBSC_TEST_ASSEMBLY_MODEL(F), 0.0, x, gq, gu, nullptr, F::kParamDefaults);
  INFO("crank at " << theta << ": " << r.message);
  REQUIRE(r.ok());
  return x;
}

/// The crank's toggle in closed form: the crank at its limit angle, coupler and rocker
/// collinear and stretched (|AQ| = b + c), every speed zero but a consistent crank-free
/// motion is impossible there, so the speeds are a multiple of the null space: zero.
std::vector<double> crank_toggle() {
  const double a = p_of("a"), b = p_of("b"), c = p_of("c"), d = p_of("d");
  const double theta = std::acos((a * a + d * d - (b + c) * (b + c)) / (2 * a * d));
  const double ax = a * std::cos(theta), ay = a * std::sin(theta);
  const double phi = std::atan2(-ay, d - ax);  // direction A -> Q
  std::vector<double> x(F::kNx, 0.0);
  x[ix("crank.theta")] = theta;
  x[ix("crank.x")] = ax / 2;
  x[ix("crank.y")] = ay / 2;
  x[ix("coupler.theta")] = phi;
  x[ix("coupler.x")] = ax + b / 2 * std::cos(phi);
  x[ix("coupler.y")] = ay + b / 2 * std::sin(phi);
  x[ix("rocker.theta")] = phi + M_PI;
  x[ix("rocker.x")] = d - c / 2 * std::cos(phi);
  x[ix("rocker.y")] = -c / 2 * std::sin(phi);
  return x;
}

double max_abs(const std::vector<double>& v) {
  double m = 0.0;
  for (double e : v) m = std::max(m, std::abs(e));
  return m;
}

std::vector<double> mult_params(const double* p) {
  std::vector<double> pm(p, p + F::kNp);
  pm.push_back(20.0);  // Baumgarte alpha, beta
  pm.push_back(20.0);
  return pm;
}

}  // namespace

TEST_CASE("four-bar toggle: every partition gives the same state derivative", "[numeric][partition]") {
  REQUIRE(F::kNpartitions == 3);
  CHECK(std::string(F::kPartitionNames[0]) == "crank.w");
  CHECK(std::string(F::kPartitionNames[1]) == "rocker.w");
  CHECK(std::string(F::kPartitionNames[2]) == "coupler.w");
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> angle(-2.0, 2.0), speed(-3.0, 3.0);
  for (int trial = 0; trial < 20; ++trial) {
    const auto x = state_at(angle(gen), speed(gen), trial % 2 ? 1 : -1);
    std::vector<std::vector<double>> xdot(F::kNpartitions, std::vector<double>(F::kNx));
    for (int k = 0; k < F::kNpartitions; ++k) {
      double rc = -1.0;
      REQUIRE(F::conditioning_partition(k, 0.0, x.data(), nullptr, F::kParamDefaults, &rc) == 0);
      CHECK(rc > 0.0);
      CHECK(rc <= 1.0);
      REQUIRE(F::rhs_partition(k, 0.0, x.data(), nullptr, F::kParamDefaults, xdot[static_cast<std::size_t>(k)].data()) == 0);
    }
    const double scale = std::max(1.0, max_abs(xdot[0]));
    for (int k = 1; k < F::kNpartitions; ++k)
      for (int i = 0; i < F::kNx; ++i)
        CHECK(std::abs(xdot[static_cast<std::size_t>(k)][static_cast<std::size_t>(i)] - xdot[0][static_cast<std::size_t>(i)]) <
              1e-9 * scale);
  }
  // Out of range partition numbers are refused, not read past the table.
  std::vector<double> x(F::kNx, 0.0), xd(F::kNx);
  double rc = 0.0;
  CHECK(F::rhs_partition(3, 0.0, x.data(), nullptr, F::kParamDefaults, xd.data()) == 3);
  CHECK(F::conditioning_partition(-1, 0.0, x.data(), nullptr, F::kParamDefaults, &rc) == 3);
}

TEST_CASE("four-bar toggle: the crank partition is singular at the crank's toggle; the selector leaves it",
          "[numeric][partition]") {
  const auto x = crank_toggle();
  std::vector<double> g(F::kNposc);
  REQUIRE(F::position_constraints(0.0, x.data(), nullptr, F::kParamDefaults, g.data()) == 0);
  REQUIRE(max_abs(g) < 1e-14);
  double rc0 = 1.0, rc1 = 0.0;
  REQUIRE(F::conditioning_partition(0, 0.0, x.data(), nullptr, F::kParamDefaults, &rc0) == 0);
  REQUIRE(F::conditioning_partition(1, 0.0, x.data(), nullptr, F::kParamDefaults, &rc1) == 0);
  CHECK(rc0 < 1e-12);
  CHECK(rc1 > 1e-2);
  // `conditioning` reports each solve (the dependent block, then the reduced mass
  // matrix): either the block solve itself fails there (status 1) or its rcond is tiny.
  REQUIRE(F::kNblocks == 2);
  CHECK(std::string(F::kBlockNames[1]) == "reduced mass matrix M z' = h");
  double rc_blocks[2] = {1.0, 1.0};
  const int status = F::conditioning(0.0, x.data(), nullptr, F::kParamDefaults, rc_blocks);
  CHECK((status == 1 || (status == 0 && rc_blocks[0] == rc0)));

  // Slightly off the toggle, with speeds: the selector picks a regular partition whose
  // accelerations match the multipliers formulation's (which has no partition).
  auto near = state_at(std::acos((0.36 + 1.0 - 2.25) / 1.2) - 1e-6, 0.5, 1);
  mbsc::runtime::PartitionSelector sel({F::kNpartitions, &F::rhs_partition, &F::conditioning_partition});
  REQUIRE(sel.update(0.0, near.data(), nullptr, F::kParamDefaults) == 0);
  CHECK(sel.active() != 0);
  CHECK(sel.switches() == 1);
  std::vector<double> a(F::kNx), b(F::kNx);
  REQUIRE(sel.rhs(0.0, near.data(), nullptr, F::kParamDefaults, a.data()) == 0);
  const auto pm = mult_params(F::kParamDefaults);
  REQUIRE(FM::rhs(0.0, near.data(), nullptr, pm.data(), b.data()) == 0);
  for (int i = 0; i < F::kNx; ++i)
    CHECK(std::abs(a[static_cast<std::size_t>(i)] - b[static_cast<std::size_t>(i)]) < 1e-8 * std::max(1.0, max_abs(b)));

  // 1e-9 rad from the limit the crank partition still returns, but loses digits
  // (rounding grows like eps / rcond); the rocker partition keeps them.
  auto closer = state_at(std::acos((0.36 + 1.0 - 2.25) / 1.2) - 1e-9, 0.5, 1);
  std::vector<double> x0(F::kNx), x1(F::kNx), xm(F::kNx);
  REQUIRE(F::rhs_partition(0, 0.0, closer.data(), nullptr, F::kParamDefaults, x0.data()) == 0);
  REQUIRE(F::rhs_partition(1, 0.0, closer.data(), nullptr, F::kParamDefaults, x1.data()) == 0);
  REQUIRE(FM::rhs(0.0, closer.data(), nullptr, pm.data(), xm.data()) == 0);
  double err0 = 0.0, err1 = 0.0;
  for (std::size_t i = 0; i < x0.size(); ++i) {
    err0 = std::max(err0, std::abs(x0[i] - xm[i]));
    err1 = std::max(err1, std::abs(x1[i] - xm[i]));
  }
  INFO("crank partition off by " << err0 << ", rocker partition by " << err1 << " (scale " << max_abs(xm) << ")");
  CHECK(err1 * 100 < err0);
  CHECK(err1 < 1e-12 * max_abs(xm));
}

TEST_CASE("four-bar toggle: a run through both links' toggles with re-selection", "[numeric][partition]") {
  std::vector<double> p(F::kParamDefaults, F::kParamDefaults + F::kNp);
  p[static_cast<std::size_t>(index_of(F::kParamNames, F::kNp, "g"))] = 0.0;  // constant kinetic energy
  auto x = state_at(0.3, 2.0, 1);
  auto xm = x;
  const auto pm = mult_params(p.data());
  double e0[3];
  REQUIRE(F::energy(0.0, x.data(), nullptr, p.data(), e0) == 0);

  mbsc::runtime::PartitionSelector sel({F::kNpartitions, &F::rhs_partition, &F::conditioning_partition});
  auto f = [&](double t, const double* s, double* sd) { return sel.rhs(t, s, nullptr, p.data(), sd); };
  auto fm = [&](double t, const double* s, double* sd) { return FM::rhs(t, s, nullptr, pm.data(), sd); };
  const double h = 5e-4;
  int crank_reversals = 0, rocker_reversals = 0;
  double max_closure = 0.0, max_energy = 0.0, max_diff = 0.0;
  std::vector<double> g(F::kNposc);
  for (int step = 0; step < 6000; ++step) {
    const double t = step * h;
    REQUIRE(sel.update(t, x.data(), nullptr, p.data()) == 0);
    const double w_crank = x[ix("crank.w")], w_rocker = x[ix("rocker.w")];
    REQUIRE(mbsc::runtime::rk4_step(f, t, h, x) == 0);
    REQUIRE(mbsc::runtime::rk4_step(fm, t, h, xm) == 0);
    crank_reversals += (w_crank > 0) != (x[ix("crank.w")] > 0);
    rocker_reversals += (w_rocker > 0) != (x[ix("rocker.w")] > 0);
    REQUIRE(F::position_constraints(0.0, x.data(), nullptr, p.data(), g.data()) == 0);
    max_closure = std::max(max_closure, max_abs(g));
    double e[3];
    REQUIRE(F::energy(0.0, x.data(), nullptr, p.data(), e) == 0);
    max_energy = std::max(max_energy, std::abs(e[2] - e0[2]) / e0[2]);
    max_diff = std::max(max_diff, std::abs(x[ix("crank.theta")] - xm[ix("crank.theta")]));
  }
  INFO("switches " << sel.switches() << ", crank reversals " << crank_reversals << ", rocker reversals "
                   << rocker_reversals << ", closure " << max_closure << ", energy " << max_energy << ", vs multipliers "
                   << max_diff);
  CHECK(crank_reversals >= 2);   // through the crank's toggles (coupler and rocker collinear)
  CHECK(rocker_reversals >= 2);  // through the rocker's (crank and coupler collinear)
  CHECK(sel.switches() >= 2);
  CHECK(max_closure < 1e-8);
  CHECK(max_energy < 1e-8);
  CHECK(max_diff < 1e-6);
}
