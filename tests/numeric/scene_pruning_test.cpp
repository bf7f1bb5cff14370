// SPDX-License-Identifier: GPL-2.0-or-later
// "Only what the scene needs": --outputs keeps only the requested functions and
// --freeze folds a parameter into the code. Both must cut the operation count and
// still agree numerically with the full model.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "double_pendulum/double_pendulum.hpp"
#include "dp_energy_only/dp_energy_only.hpp"
#include "dp_no_gravity/dp_no_gravity.hpp"
#include "mbsc/driver/pipeline.hpp"
#include "test_support.hpp"

namespace DP = mbsc_gen::double_pendulum;
using mbsc_test::index_of;

namespace {

long total_ops(const mbsc::driver::GenerateOptions& opt, std::vector<std::string>* names = nullptr) {
  mbsc::Diagnostics diags;
  auto m = mbsc::driver::load_model(std::string(MBSC_SOURCE_DIR) + "/models/double_pendulum.mbs", diags);
  REQUIRE(m);
  mbsc::sym::Options so;
  so.frozen = opt.frozen;
  auto eom = mbsc::sym::derive(*m, so, diags);
  REQUIRE(eom);
  auto g = mbsc::driver::generate(*m, *eom, opt, diags);
  REQUIRE(g);
  long total = 0;
  for (const auto& f : g->functions) {
    total += f.ops.total();
    if (names) names->push_back(f.name);
  }
  return total;
}

std::vector<double> random_state(std::mt19937& rng) {
  std::uniform_real_distribution<double> d(-2.0, 2.0);
  std::vector<double> x(DP::kNx);
  for (auto& v : x) v = d(rng);
  return x;
}

}  // namespace

TEST_CASE("--freeze g=0 folds gravity away and matches the full model with g = 0", "[numeric][pruning]") {
  mbsc::driver::GenerateOptions full, frozen;
  frozen.frozen["g"] = 0.0;
  const long ops_full = total_ops(full), ops_frozen = total_ops(frozen);
  INFO("ops full " << ops_full << ", frozen " << ops_frozen);
  CHECK(ops_frozen < ops_full);
  namespace F = mbsc_gen::dp_no_gravity;
  REQUIRE(F::kNp == DP::kNp - 1);
  std::vector<double> p_full(DP::kParamDefaults, DP::kParamDefaults + DP::kNp);
  p_full[index_of(DP::kParamNames, DP::kNp, "g")] = 0.0;
  std::mt19937 rng(3);
  for (int k = 0; k < 20; ++k) {
    auto x = random_state(rng);
    std::vector<double> a(DP::kNx), b(DP::kNx);
    REQUIRE(DP::rhs(0.0, x.data(), nullptr, p_full.data(), a.data()) == 0);
    REQUIRE(F::rhs(0.0, x.data(), nullptr, F::kParamDefaults, b.data()) == 0);
    for (int i = 0; i < DP::kNx; ++i) CHECK(b[i] == Approx(a[i]).margin(1e-12).epsilon(1e-12));
  }
}

TEST_CASE("--outputs energy emits the energy alone, with fewer operations, and the same values", "[numeric][pruning]") {
  mbsc::driver::GenerateOptions full, energy_only;
  energy_only.functions = {"energy"};
  std::vector<std::string> names;
  const long ops_full = total_ops(full), ops_energy = total_ops(energy_only, &names);
  CHECK(names == std::vector<std::string>{"energy"});
  CHECK(ops_energy < ops_full);
  namespace E = mbsc_gen::dp_energy_only;
  std::mt19937 rng(4);
  for (int k = 0; k < 20; ++k) {
    auto x = random_state(rng);
    double a[3], b[3];
    REQUIRE(DP::energy(0.0, x.data(), nullptr, DP::kParamDefaults, a) == 0);
    REQUIRE(E::energy(0.0, x.data(), nullptr, E::kParamDefaults, b) == 0);
    for (int i = 0; i < 3; ++i) CHECK(b[i] == Approx(a[i]).epsilon(1e-14));
  }
}
