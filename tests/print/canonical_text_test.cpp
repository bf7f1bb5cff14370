// SPDX-License-Identifier: GPL-2.0-or-later
// The text printer of `mbsc print` in the cases the display forms brought up: the
// factor order a person uses, a number taken into a sum, and the sign of an odd
// function of a sign-normalised angle (sin(y - x) printed as -sin(x - y)) moved out of
// products, powers and denominators.
#include "mbsc/print/canonical_text.hpp"

#include <catch2/catch.hpp>

using namespace GiNaC;
using mbsc::print::canonical_text;

TEST_CASE("canonical_text: factors as a person orders them", "[print][text]") {
  symbol m1("m1"), m2("m2"), l1("l1"), l2("l2"), a("a"), b("b"), th1("th1"), th2("th2");
  CHECK(canonical_text(m2 * l1 * l2 * cos(th1 - th2), false) == "l1*l2*m2*cos(th1 - th2)");
  CHECK(canonical_text((m1 + m2) * pow(l1, 2), false) == "(m1 + m2)*l1^2");
  CHECK(canonical_text(a * cos(th1) / (b * cos(th2)), false) == "a*cos(th1)/(b*cos(th2))");
  // GiNaC keeps 1/3*(m1 + 3*m2)*l1^2; the shorter (1/3*m1 + m2)*l1^2 is printed.
  CHECK(canonical_text((m1 / 3 + m2) * pow(l1, 2), false) == "(1/3*m1 + m2)*l1^2");
  CHECK(canonical_text(-(m1 / 2 + m2) * a, false) == "-(1/2*m1 + m2)*a");
  CHECK(canonical_text((m1 / 2 + m2) * a, true) == "\\left(\\frac{1}{2} m_{1} + m_{2}\\right) a");
  // A fraction's bar groups: its only denominator has no parentheses in LaTeX (two do).
  CHECK(canonical_text(a / (m1 + m2), true) == "\\frac{a}{m_{1} + m_{2}}");
  CHECK(canonical_text(a / ((m1 + m2) * b), true) == "\\frac{a}{\\left(m_{1} + m_{2}\\right) b}");
  CHECK(canonical_text(a / (m1 + m2), false) == "a/(m1 + m2)");
}

TEST_CASE("canonical_text: the sign of an odd function leaves products, powers and denominators", "[print][text]") {
  symbol x("x"), y("y"), a("a");
  CHECK(canonical_text(a * sin(y - x), false) == "-a*sin(x - y)");
  CHECK(canonical_text(3 * a * sin(y - x), false) == "-3*a*sin(x - y)");
  CHECK(canonical_text(a * pow(sin(y - x), 2), false) == "a*sin(x - y)^2");
  CHECK(canonical_text(a * pow(sin(y - x), 3), false) == "-a*sin(x - y)^3");
  CHECK(canonical_text(a / pow(sin(y - x), 3), false) == "-a/sin(x - y)^3");
  CHECK(canonical_text(1 / pow(sin(y - x), 3), false) == "-1/sin(x - y)^3");
  CHECK(canonical_text(a * pow(cos(y - x), 3), false) == "a*cos(x - y)^3");
}

TEST_CASE("canonical_text: an even power of a sum reads with a leading plus, whatever sign GiNaC keeps", "[print][text]") {
  // GiNaC stores (b - a)^2 as it is or as (a - b)^2 by its internal term order (which
  // depends on the order symbols were made in); the text must not.
  symbol b("b"), a("a"), k("k");
  for (const ex& base : {ex(a - b), ex(b - a), ex(-a - k * b), ex(a + k * b)}) {
    const std::string plus = canonical_text(base, false)[0] == '-' ? canonical_text(-base, false) : canonical_text(base, false);
    CHECK(canonical_text(pow(base, 2), false) == "(" + plus + ")^2");
    CHECK(canonical_text(k / pow(base, 4), false) == "k/(" + plus + ")^4");
  }
  CHECK(canonical_text(pow(b - a, 2), false) == "(a - b)^2");
}
