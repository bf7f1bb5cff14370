// SPDX-License-Identifier: GPL-2.0-or-later
// The one-pass derivatives (sym/linear_gradient.hpp, sym/symbol_set.hpp) against GiNaC's
// own diff, symbol by symbol: the same expressions (is_equal), so the generated code
// cannot change, on random sums linear in the symbols, sums with terms of other shapes
// (which fall back to diff) and expressions that are not sums.
#include <catch2/catch.hpp>

#include <random>

#include "mbsc/sym/linear_gradient.hpp"
#include "mbsc/sym/symbol_set.hpp"

namespace {

void check_against_diff(const GiNaC::ex& e, const std::vector<GiNaC::symbol>& by) {
  const auto g = mbsc::sym::linear_gradient(e, by);
  REQUIRE(g.size() == by.size());
  const mbsc::sym::SymbolSet in_e(e);
  for (std::size_t j = 0; j < by.size(); ++j) {
    INFO(e << " by " << by[j]);
    CHECK(g[j].is_equal(e.diff(by[j])));
    CHECK(in_e.diff(e, by[j]).is_equal(e.diff(by[j])));
    CHECK(in_e.contains(by[j]) == e.has(by[j]));
  }
}

}  // namespace

TEST_CASE("linear_gradient equals diff on random linear sums and on other shapes", "[sym][scale]") {
  std::mt19937 rng(7);
  std::vector<GiNaC::symbol> u, q;
  for (int k = 0; k < 12; ++k) {
    u.emplace_back("ud" + std::to_string(k));
    q.emplace_back("q" + std::to_string(k));
  }
  const GiNaC::symbol l("l"), m("m");
  auto pick = [&](int n) { return static_cast<std::size_t>(std::uniform_int_distribution<int>(0, n - 1)(rng)); };
  for (int trial = 0; trial < 200; ++trial) {
    // A dependent rate of a chain: sum_k c_k(q, l) ud_k + terms without ud.
    GiNaC::ex e = 0;
    const int terms = 1 + static_cast<int>(pick(10));
    for (int t = 0; t < terms; ++t) {
      GiNaC::ex c;
      switch (pick(5)) {
        case 0: c = l * GiNaC::sin(q[pick(12)]); break;
        case 1: c = -GiNaC::cos(q[pick(12)]) * GiNaC::sin(q[pick(12)]) / m; break;
        case 2: c = GiNaC::numeric(static_cast<int>(pick(7)) - 3, 2); break;
        case 3: c = GiNaC::pow(l, 2) + m; break;
        default: c = 3 * l; break;
      }
      e += pick(6) == 0 ? c : c * u[pick(12)];
    }
    if (trial % 4 == 1) e += u[pick(12)] * u[pick(12)];                 // a square or a product
    if (trial % 4 == 2) e += GiNaC::sin(u[pick(12)]) * l;                // inside a function
    if (trial % 4 == 3) e += (u[pick(12)] + u[pick(12)] * l) * q[pick(12)];  // a nested sum
    check_against_diff(e, u);
  }
  // Not a sum: a single term, a number, a symbol.
  check_against_diff(l * GiNaC::cos(q[0]) * u[3], u);
  check_against_diff(GiNaC::ex(5), u);
  check_against_diff(u[2], u);
  check_against_diff(GiNaC::ex(0), {});
}
