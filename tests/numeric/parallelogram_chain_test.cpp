// SPDX-License-Identifier: GPL-2.0-or-later
// The chain of N parallelogram four-bars (models/parallelogram_chain.mbs, generated for
// N = 3 and N = 5 from the same file):
//   - sizes and DOF follow Gruebler's count for each N, and the numeric rank of the
//     position Jacobian at a regular configuration gives the same DOF;
//   - flat (every link on the ground line) the Jacobian loses exactly N ranks, the
//     conditioning report is zero for the block the rhs solves, the rhs returns status
//     1, the selector finds no regular partition, and assembly warns;
//   - complement and multipliers agree on accelerations (1e-9) and trajectories (1e-7).
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "chain5/chain5.hpp"
#include "chain_mult/chain_mult.hpp"
#include "mbsc/runtime/assemble.hpp"
#include "mbsc/runtime/least_squares.hpp"
#include "mbsc/runtime/partition_selector.hpp"
#include "mbsc/runtime/rk4.hpp"
#include "parallelogram_chain/parallelogram_chain.hpp"
#include "test_support.hpp"

namespace C3 = mbsc_gen::parallelogram_chain;
namespace CM = mbsc_gen::chain_mult;
using mbsc_test::index_of;

namespace {

/// One generated chain (namespaces cannot be template arguments).
struct Chain {
  using Fn = int (*)(double, const double*, const double*, const double*, double*);
  using PartFn = mbsc::runtime::PartitionFunctions::Fn;
  int kNq, kNu, kNx, kNposc, kNc, kNp, kNdof, kNpartitions;
  const char* const* kStateNames;
  const char* const* kParamNames;
  const double* kParamDefaults;
  Fn position_constraints, velocity_constraints, position_jacobian, rhs;
  PartFn rhs_partition, conditioning_partition;
  mbsc::runtime::AssemblyModel assembly;
};

#define CHAIN_OF(NS)                                                                                                  \
  Chain {                                                                                                             \
    NS::kNq, NS::kNu, NS::kNx, NS::kNposc, NS::kNc, NS::kNp, NS::kNdof, NS::kNpartitions, NS::kStateNames,              \
        NS::kParamNames, NS::kParamDefaults, NS::position_constraints, NS::velocity_constraints, NS::position_jacobian, \
        NS::rhs, NS::rhs_partition, NS::conditioning_partition, MBSC_TEST_ASSEMBLY_MODEL(NS)                            \
  }

/// The parallelogram branch in closed form: every crank at `theta` turning at `w`,
/// couplers level and translating.
std::vector<double> parallelogram(const Chain& NS, int N, double theta, double w) {
  const double L = NS.kParamDefaults[index_of(NS.kParamNames, NS.kNp, "L")];
  const double a = NS.kParamDefaults[index_of(NS.kParamNames, NS.kNp, "a")];
  std::vector<double> x(NS.kNx, 0.0);
  auto set = [&](const std::string& name, double v) { x[static_cast<std::size_t>(index_of(NS.kStateNames, NS.kNx, name))] = v; };
  const double c = std::cos(theta), s = std::sin(theta);
  for (int i = 0; i <= N; ++i) {
    const std::string b = "crank_" + std::to_string(i);
    set(b + ".x", i * L + a / 2 * c);
    set(b + ".y", a / 2 * s);
    set(b + ".theta", theta);
    set(b + ".u", -a / 2 * s * w);
    set(b + ".v", a / 2 * c * w);
    set(b + ".w", w);
  }
  for (int j = 1; j <= N; ++j) {
    const std::string b = "coupler_" + std::to_string(j);
    set(b + ".x", (j - 1) * L + a * c + L / 2);
    set(b + ".y", a * s);
    set(b + ".u", -a * s * w);
    set(b + ".v", a * c * w);
  }
  return x;
}

int position_rank(const Chain& NS, const std::vector<double>& x) {
  std::vector<double> J(static_cast<std::size_t>(NS.kNposc * NS.kNq));
  REQUIRE(NS.position_jacobian(0.0, x.data(), nullptr, NS.kParamDefaults, J.data()) == 0);
  return mbsc::runtime::solve_least_squares(J, std::vector<double>(NS.kNposc, 0.0), NS.kNposc, NS.kNq, 1e-10).rank;
}

void check_chain(const Chain& NS, int N) {
  INFO("N = " << N);
  // Gruebler: 2N + 1 bars (3 coordinates each), 3N + 1 pins (2 constraints each).
  CHECK(NS.kNq == 3 * (2 * N + 1));
  CHECK(NS.kNposc == 2 * (3 * N + 1));
  CHECK(NS.kNdof == 3 * (2 * N + 1) - 2 * (3 * N + 1));
  CHECK(NS.kNdof == 1);

  // Regular configuration: consistent, full rank, DOF = coordinates - rank.
  const auto x = parallelogram(NS, N, 0.7, 1.3);
  std::vector<double> g(NS.kNposc), r(NS.kNc);
  REQUIRE(NS.position_constraints(0.0, x.data(), nullptr, NS.kParamDefaults, g.data()) == 0);
  REQUIRE(NS.velocity_constraints(0.0, x.data(), nullptr, NS.kParamDefaults, r.data()) == 0);
  for (double e : g) CHECK(std::abs(e) < 1e-14);
  for (double e : r) CHECK(std::abs(e) < 1e-14);
  CHECK(NS.kNq - position_rank(NS, x) == NS.kNdof);
  double rc = 0.0;
  REQUIRE(NS.conditioning_partition(0, 0.0, x.data(), nullptr, NS.kParamDefaults, &rc) == 0);
  CHECK(rc > 1e-3);

  // Flat: N ranks lost, the solved block is singular, nothing to switch to.
  const auto flat = parallelogram(NS, N, 0.0, 0.0);
  CHECK(position_rank(NS, flat) == NS.kNposc - N);
  REQUIRE(NS.conditioning_partition(0, 0.0, flat.data(), nullptr, NS.kParamDefaults, &rc) == 0);
  CHECK(rc < 1e-12);
  std::vector<double> xdot(NS.kNx);
  CHECK(NS.rhs(0.0, flat.data(), nullptr, NS.kParamDefaults, xdot.data()) == 1);  // singular, reported
  mbsc::runtime::PartitionSelector sel({NS.kNpartitions, NS.rhs_partition, NS.conditioning_partition});
  CHECK(sel.update(0.0, flat.data(), nullptr, NS.kParamDefaults) == 1);

  // The conditioning falls with the distance to the flat configuration.
  double rc_far = 0.0, rc_near = 0.0;
  const auto far = parallelogram(NS, N, 1e-2, 0.0), near = parallelogram(NS, N, 1e-4, 0.0);
  NS.conditioning_partition(0, 0.0, far.data(), nullptr, NS.kParamDefaults, &rc_far);
  NS.conditioning_partition(0, 0.0, near.data(), nullptr, NS.kParamDefaults, &rc_near);
  CHECK(rc_near < rc_far / 10);

  // Assembly from the first crank's angle: it completes the flat chain and warns.
  auto guess = parallelogram(NS, N, 0.0, 0.0);
  for (std::size_t i = 0; i < guess.size(); ++i) guess[i] += 1e-3 * std::sin(3.0 * i);
  guess[static_cast<std::size_t>(index_of(NS.kStateNames, NS.kNx, "crank_0.theta"))] = 0.0;
  std::vector<bool> gq(NS.kNq, false), gu(NS.kNu, true);
  gq[static_cast<std::size_t>(index_of(NS.kStateNames, NS.kNx, "crank_0.theta"))] = true;
  for (int k = NS.kNq; k < NS.kNx; ++k) guess[static_cast<std::size_t>(k)] = 0.0;
  const auto res = mbsc::runtime::assemble(NS.assembly, 0.0, guess, gq, gu, nullptr, NS.kParamDefaults);
  INFO(res.message);
  // Newton meets a double root there, so it stops a little off the exact flat point:
  // the pivots, not the rank at 1e-12, show it.
  CHECK(res.ok());
  CHECK(res.near_singular);
  CHECK(res.pivot_ratio > 1e7);
  CHECK(res.message.find("near a singular configuration") != std::string::npos);
}

}  // namespace

TEST_CASE("parallelogram chain: Gruebler, rank, and the rank drop when flat (N = 3 and N = 5)", "[numeric][chain]") {
  check_chain(CHAIN_OF(mbsc_gen::parallelogram_chain), 3);
  check_chain(CHAIN_OF(mbsc_gen::chain5), 5);
}

TEST_CASE("parallelogram chain: complement and multipliers agree", "[numeric][chain]") {
  std::vector<double> pm(C3::kParamDefaults, C3::kParamDefaults + C3::kNp);
  pm.push_back(10.0);
  pm.push_back(10.0);
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> angle(-2.8, -0.3), speed(-2.0, 2.0);
  for (int trial = 0; trial < 10; ++trial) {
    const auto x = parallelogram(CHAIN_OF(C3), 3, angle(gen), speed(gen));
    std::vector<double> a(C3::kNx), b(C3::kNx);
    REQUIRE(C3::rhs(0.0, x.data(), nullptr, C3::kParamDefaults, a.data()) == 0);
    REQUIRE(CM::rhs(0.0, x.data(), nullptr, pm.data(), b.data()) == 0);
    double scale = 1.0;
    for (double e : a) scale = std::max(scale, std::abs(e));
    for (int i = 0; i < C3::kNx; ++i) CHECK(std::abs(a[static_cast<std::size_t>(i)] - b[static_cast<std::size_t>(i)]) < 1e-9 * scale);
  }
  // 1 s of swinging below the ground line (never flat), both formulations.
  auto x = parallelogram(CHAIN_OF(C3), 3, -1.0, 0.0), xm = x;
  auto f = [&](double t, const double* s, double* sd) { return C3::rhs(t, s, nullptr, C3::kParamDefaults, sd); };
  auto fm = [&](double t, const double* s, double* sd) { return CM::rhs(t, s, nullptr, pm.data(), sd); };
  double diff = 0.0;
  for (int step = 0; step < 2000; ++step) {
    REQUIRE(mbsc::runtime::rk4_step(f, step * 5e-4, 5e-4, x) == 0);
    REQUIRE(mbsc::runtime::rk4_step(fm, step * 5e-4, 5e-4, xm) == 0);
    for (std::size_t i = 0; i < x.size(); ++i) diff = std::max(diff, std::abs(x[i] - xm[i]));
  }
  CHECK(diff < 1e-7);
  CHECK(x[static_cast<std::size_t>(index_of(C3::kStateNames, C3::kNx, "crank_0.theta"))] < -1.0);  // it swung
}
