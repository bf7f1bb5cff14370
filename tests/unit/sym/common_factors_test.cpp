// SPDX-License-Identifier: GPL-2.0-or-later
// sym::common_factors (src/sym/common_factors.cpp): what it pulls out, that it keeps the
// value, and that what it does inside a sum does not hang on the whole sum (GiNaC's
// collect_common_factors, which it replaces, decides that by its run-dependent term
// order: docs/backend.md "Determinism"; tests/cli/determinism_test.cpp runs whole models
// in separate processes).
#include <catch2/catch.hpp>

#include "mbsc/sym/common_factors.hpp"

using namespace GiNaC;
using mbsc::sym::common_factors;

TEST_CASE("common factors: what is pulled out", "[sym]") {
  symbol x("x"), a("a"), b("b"), c("c");
  // Monomials, rational content, the smallest power, a sum and its negation as one factor.
  CHECK(common_factors(2 * x * a + 4 * x * b).is_equal(2 * x * (a + 2 * b)));
  CHECK(common_factors(x * a / 2 + x * b / 3).is_equal(x * (3 * a + 2 * b) / 6));
  CHECK(common_factors(pow(x, 2) * a + pow(x, 3) * b).is_equal(pow(x, 2) * (a + x * b)));
  CHECK(common_factors((x - a) * b + (a - x) * c).is_equal((x - a) * (b - c)));
  CHECK(common_factors(pow(x - a, 3) * b + pow(a - x, 2) * c).is_equal(pow(x - a, 2) * (c + (x - a) * b)));
  // Nothing common: the sum as it was; inner sums are collected first.
  CHECK(common_factors(x * a + b).is_equal(x * a + b));
  CHECK(common_factors(sin(x * a + x * b) + c).is_equal(sin(x * (a + b)) + c));
  // Floating-point coefficients give no content.
  CHECK(common_factors(0.5 * x * a + x * b).is_equal(x * (0.5 * a + b)));
}

TEST_CASE("common factors: the value is kept", "[sym]") {
  symbol x("x"), y("y"), a("a"), b("b");
  for (const ex& e : {ex(x * a * (y + 1) + x * b * (y + 1) + x), pow(a + b, 2) * x - (a + b) * y,
                      cos(y) * (a - b) * x - (b - a) * (cos(y) - 1) * x, ex(numeric(3, 4) * a * b - numeric(9, 8) * b * x)})
    CHECK((common_factors(e) - e).expand().is_zero());
}

TEST_CASE("common factors: inner sums are collected whatever the whole sum has", "[sym]") {
  // The flyball governor's rate, A*(cos(p) - (cos(p) - 1))*w + B*(...)*d^2 with A, B sums:
  // the whole sum has no common factor, each inner one has A or B. GiNaC's function gave
  // up on the inner ones when its gcd of the whole came out as 1 rather than -1, by its
  // term order (about a third of the processes): here they are always collected.
  symbol p("p"), a1("a1"), w("w"), d("d");
  const ex A = cos(a1) - 10 * sin(a1), B = 10 * cos(a1) + sin(a1);
  const ex e = numeric(-1, 10) * (cos(p) * A - (cos(p) - 1) * A) * w + numeric(1, 10) * d * d * (cos(p) * B - (cos(p) - 1) * B);
  CHECK(common_factors(e).is_equal(numeric(-1, 10) * A * w + numeric(1, 10) * B * d * d));
}
