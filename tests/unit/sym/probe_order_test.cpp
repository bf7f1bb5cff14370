// SPDX-License-Identifier: GPL-2.0-or-later
// Probe::eval forms sums and products in an order of the values, not in GiNaC's
// run-dependent order of the terms (src/sym/probe.cpp): rounding depends on the order,
// and the probe's values decide pivots, ranks and partitions. Symbols created in a
// different order reorder GiNaC's terms inside one process.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstring>
#include <vector>

#include "mbsc/sym/probe.hpp"

namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

TEST_CASE("probe: sums and products have the same bits in every term order", "[sym]") {
  // 1 + 1e-16 + 1e-16 - 1 is 0 or 2.2e-16 by the order of the additions.
  const double values[] = {1.0, 1e-16, 1e-16, -1.0, 3.0 / 7.0};
  std::vector<int> order = {0, 1, 2, 3, 4};
  std::vector<double> sums, negated, products;
  const mbsc::model::Model m;
  do {
    std::vector<GiNaC::symbol> s(5);
    for (int i : order) s[static_cast<std::size_t>(i)] = GiNaC::symbol("s" + std::to_string(i));
    mbsc::sym::Probe probe(m, {});
    for (int i = 0; i < 5; ++i) probe.bind(s[static_cast<std::size_t>(i)], values[i]);
    GiNaC::ex sum = 0, product = 1;
    for (int i : order) sum += s[static_cast<std::size_t>(i)];
    for (int i : order) product *= 1 + s[static_cast<std::size_t>(i)] / 3;
    sums.push_back(probe.eval(sum));
    negated.push_back(probe.eval(-sum));
    products.push_back(probe.eval(product));
  } while (std::next_permutation(order.begin(), order.end()));
  for (std::size_t i = 0; i < sums.size(); ++i) {
    CHECK(same_bits(sums[i], sums.front()));
    CHECK(same_bits(negated[i], -sums.front()));  // a sum GiNaC holds negated: exactly the negation
    CHECK(same_bits(products[i], products.front()));
  }
}
