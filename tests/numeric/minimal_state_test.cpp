// SPDX-License-Identifier: GPL-2.0-or-later
// --state minimal against --state full of the same models:
//  - full_state() rebuilds a state that satisfies every velocity constraint and every
//    explicitly solved position constraint (residuals from the full model's functions);
//  - the minimal rhs equals the full rhs at that state (kept coordinate rates, z rates);
//  - RK4 runs in the two states agree (four-bar) and conserve energy (double pendulum).
#include <catch2/catch.hpp>
#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "double_pendulum/double_pendulum.hpp"
#include "dp_min/dp_min.hpp"
#include "four_bar/four_bar.hpp"
#include "four_bar_min/four_bar_min.hpp"
#include "mbsc/runtime/rk4.hpp"
#include "ring_disc/ring_disc.hpp"
#include "ring_disc_min/ring_disc_min.hpp"
#include "test_support.hpp"

using mbsc_test::index_of;

namespace {

/// The pair (minimal, full) of one model, through function pointers.
using Fn = int (*)(double, const double*, const double*, const double*, double*);
struct Pair {
  Fn rhs_min, full_state, velocity_min, rhs_full, position_full, velocity_full;
  const char* const* names_min;
  const char* const* names_full;
  int nx_min, nx_full, nc, nposc, nin;
  const double* params;  // same defaults in both
};

#define MBSC_PAIR(MIN, FULL, POSITION)                                                                              \
  Pair {                                                                                                            \
    MIN::rhs, MIN::full_state, MIN::velocity_constraints, FULL::rhs, POSITION,                                     \
        FULL::velocity_constraints, MIN::kStateNames, FULL::kStateNames, MIN::kNx, FULL::kNx, FULL::kNc, FULL::kNposc, \
        FULL::kNin, FULL::kParamDefaults                                                                              \
  }

double inf_norm(const std::vector<double>& v) {
  double m = 0.0;
  for (double e : v) m = std::max(m, std::abs(e));
  return m;
}

/// At x_min: the rebuilt full state is velocity-consistent and both rhs agree.
/// Returns the full state. `explicit_rows` are the position constraints solved explicitly.
std::vector<double> compare_at(const Pair& p, const std::vector<double>& x_min, const std::vector<int>& explicit_rows) {
  std::vector<double> u(std::max(1, p.nin), 0.0), x_full(p.nx_full), r(p.nc), rp(std::max(1, p.nposc));
  REQUIRE(p.full_state(0.0, x_min.data(), u.data(), p.params, x_full.data()) == 0);
  for (int i = 0; i < p.nx_min; ++i)
    CHECK(x_full[index_of(p.names_full, p.nx_full, p.names_min[i])] == x_min[static_cast<std::size_t>(i)]);
  REQUIRE(p.velocity_full(0.0, x_full.data(), u.data(), p.params, r.data()) == 0);
  CHECK(inf_norm(r) < 1e-12 * std::max(1.0, inf_norm(x_full)));
  std::vector<double> rv_min(p.nc);
  REQUIRE(p.velocity_min(0.0, x_min.data(), u.data(), p.params, rv_min.data()) == 0);
  CHECK(inf_norm(rv_min) < 1e-12 * std::max(1.0, inf_norm(x_full)));
  if (p.nposc > 0) {
    REQUIRE(p.position_full(0.0, x_full.data(), u.data(), p.params, rp.data()) == 0);
    for (int k : explicit_rows) CHECK(std::abs(rp[static_cast<std::size_t>(k)]) < 1e-13);
  }
  std::vector<double> xd_min(p.nx_min), xd_full(p.nx_full);
  REQUIRE(p.rhs_min(0.0, x_min.data(), u.data(), p.params, xd_min.data()) == 0);
  REQUIRE(p.rhs_full(0.0, x_full.data(), u.data(), p.params, xd_full.data()) == 0);
  const double scale = std::max(1.0, inf_norm(xd_full));
  for (int i = 0; i < p.nx_min; ++i)
    CHECK(std::abs(xd_min[static_cast<std::size_t>(i)] - xd_full[index_of(p.names_full, p.nx_full, p.names_min[i])]) <
          1e-10 * scale);
  return x_full;
}

}  // namespace

TEST_CASE("minimal state: double pendulum is (angles, rates), agrees with the full state, conserves energy",
          "[numeric][minimal_state]") {
  namespace M = mbsc_gen::dp_min;
  namespace F = mbsc_gen::double_pendulum;
  REQUIRE(M::kNx == 4);
  REQUIRE(M::kNxFull == F::kNx);
  const Pair p = MBSC_PAIR(M, F, F::position_constraints);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> angle(-3.0, 3.0), rate(-4.0, 4.0);
  for (int k = 0; k < 30; ++k) {
    std::vector<double> x(M::kNx);
    for (int i = 0; i < 2; ++i) x[static_cast<std::size_t>(i)] = angle(rng);
    for (int i = 2; i < 4; ++i) x[static_cast<std::size_t>(i)] = rate(rng);
    compare_at(p, x, {0, 1, 2, 3});
  }
  // Energy along a fine RK4 run in the minimal state (the full state's test: 1e-9).
  std::vector<double> x = {2.0, -1.0, 0.0, 0.5}, E(3);
  auto f = [](double t, const double* xs, double* xd) { return M::rhs(t, xs, nullptr, M::kParamDefaults, xd); };
  REQUIRE(M::energy(0.0, x.data(), nullptr, M::kParamDefaults, E.data()) == 0);
  const double E0 = E[2];
  double worst = 0.0;
  REQUIRE(mbsc::runtime::rk4_integrate(f, 0.0, 10.0, 40000, x, [&](double t, const std::vector<double>& xs) {
            M::energy(t, xs.data(), nullptr, M::kParamDefaults, E.data());
            worst = std::max(worst, std::abs(E[2] - E0));
          }) == 0);
  CHECK(worst / std::abs(E0) < 1e-9);
}

TEST_CASE("minimal state: four-bar keeps the loop angles, solves the speeds numerically, same motion",
          "[numeric][minimal_state]") {
  namespace M = mbsc_gen::four_bar_min;
  namespace F = mbsc_gen::four_bar;
  const Pair p = MBSC_PAIR(M, F, F::position_constraints);
  REQUIRE(M::kNu == 1);
  // Close the loop: Newton on the minimal model's position residuals over every kept
  // coordinate but the crank angle (finite-difference Jacobian, least squares).
  const int crank = index_of(M::kStateNames, M::kNx, "crank.theta");
  std::vector<double> x(M::kNx, 0.0), r(M::kNposc), rp(M::kNposc), rm(M::kNposc);
  x[static_cast<std::size_t>(crank)] = 1.2;
  x[static_cast<std::size_t>(index_of(M::kStateNames, M::kNx, "coupler.theta"))] = 0.4;
  x[static_cast<std::size_t>(index_of(M::kStateNames, M::kNx, "rocker.theta"))] = 1.9;
  x[static_cast<std::size_t>(index_of(M::kStateNames, M::kNx, "crank.w"))] = 2.0;
  for (int it = 0; it < 50; ++it) {
    REQUIRE(M::position_constraints(0.0, x.data(), nullptr, M::kParamDefaults, r.data()) == 0);
    if (inf_norm(r) < 1e-14) break;
    Eigen::MatrixXd J(M::kNposc, M::kNq - 1);
    std::vector<int> cols;
    for (int i = 0; i < M::kNq; ++i)
      if (i != crank) cols.push_back(i);
    for (std::size_t c = 0; c < cols.size(); ++c) {
      std::vector<double> xp = x, xm = x;
      xp[static_cast<std::size_t>(cols[c])] += 1e-7;
      xm[static_cast<std::size_t>(cols[c])] -= 1e-7;
      M::position_constraints(0.0, xp.data(), nullptr, M::kParamDefaults, rp.data());
      M::position_constraints(0.0, xm.data(), nullptr, M::kParamDefaults, rm.data());
      for (int i = 0; i < M::kNposc; ++i) J(i, static_cast<Eigen::Index>(c)) = (rp[static_cast<std::size_t>(i)] - rm[static_cast<std::size_t>(i)]) / 2e-7;
    }
    const Eigen::VectorXd dx = J.colPivHouseholderQr().solve(-Eigen::Map<Eigen::VectorXd>(r.data(), M::kNposc));
    for (std::size_t c = 0; c < cols.size(); ++c) x[static_cast<std::size_t>(cols[c])] += dx(static_cast<Eigen::Index>(c));
  }
  REQUIRE(inf_norm(r) < 1e-13);
  std::vector<int> all_rows;
  for (int k = 0; k < F::kNposc; ++k) all_rows.push_back(k);
  std::vector<double> x_full = compare_at(p, x, all_rows);
  // One second of RK4 in each state: the crank angle agrees.
  auto fmin = [](double t, const double* xs, double* xd) { return M::rhs(t, xs, nullptr, M::kParamDefaults, xd); };
  auto ffull = [](double t, const double* xs, double* xd) { return F::rhs(t, xs, nullptr, F::kParamDefaults, xd); };
  auto ignore = [](double, const std::vector<double>&) {};
  REQUIRE(mbsc::runtime::rk4_integrate(fmin, 0.0, 1.0, 4000, x, ignore) == 0);
  REQUIRE(mbsc::runtime::rk4_integrate(ffull, 0.0, 1.0, 4000, x_full, ignore) == 0);
  const double a = x[static_cast<std::size_t>(crank)], b = x_full[index_of(F::kStateNames, F::kNx, "crank.theta")];
  CHECK(std::abs(a - b) < 1e-8);
  // Random consistent states along the way: same rhs.
  for (int step = 0; step < 5; ++step) {
    REQUIRE(mbsc::runtime::rk4_integrate(fmin, 0.0, 0.1, 400, x, ignore) == 0);
    compare_at(p, x, {});
  }
}

TEST_CASE("minimal state: ring and disc keep every coordinate (nonholonomic), speeds rebuilt", "[numeric][minimal_state]") {
  namespace M = mbsc_gen::ring_disc_min;
  namespace F = mbsc_gen::ring_disc;
  const Pair p = MBSC_PAIR(M, F, nullptr);  // no position constraints
  REQUIRE(M::kNq == F::kNq);
  REQUIRE(M::kNu == F::kNdof);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> val(-1.0, 1.0);
  for (int k = 0; k < 20; ++k) {
    std::vector<double> x(M::kNx);
    for (double& e : x) e = val(rng);
    compare_at(p, x, {});
  }
}
