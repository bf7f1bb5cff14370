// SPDX-License-Identifier: GPL-2.0-or-later
// mass_matrix formed in the generated code from the factors of M = C^T My C
// (--mass-matrix factors, what auto picks for long chains) against the symbolic form of
// the same model (--mass-matrix symbolic: every entry simplified and shared), entry by
// entry at random states: the N = 40 pendulum chain (minimal state; also against its
// closed form in long double), and shipped models with numeric solves, a minimal state,
// a 3-D body and the multipliers formulation.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "chain40_mm_factors/chain40_mm_factors.hpp"
#include "chain40_mm_symbolic/chain40_mm_symbolic.hpp"
#include "dp_mult_mm_factors/dp_mult_mm_factors.hpp"
#include "dp_mult_mm_symbolic/dp_mult_mm_symbolic.hpp"
#include "four_bar_mm_factors/four_bar_mm_factors.hpp"
#include "four_bar_mm_symbolic/four_bar_mm_symbolic.hpp"
#include "four_bar_min_mm_factors/four_bar_min_mm_factors.hpp"
#include "four_bar_min_mm_symbolic/four_bar_min_mm_symbolic.hpp"
#include "whipple_mm_factors/whipple_mm_factors.hpp"
#include "whipple_mm_symbolic/whipple_mm_symbolic.hpp"

namespace {

using MassFn = int (*)(double, const double*, const double*, const double*, double*);

struct Agreement {
  int evaluated = 0;      // states where both returned 0
  double worst = 0.0;     // max |Mf - Ms| / max |Ms| over those states
  bool symmetric = true;  // Mf exactly symmetric at every state
};

// Both forms at `trials` random states (x in [-1.5, 1.5], the default parameters).
Agreement compare(MassFn factors, MassFn symbolic, int nx, int nd, const double* defaults, int np, int trials) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> val(-1.5, 1.5);
  const std::vector<double> p(defaults, defaults + np);
  const std::vector<double> u(64, 0.0);  // more than any of these models has inputs
  Agreement out;
  for (int trial = 0; trial < trials; ++trial) {
    std::vector<double> x(static_cast<std::size_t>(nx)), mf(static_cast<std::size_t>(nd * nd)), ms(mf.size());
    for (auto& v : x) v = val(rng);
    const int rf = factors(0.0, x.data(), u.data(), p.data(), mf.data());
    const int rs = symbolic(0.0, x.data(), u.data(), p.data(), ms.data());
    CHECK(rf == rs);
    if (rf != 0 || rs != 0) continue;
    ++out.evaluated;
    double scale = 0.0, err = 0.0;
    for (std::size_t k = 0; k < ms.size(); ++k) {
      scale = std::max(scale, std::fabs(ms[k]));
      err = std::max(err, std::fabs(mf[k] - ms[k]));
    }
    out.worst = std::max(out.worst, err / scale);
    for (int a = 0; a < nd; ++a)
      for (int b = 0; b < nd; ++b)
        out.symmetric = out.symmetric && mf[static_cast<std::size_t>(a * nd + b)] == mf[static_cast<std::size_t>(b * nd + a)];
  }
  return out;
}

int index_of(const char* const* names, int n, const std::string& name) {
  for (int i = 0; i < n; ++i)
    if (name == names[i]) return i;
  FAIL("no state named " << name);
  return -1;
}

}  // namespace

TEST_CASE("mass_matrix from its factors: the N = 40 chain against the symbolic form and the closed form",
          "[mass_matrix_factors]") {
  namespace f = mbsc_gen::chain40_mm_factors;
  namespace s = mbsc_gen::chain40_mm_symbolic;
  const Agreement a = compare(f::mass_matrix, s::mass_matrix, f::kNx, f::kNdof, f::kParamDefaults, f::kNp, 50);
  INFO("relative difference " << a.worst);
  CHECK(a.evaluated == 50);
  CHECK(a.worst < 1e-14);
  CHECK(a.symmetric);

  // The closed form m l^2 (N - max(i, j) + 1) cos(th_i - th_j), i, j = 1..N, in long double.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> angle(-3.1, 3.1);
  const int n = 40;
  REQUIRE(f::kNdof == n);
  const std::vector<double> p(f::kParamDefaults, f::kParamDefaults + f::kNp);
  const double m = p[static_cast<std::size_t>(index_of(f::kParamNames, f::kNp, "m"))];
  const double l = p[static_cast<std::size_t>(index_of(f::kParamNames, f::kNp, "l"))];
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<double> x(static_cast<std::size_t>(f::kNx), 0.0), th(static_cast<std::size_t>(n)), M(static_cast<std::size_t>(n * n));
    for (int k = 0; k < n; ++k) {
      th[static_cast<std::size_t>(k)] = angle(rng);
      x[static_cast<std::size_t>(index_of(f::kStateNames, f::kNx, "th_" + std::to_string(k + 1)))] = th[static_cast<std::size_t>(k)];
    }
    REQUIRE(f::mass_matrix(0.0, x.data(), nullptr, p.data(), M.data()) == 0);
    long double err = 0;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        // Rows and columns follow kDofNames (w_1 .. w_N).
        const int a = index_of(f::kDofNames, n, "w_" + std::to_string(i + 1));
        const int b = index_of(f::kDofNames, n, "w_" + std::to_string(j + 1));
        const long double ref = static_cast<long double>(m) * l * l * static_cast<long double>(n - std::max(i, j)) *
                                std::cos(static_cast<long double>(th[static_cast<std::size_t>(i)]) - th[static_cast<std::size_t>(j)]);
        err = std::max(err, std::fabs(static_cast<long double>(M[static_cast<std::size_t>(a * n + b)]) - ref));
      }
    CHECK(static_cast<double>(err) < 1e-13 * m * l * l * n);
  }
}

TEST_CASE("mass_matrix from its factors equals the symbolic form on shipped models", "[mass_matrix_factors]") {
  SECTION("four_bar (numeric dependent block)") {
    namespace f = mbsc_gen::four_bar_mm_factors;
    namespace s = mbsc_gen::four_bar_mm_symbolic;
    const Agreement a = compare(f::mass_matrix, s::mass_matrix, f::kNx, f::kNdof, f::kParamDefaults, f::kNp, 100);
    INFO("relative difference " << a.worst);
    CHECK(a.evaluated > 90);
    CHECK(a.worst < 1e-14);
    CHECK(a.symmetric);
  }
  SECTION("four_bar, --state minimal") {
    namespace f = mbsc_gen::four_bar_min_mm_factors;
    namespace s = mbsc_gen::four_bar_min_mm_symbolic;
    const Agreement a = compare(f::mass_matrix, s::mass_matrix, f::kNx, f::kNdof, f::kParamDefaults, f::kNp, 100);
    INFO("relative difference " << a.worst);
    CHECK(a.evaluated > 90);
    CHECK(a.worst < 1e-14);
    CHECK(a.symmetric);
  }
  SECTION("whipple_bicycle (rigid bodies in 3-D, rolling contact)") {
    namespace f = mbsc_gen::whipple_mm_factors;
    namespace s = mbsc_gen::whipple_mm_symbolic;
    const Agreement a = compare(f::mass_matrix, s::mass_matrix, f::kNx, f::kNdof, f::kParamDefaults, f::kNp, 100);
    INFO("relative difference " << a.worst);
    CHECK(a.evaluated > 90);
    CHECK(a.worst < 1e-14);
    CHECK(a.symmetric);
  }
  SECTION("double_pendulum, --formulation multipliers (the common ABI's reduced M)") {
    namespace f = mbsc_gen::dp_mult_mm_factors;
    namespace s = mbsc_gen::dp_mult_mm_symbolic;
    const Agreement a = compare(f::mass_matrix, s::mass_matrix, f::kNx, f::kNdof, f::kParamDefaults, f::kNp, 100);
    INFO("relative difference " << a.worst);
    CHECK(a.evaluated == 100);
    CHECK(a.worst < 1e-14);
    CHECK(a.symmetric);
  }
}
