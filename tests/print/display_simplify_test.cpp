// SPDX-License-Identifier: GPL-2.0-or-later
// The display simplifier of `mbsc print` on identities. Each case checks the exact text
// (which a pass-through returning its input unchanged would not give: checked too), the
// value at random points and the equality by the half-angle substitution.
#include "mbsc/print/display_simplify.hpp"

#include <catch2/catch.hpp>

#include <random>

#include "mbsc/print/canonical_text.hpp"
#include "mbsc/sym/tidy.hpp"
#include "trig_check.hpp"

using namespace GiNaC;
using mbsc::print::canonical_text;
using mbsc::print::display_simplify;

namespace {

symbol x("x"), y("y"), z("z"), a("a"), b("b"), k("k"), l("l"), m("m"), m1("m1"), m2("m2");

/// The same value as e at random points of its symbols.
void check_same_value(const ex& e, const ex& out) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.3, 1.7);
  for (int trial = 0; trial < 5; ++trial) {
    exmap values;
    for (const symbol& s : {x, y, z, a, b, k, l, m, m1, m2}) values[s] = u(rng);
    const double want = mbsc_test::eval(e, values), got = mbsc_test::eval(out, values);
    CHECK(got == Approx(want).epsilon(1e-12).margin(1e-12));
  }
}

void check_simplifies(const ex& e, const std::string& expected) {
  INFO("input: " << canonical_text(e, false));
  const ex out = display_simplify(e);
  CHECK(canonical_text(out, false) == expected);
  CHECK(canonical_text(e, false) != expected);  // the case tests a rewrite, not a pass-through
  check_same_value(e, out);
  CHECK(mbsc_test::trig_equal(e, out));
}

}  // namespace

TEST_CASE("display_simplify: sin^2 + cos^2 = 1 in every form", "[print][display]") {
  // With common factors, as the 3R arm's and the double pendulum's M held it.
  check_simplifies(a * pow(cos(x), 2) * m + a * pow(sin(x), 2) * m, "a*m");
  check_simplifies((1 + 3 * pow(cos(x - y), 2) + 3 * pow(sin(x - y), 2)) * pow(l, 2) * m / 12, "1/3*l^2*m");
  // In a sum with other terms, and not side by side.
  check_simplifies(pow(sin(x), 2) + y + pow(cos(x), 2), "1 + y");
  check_simplifies(m1 * pow(cos(x), 2) + m2 * pow(sin(x), 2) + m2 * pow(cos(x), 2) + m1 * pow(sin(x), 2), "m1 + m2");
  // Powers of it, also expanded.
  check_simplifies(pow(pow(sin(x), 2) + pow(cos(x), 2), 2) * k, "k");
  check_simplifies(k * pow(cos(x), 4) + 2 * k * pow(cos(x), 2) * pow(sin(x), 2) + k * pow(sin(x), 4), "k");
  // Beside products that folding into sums of angles would only lengthen; in a power
  // too large to expand.
  check_simplifies(sin(2 * x) * cos(3 * y) + pow(sin(z), 2) + pow(cos(z), 2) + a * b, "1 + a*b + cos(3*y)*sin(2*x)");
  check_simplifies(pow(sin(2 * x) * cos(3 * y) + pow(sin(z), 2) + pow(cos(z), 2) + a * b, 9) * k,
                   "(1 + a*b + cos(3*y)*sin(2*x))^9*k");
  // One square for the other: 1 - sin^2 = cos^2.
  check_simplifies(m - m * pow(sin(x), 2), "m*cos(x)^2");
  // Inside the arguments and bases the expansion does not touch.
  check_simplifies(sqrt(pow(l, 2) * pow(cos(x), 2) + pow(l, 2) * pow(sin(x), 2) + a), "(a + l^2)^(1/2)");
  check_simplifies((a * pow(cos(y), 2) + a * pow(sin(y), 2)) / (b * pow(cos(x), 2) + b * pow(sin(x), 2)), "a/b");
}

TEST_CASE("display_simplify: sines and cosines folded into sums and differences of angles", "[print][display]") {
  check_simplifies(cos(x) * cos(y) + sin(x) * sin(y), "cos(x - y)");
  check_simplifies(cos(x) * cos(y) - sin(x) * sin(y), "cos(x + y)");
  check_simplifies(sin(x) * cos(y) - cos(x) * sin(y), "sin(x - y)");
  check_simplifies(sin(x) * cos(y) + cos(x) * sin(y), "sin(x + y)");
  check_simplifies(sin(y) * cos(x) - cos(y) * sin(x), "-sin(x - y)");
  // With factors, as the double pendulum's coupling term.
  check_simplifies((cos(x) * cos(y) + sin(x) * sin(y)) * l * m * a, "a*l*m*cos(x - y)");
  // Three angles.
  check_simplifies(cos(x) * cos(y - z) - sin(x) * sin(y - z), "cos(x + y - z)");
  check_simplifies(2 * k * sin(x) * cos(x), "k*sin(2*x)");
}

TEST_CASE("display_simplify: identities within groups of a sum that is shortest unexpanded", "[print][display]") {
  // The review's reproduction: the square of a rational function of sines and cosines
  // grows when expanded, so the whole was printed as it came, sin^2 + cos^2 included.
  const ex ratio = b * cos(x) * sin(y) / cos(y) - k * sin(x);
  check_simplifies(a * pow(cos(x), 2) + a * pow(sin(x), 2) + pow(ratio, 2), "(b*cos(x)*sin(y)/cos(y) - k*sin(x))^2 + a");
  // The slider-crank's M: terms over the same denominator grouped, the plain ones folded.
  check_simplifies(pow(ratio, 2) * m + m1 * pow(l, 2) * pow(cos(x), 2) / 4 + m1 * pow(l, 2) * pow(sin(x), 2) / 4 +
                       m2 * pow(l, 2) * pow(cos(x), 2) / 4 + a * pow(cos(x), 2) / pow(cos(y), 2),
                   "(b*cos(x)*sin(y)/cos(y) - k*sin(x))^2*m + 1/4*(m1 + m2*cos(x)^2)*l^2 + a*cos(x)^2/cos(y)^2");
  // Whitworth's: a product of sines and cosines inside a term with a denominator,
  // folded to cos(x - y) without expanding the rest.
  check_simplifies(2 * (cos(x) * cos(y) + sin(x) * sin(y)) * a * sin(y) / (a + b * cos(z)) + pow(ratio, 2),
                   "(b*cos(x)*sin(y)/cos(y) - k*sin(x))^2 + 2*a*cos(x - y)*sin(y)/(a + b*cos(z))");
  // Terms sharing a denominator: the identity applies to their numerators together.
  check_simplifies(a * pow(cos(x), 2) / (b + cos(z)) + a * pow(sin(x), 2) / (b + cos(z)) + pow(ratio, 2),
                   "(b*cos(x)*sin(y)/cos(y) - k*sin(x))^2 + a/(b + cos(z))");
}

TEST_CASE("display_simplify: common factors collected", "[print][display]") {
  check_simplifies(m1 * pow(l, 2) + m2 * pow(l, 2), "(m1 + m2)*l^2");
  check_simplifies(m1 * pow(l, 2) / 3 + m2 * pow(l, 2), "(1/3*m1 + m2)*l^2");
  check_simplifies(a * m * sin(x) + a * m1 * sin(x) * pow(cos(y), 2) + a * m1 * sin(x) * pow(sin(y), 2),
                   "(m + m1)*a*sin(x)");
}

TEST_CASE("display_simplify: short forms stay, and the output does not depend on creation order", "[print][display]") {
  // Already the shortest: no double angle, no expansion.
  for (const ex& e : {ex(m * pow(sin(x), 2)), ex((a + b) * cos(x - y)), ex(a / (b + cos(x))), ex(pow(a + b, 3))}) {
    const ex out = display_simplify(e);
    CHECK(canonical_text(out, false).size() <= canonical_text(e, false).size());
    check_same_value(e, out);
  }
  // Symbols made in the other order (GiNaC orders terms by creation): the same text.
  symbol q2("q2"), q1("q1");
  const ex e = m * cos(q1) * cos(q2) + m * sin(q1) * sin(q2) + pow(sin(q2), 2) * a;
  symbol p1("q1"), p2("q2");
  const ex f = pow(sin(p2), 2) * a + m * sin(p1) * sin(p2) + m * cos(p1) * cos(p2);
  CHECK(canonical_text(display_simplify(e), false) == canonical_text(display_simplify(f), false));
}

TEST_CASE("display_simplify: over its work limits it returns the plain form", "[print][display]") {
  // (sum of 8 products of cosines)^4 has far more terms than the limit allows.
  ex s = 0;
  for (int i = 0; i < 8; ++i) s += cos(x + i * y) * sin(i * x - y);
  const ex big = pow(s, 4) + pow(sin(z), 2) + pow(cos(z), 2);
  mbsc::print::DisplayLimits tight;
  tight.max_expanded_terms = 100;
  const ex out = display_simplify(big, tight);
  CHECK(out.is_equal(mbsc::sym::tidy(big)));
  // Few allowed products of waves: the budget stops the rewriting, the value stays.
  mbsc::print::DisplayLimits budget;
  budget.max_wave_terms = 10;
  const ex e = pow(cos(x), 6) * pow(sin(y), 5) + a;
  const ex out2 = display_simplify(e, budget);
  CHECK(out2.is_equal(mbsc::sym::tidy(e)));
  check_same_value(e, out2);
  // The printing that compares candidates is charged too: sin^2 + cos^2 = 1 is found
  // with the default limits, and not when the call may print only a few characters.
  const ex f = a * pow(sin(x), 2) + a * pow(cos(x), 2) + b * cos(y);
  CHECK(canonical_text(display_simplify(f), false) == canonical_text(a + b * cos(y), false));
  mbsc::print::DisplayLimits few_chars;
  few_chars.max_printed_chars = 20;
  const ex out3 = display_simplify(f, few_chars);
  CHECK(out3.is_equal(mbsc::sym::tidy(f)));
  check_same_value(f, out3);
}
