// SPDX-License-Identifier: GPL-2.0-or-later
#include <catch2/catch.hpp>

#include <cmath>

#include "mbsc/model/value_bound.hpp"

using namespace GiNaC;
using mbsc::model::constant_value;
using mbsc::model::value_problem;

TEST_CASE("value bound: numbers and constant parts are real and at most 1e30", "[model][values]") {
  const symbol x("x");
  CHECK_FALSE(value_problem(ex(numeric(981, 100)) * x + sin(ex(numeric(1e29)))));
  CHECK_FALSE(value_problem(pow(x, 1000)));  // an exponent is a number like the others
  // A number beyond the bound, alone or as a coefficient.
  auto p = value_problem(numeric(2) * pow(numeric(10), 307));
  REQUIRE(p);
  CHECK(p->text() == "2e+307 is larger in magnitude than 1e+30, the largest value a model may hold");
  p = value_problem(-pow(numeric(10), 40) * x);
  REQUIRE(p);
  CHECK(p->text() == "-1e+40 is larger in magnitude than 1e+30, the largest value a model may hold");
  // Beyond a double: its magnitude.
  p = value_problem(pow(numeric(10), 400) * x);
  REQUIRE(p);
  CHECK(p->text() == "about 1e+400 is larger in magnitude than 1e+30, the largest value a model may hold");
  // A constant part, evaluated in doubles: exp(80) is 5.5e34.
  p = value_problem(exp(ex(80)) * x);
  REQUIRE(p);
  CHECK(p->text().rfind("exp(80) = 5.54062e+34 is larger", 0) == 0);
  // Not real: GiNaC's I, a complex root, an overflow (CLN's evalf says exp(exp(exp(5))) is 1).
  p = value_problem(sqrt(ex(-1)) * x);
  REQUIRE(p);
  CHECK(p->text() == "the complex number I is not a finite real number");
  p = value_problem(pow(ex(-8), numeric(1, 3)));
  REQUIRE(p);
  CHECK(p->not_real);
  p = value_problem(exp(exp(exp(ex(5)))));
  REQUIRE(p);
  CHECK(p->text().rfind("exp(exp(5)) = 2.85112e+64 is larger", 0) == 0);
  p = value_problem(exp(ex(1000)) * x);
  REQUIRE(p);
  CHECK(p->text() == "exp(1000) is not a finite real number");
}

TEST_CASE("value bound: the double value of a constant, as generated code computes it", "[model][values]") {
  const symbol x("x");
  CHECK(constant_value(sin(ex(Pi) / 2) + numeric(1, 4)) == Approx(1.25));
  CHECK(constant_value(atan2(ex(1), ex(1))) == Approx(M_PI / 4));
  CHECK_FALSE(constant_value(x + 1));
  const auto nan = constant_value(pow(ex(-8), numeric(1, 3)));
  REQUIRE(nan);
  CHECK(std::isnan(*nan));
}
