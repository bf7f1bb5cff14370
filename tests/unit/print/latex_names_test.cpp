// SPDX-License-Identifier: GPL-2.0-or-later
// Model names as LaTeX symbols (mbsc print --latex): the rules of docs/language.md
// "Symbols in LaTeX", one case each, and the `latex` statements' overrides.
#include <catch2/catch.hpp>

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "mbsc/print/latex_names.hpp"

using mbsc::print::latex_call;
using mbsc::print::latex_symbol;

TEST_CASE("latex symbols: letters, Greek names and subscripts", "[latex]") {
  const std::vector<std::pair<const char*, const char*>> cases = {
      // a letter, a letter with a number
      {"g", "g"},
      {"l2", "l_{2}"},
      {"m12", "m_{12}"},
      // Greek names, the abbreviation th, capitals that LaTeX has and those it draws as Latin
      {"th1", "\\theta_{1}"},
      {"theta", "\\theta"},
      {"alpha", "\\alpha"},
      {"epsilon", "\\epsilon"},
      {"varphi", "\\varphi"},
      {"omega3", "\\omega_{3}"},
      {"Omega", "\\Omega"},
      {"Theta", "\\Theta"},
      {"Gamma", "\\Gamma"},
      {"Mu", "M"},
      {"Alpha", "A"},
      {"tau0", "\\tau_{0}"},
      // written subscripts: numbers, letters, Greek names, words
      {"m_3", "m_{3}"},
      {"x_G", "x_{G}"},
      {"r_phi", "r_{\\phi}"},
      {"m_crank", "m_{\\mathrm{crank}}"},
      {"v_left", "v_{\\mathrm{left}}"},
      {"F_load", "F_{\\mathrm{load}}"},
      {"l1_a", "l_{1,a}"},
      {"th_2", "\\theta_{2}"},
      {"e_b1_u", "e_{b_{1},u}"},
      {"r_crank_2_w", "r_{\\mathrm{crank},2,w}"},
      {"x_th1", "x_{\\theta_{1}}"},
      // a letter and a tag: one letter after it, or capitals after a small letter
      {"Im", "I_{m}"},
      {"bm", "b_{m}"},
      {"mL", "m_{L}"},
      {"mUL", "m_{\\mathrm{UL}}"},
      {"aBR", "a_{\\mathrm{BR}}"},
      // anything else is the name in upright letters
      {"dchi", "\\mathrm{dchi}"},
      {"Load", "\\mathrm{Load}"},
      {"kappa_", "\\mathrm{kappa\\_}"},
      {"_x", "\\mathrm{\\_x}"},
      {"a__b", "\\mathrm{a\\_\\_b}"},
  };
  for (const auto& [name, symbol] : cases) {
    INFO(name);
    CHECK(latex_symbol(name) == symbol);
  }
}

TEST_CASE("latex symbols: NAME_dot is the rate of NAME (a joint coordinate's default speed)", "[latex]") {
  CHECK(latex_symbol("q1_dot") == "\\dot{q}_{1}");
  CHECK(latex_symbol("th_dot") == "\\dot{\\theta}");
  CHECK(latex_symbol("arm.q2_dot") == "\\dot{q}_{\\mathrm{arm},2}");
  CHECK(latex_symbol("q1_dot'") == "\\ddot{q}_{1}");
  // Not a suffix of a name: kept as written.
  CHECK(latex_symbol("_dot") == "\\mathrm{\\_dot}");
}

TEST_CASE("latex symbols: qualified names put their bodies in the subscript", "[latex]") {
  CHECK(latex_symbol("b.x") == "x_{b}");
  CHECK(latex_symbol("crank.theta") == "\\theta_{\\mathrm{crank}}");
  CHECK(latex_symbol("crank.th") == "\\theta_{\\mathrm{crank}}");
  CHECK(latex_symbol("crank.th1") == "\\theta_{\\mathrm{crank},1}");
  CHECK(latex_symbol("b1.x") == "x_{b_{1}}");
  // crank[2].w after loop expansion is crank_2.w
  CHECK(latex_symbol("crank_2.w") == "w_{\\mathrm{crank}_{2}}");
  CHECK(latex_symbol("left.upper.theta") == "\\theta_{\\mathrm{left},\\mathrm{upper}}");
  CHECK(latex_symbol("R.A_x") == "A_{R,x}");
  // Body and subsystem names are labels: no letter-and-tag reading, words kept whole.
  CHECK(latex_symbol("HC.distal.theta") == "\\theta_{\\mathrm{HC},\\mathrm{distal}}");
  CHECK(latex_symbol("motor_left.w") == "w_{\\mathrm{motor\\_left}}");
  CHECK(latex_symbol("grid_2_3.x") == "x_{\\mathrm{grid}_{2,3}}");
  CHECK(latex_symbol("th1.x") == "x_{\\theta_{1}}");
}

TEST_CASE("latex symbols: rates are dotted letters", "[latex]") {
  CHECK(latex_symbol("w1'") == "\\dot{w}_{1}");
  CHECK(latex_symbol("th1'") == "\\dot{\\theta}_{1}");
  CHECK(latex_symbol("crank.w'") == "\\dot{w}_{\\mathrm{crank}}");
  CHECK(latex_symbol("x''") == "\\ddot{x}");
  CHECK(latex_symbol("x'''") == "\\dddot{x}");
  CHECK(latex_symbol("x''''") == "{x^{(4)}}");
  CHECK(latex_symbol("m_crank'") == "\\dot{m}_{\\mathrm{crank}}");
}

TEST_CASE("latex symbols: the latex statements' text wins, braced when it has scripts", "[latex]") {
  const std::map<std::string, std::string> given = {
      {"crank.theta", "\\varphi"}, {"m1", "m_{\\mathrm{arm}}"}, {"F", "F^{*}"}, {"q", "q'"}};
  CHECK(latex_symbol("crank.theta", given) == "\\varphi");
  CHECK(latex_symbol("crank.theta'", given) == "\\dot{\\varphi}");
  // braced so that a power or another subscript after it is no double script
  CHECK(latex_symbol("m1", given) == "{m_{\\mathrm{arm}}}");
  CHECK(latex_symbol("F", given) == "{F^{*}}");
  CHECK(latex_symbol("q", given) == "{q'}");
  // names not given keep their automatic symbol
  CHECK(latex_symbol("rocker.theta", given) == latex_symbol("rocker.theta"));
  CHECK(latex_symbol("m2", given) == "m_{2}");
}

TEST_CASE("latex calls: LaTeX's operator names, others upright", "[latex]") {
  CHECK(latex_call("sin", "x") == "\\sin\\left(x\\right)");
  CHECK(latex_call("asin", "x") == "\\arcsin\\left(x\\right)");
  CHECK(latex_call("atan", "x") == "\\arctan\\left(x\\right)");
  CHECK(latex_call("log", "x") == "\\ln\\left(x\\right)");
  CHECK(latex_call("abs", "x") == "\\left|x\\right|");
  CHECK(latex_call("atan2", "y, x") == "\\operatorname{atan2}\\left(y, x\\right)");
  CHECK(latex_call("step", "x") == "\\operatorname{step}\\left(x\\right)");
}
