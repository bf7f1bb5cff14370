// SPDX-License-Identifier: GPL-2.0-or-later
// The reader of command-line expressions: the model language's syntax and guards, its
// values, and the C++ written from the text as given.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "mbsc/model/expr_convert.hpp"
#include "mbsc/model/option_expression.hpp"

using namespace mbsc::model;

TEST_CASE("option expressions: values, names and pi", "[model][option]") {
  const OptionNames names = {{"l", exact_decimal(1.5)}, {"arm.th", exact_decimal(0.25)}};
  double v = 0;
  std::string error;
  REQUIRE(option_value("2*l + arm.th^2 - sin(pi/6)", names, "numbers", v, error));
  CHECK(v == Approx(3.0 + 0.0625 - 0.5).epsilon(1e-15));
  REQUIRE(option_value("atan2(1, 1)*4", names, "numbers", v, error));
  CHECK(v == Approx(M_PI).epsilon(1e-15));
  REQUIRE(option_value("-(-3)", names, "numbers", v, error));
  CHECK(v == 3);
}

TEST_CASE("option expressions: refused with the column and the reason, in bounded time", "[model][option]") {
  const OptionNames names = {{"l", exact_decimal(1.5)}};
  struct Case {
    std::string text, expect;
  } cases[] = {
      {"2^(2^40)", "cannot be folded exactly"},
      {"factorial(5)", "unknown function 'factorial'"},
      {std::string(10000, '(') + "1" + std::string(10000, ')'), "nesting too deep"},
      {"1/0", "division by zero"},
      {"log(0)", "undefined"},
      {"acos(2)", "not a finite real number"},
      {"1e-320", "too small for a double"},
      {"1e400", "too large for a double"},
      {"ll + 1", "unknown name 'll'"},
      {"l'", "no rates here"},
      {"1 +", "expected"},
      {"1 2", "the end of the expression"},
      {"sqrt(-1)", "not a finite real number"},
      {"model x", "keyword"},
      {"exp(exp(exp(5)))", "larger in magnitude than 1e+30"},
      {"1e31", "larger in magnitude than 1e+30"},
  };
  for (const auto& c : cases) {
    double v = 0;
    std::string error;
    INFO(c.text.substr(0, 40));
    CHECK_FALSE(option_value(c.text, names, "numbers", v, error));
    INFO(error);
    CHECK(error.find(c.expect) != std::string::npos);
    CHECK(error.size() < 400);  // a long text is cut in the message
  }
}

TEST_CASE("option expressions: the C++ of an input follows the text and evaluates to its value", "[model][option]") {
  const GiNaC::symbol t("t"), m("m");
  const OptionNames names = {{"t", t}, {"m", m}};
  std::string error;
  const std::string text = "2*sin(pi*t/4) - m^2/(t + 3) + abs(t - 1)";
  const auto e = read_option_expression(text, names, "t and the parameters", error);
  REQUIRE(e);
  const std::string cpp = option_expression_cpp(text, {{"t", "t"}, {"m", "p[0]"}});
  CHECK(cpp == "((2.0 * std::sin((3.141592653589793 * t / 4.0))) - (std::pow(p[0], 2.0) / (t + 3.0)) + "
               "std::fabs((t - 1.0)))");
  // The same text always gives the same C++.
  CHECK(option_expression_cpp(text, {{"t", "t"}, {"m", "p[0]"}}) == cpp);
  double v = 0;
  REQUIRE(evaluate_number(e->subs(GiNaC::lst{t == GiNaC::numeric(7, 10), m == GiNaC::numeric(3, 2)}), v));
  const double tt = 0.7, p0 = 1.5;
  CHECK(v == Approx(2.0 * std::sin(3.141592653589793 * tt / 4.0) - std::pow(p0, 2.0) / (tt + 3.0) + std::fabs(tt - 1.0))
                 .epsilon(1e-14));
}
