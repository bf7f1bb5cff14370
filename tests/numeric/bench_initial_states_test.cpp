// SPDX-License-Identifier: GPL-2.0-or-later
// The benchmark's initial states (bench/simbody/initial_states.txt, shared by the Simbody
// peer and `mbsc bench`) against the shipped models: every name is a state of the model,
// the given speeds are exactly its independent speeds, assembly from the given values
// and the guesses succeeds away from singular configurations, keeps the given values,
// lands next to the guesses (so the branch is the one the Simbody peer assembles), and
// the model's rhs integrates from there. The file's reader reports malformed lines.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>
#include <string>

#include "five_bar/five_bar.hpp"
#include "four_bar/four_bar.hpp"
#include "four_bar_toggle/four_bar_toggle.hpp"
#include "initial_states.hpp"
#include "mbsc/runtime/assemble.hpp"
#include "mbsc/runtime/rk4.hpp"
#include "parallelogram_chain/parallelogram_chain.hpp"
#include "slider_crank/slider_crank.hpp"
#include "test_support.hpp"
#include "three_rrr/three_rrr.hpp"
#include "whitworth/whitworth.hpp"

namespace {

const std::string kFile = MBSC_SOURCE_DIR "/bench/simbody/initial_states.txt";

template <class Names>
int find(const Names& names, int n, const std::string& name) {
  for (int i = 0; i < n; ++i)
    if (name == names[i]) return i;
  return -1;
}

template <int Nq, int Nu, int Nx, int Ndof, int Nin, class Model>
void check_model(const char* name, const Model& m, const char* const* state_names, const char* const* dof_names,
                 int (*rhs)(double, const double*, const double*, const double*, double*), const double* p) {
  INFO("model " << name);
  const simbench::InitialState init = simbench::find_initial_state(kFile, name);
  std::vector<double> x(Nx, 0.0);
  std::vector<bool> gq(Nq, false), gu(Nu, false);
  std::set<std::string> given_speeds;
  for (const auto& [n, v] : init.guess) {
    const int i = find(state_names, Nx, n);
    INFO("guess " << n);
    REQUIRE(i >= 0);
    REQUIRE(i < Nq);  // guesses are coordinates
    x[static_cast<std::size_t>(i)] = v;
  }
  for (const auto& [n, v] : init.given) {
    const int i = find(state_names, Nx, n);
    INFO("given " << n);
    REQUIRE(i >= 0);
    x[static_cast<std::size_t>(i)] = v;
    if (i < Nq) gq[static_cast<std::size_t>(i)] = true;
    else gu[static_cast<std::size_t>(i - Nq)] = true, given_speeds.insert(n);
  }
  std::set<std::string> dofs(dof_names, dof_names + Ndof);
  CHECK(given_speeds == dofs);
  const std::vector<double> u(static_cast<std::size_t>(Nin > 0 ? Nin : 1), 0.0);
  const auto r = mbsc::runtime::assemble(m, 0.0, x, gq, gu, u.data(), p);
  INFO(r.message);
  REQUIRE(r.ok());
  CHECK_FALSE(r.near_singular);
  for (const auto& [n, v] : init.given) CHECK(x[static_cast<std::size_t>(find(state_names, Nx, n))] == v);
  for (const auto& [n, v] : init.guess) {
    INFO("guess " << n << " = " << v);
    CHECK(std::fabs(x[static_cast<std::size_t>(find(state_names, Nx, n))] - v) < 0.5);
  }
  // The rhs runs from there (0.5 s of RK4, h = 1e-3: no singular configuration on the way).
  auto f = [&](double t, const double* xs, double* xd) { return rhs(t, xs, u.data(), p, xd); };
  CHECK(mbsc::runtime::rk4_integrate(f, 0.0, 0.5, 500, x, [](double, const std::vector<double>&) {}) == 0);
}

#define CHECK_MODEL(NS)                                                                                        \
  check_model<mbsc_gen::NS::kNq, mbsc_gen::NS::kNu, mbsc_gen::NS::kNx, mbsc_gen::NS::kNdof, mbsc_gen::NS::kNin>( \
      #NS, MBSC_TEST_ASSEMBLY_MODEL(mbsc_gen::NS), mbsc_gen::NS::kStateNames, mbsc_gen::NS::kDofNames,           \
      &mbsc_gen::NS::rhs, mbsc_gen::NS::kParamDefaults)

}  // namespace

TEST_CASE("bench initial states: consistent with every shipped closed-loop model", "[numeric][bench]") {
  CHECK_MODEL(four_bar);
  CHECK_MODEL(four_bar_toggle);
  CHECK_MODEL(slider_crank);
  CHECK_MODEL(five_bar);
  CHECK_MODEL(whitworth);
  CHECK_MODEL(three_rrr);
  CHECK_MODEL(parallelogram_chain);
}

TEST_CASE("bench initial states: the reader names the bad line", "[numeric][bench]") {
  const std::string path = "bench_initial_states_test_bad.txt";
  auto fails_with = [&](const std::string& text, const std::string& what) {
    {
      std::ofstream(path) << "# comment\nfour_bar crank.theta=1 # trailing\n" << text << "\n";
    }
    std::string msg;
    try {
      simbench::read_initial_states(path);
    } catch (const std::exception& e) {
      msg = e.what();
    }
    INFO(msg);
    CHECK(msg.find(path + ":3: ") == 0);
    CHECK(msg.find(what) != std::string::npos);
  };
  fails_with("four_bar crank.theta", "expected name=value or name~value, got 'crank.theta'");
  fails_with("four_bar crank.theta=1x", "'1x' is not a number");
  fails_with("four_bar =1", "expected name=value");
  {
    std::ofstream(path) << "four_bar crank.theta=1.5 crank.w=-2 coupler.theta~0.25\n";
  }
  const auto all = simbench::read_initial_states(path);
  REQUIRE(all.size() == 1);
  CHECK(all[0].given.size() == 2);
  CHECK(all[0].given[1].second == -2.0);
  CHECK(all[0].guess.size() == 1);
  CHECK(all[0].guess[0].first == "coupler.theta");
  CHECK_THROWS_WITH(simbench::find_initial_state(path, "slider_crank"), Catch::Contains("no initial state for model 'slider_crank'"));
  std::remove(path.c_str());
}
