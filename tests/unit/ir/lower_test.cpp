// SPDX-License-Identifier: GPL-2.0-or-later
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "mbsc/ir/program.hpp"

using namespace GiNaC;
using mbsc::ir::Binding;
using mbsc::ir::Define;
using mbsc::ir::FunctionSpec;
using mbsc::ir::lower;
using mbsc::ir::LoweredFunction;
using mbsc::ir::Solve;

namespace {

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + what.size())) ++n;
  return n;
}

bool has(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

FunctionSpec spec_of(std::vector<ex> outputs) {
  FunctionSpec s;
  s.name = "f";
  s.outputs = std::move(outputs);
  return s;
}

// q0..q2 -> x[0..2], m -> p[0], l -> p[1].
struct Syms {
  symbol q0{"q0"}, q1{"q1"}, q2{"q2"}, m{"m"}, l{"l"};
  std::vector<Binding> bindings() const {
    return {{q0, "x[0]"}, {q1, "x[1]"}, {q2, "x[2]"}, {m, "p[0]"}, {l, "p[1]"}};
  }
};

}  // namespace

TEST_CASE("lower: canonical text independent of construction order", "[ir]") {
  // Symbols created in opposite orders get different GiNaC serials, hence different
  // GiNaC term orders.
  symbol a1("a"), b1("b"), c1("c");
  symbol c2("c"), b2("b"), a2("a");
  const std::vector<Binding> bind1 = {{a1, "x[0]"}, {b1, "x[1]"}, {c1, "x[2]"}};
  const std::vector<Binding> bind2 = {{c2, "x[2]"}, {a2, "x[0]"}, {b2, "x[1]"}};
  const ex e1 = a1 * sin(b1) + c1 * c1 * a1 - 3 * b1 / (a1 + c1) + pow(a1 + b1, 2) * cos(b1) + exp(c1 - a1);
  const ex e2 = exp(-a2 + c2) + cos(b2) * pow(b2 + a2, 2) + a2 * c2 * c2 - b2 * 3 / (c2 + a2) + sin(b2) * a2;
  const LoweredFunction f1 = lower(spec_of({e1, e1 * b1}), bind1);
  const LoweredFunction f2 = lower(spec_of({e2, b2 * e2}), bind2);
  CHECK(f1.body == f2.body);
  CHECK(f1.ops.total() == f2.ops.total());
}

TEST_CASE("lower: CSE names a shared subexpression once", "[ir]") {
  Syms s;
  const ex shared = s.q0 + s.q1;
  const LoweredFunction f = lower(spec_of({shared * s.m, shared * s.l + exp(shared)}), s.bindings());
  CHECK(count(f.body, "x[0] + x[1]") + count(f.body, "x[1] + x[0]") == 1);
  CHECK(has(f.body, "const double t0 = "));
  CHECK(count(f.body, "std::exp(t0)") == 1);
}

TEST_CASE("lower: an output used twice is computed once", "[ir]") {
  Syms s;
  const ex e = s.q0 * s.q1 * s.q2;
  const LoweredFunction f = lower(spec_of({e, e}), s.bindings());
  CHECK(has(f.body, "const double t0 = "));
  CHECK(has(f.body, "OUT[0] = t0;"));
  CHECK(has(f.body, "OUT[1] = t0;"));
  CHECK(f.ops.muls == 2);
}

TEST_CASE("lower: dead Define and Solve steps disappear", "[ir]") {
  Syms s;
  symbol used("used"), dead("dead"), X0("X0");
  FunctionSpec spec = spec_of({used * s.q0});
  spec.steps.push_back(Define{dead, exp(s.q1) * sin(s.q2) + pow(s.q2, 7)});
  spec.steps.push_back(Define{used, s.q1 * s.q2 + s.m});
  Solve solve;
  solve.label = "unused solve";
  solve.n = 1;
  solve.k = 1;
  solve.A = {s.q0 + dead};
  solve.B = {s.q1};
  solve.X = {X0};
  spec.steps.push_back(solve);
  const LoweredFunction f = lower(spec, s.bindings());
  CHECK_FALSE(has(f.body, "dead"));
  CHECK_FALSE(has(f.body, "std::exp"));
  CHECK_FALSE(has(f.body, "lu_solve"));
  CHECK(has(f.body, "const double used = "));
  CHECK(f.ops.solve_flops == 0);
  CHECK(f.ops.calls == 0);
  CHECK(f.ops.adds == 1);
  CHECK(f.ops.muls == 2);
}

TEST_CASE("lower: sin and cos of one argument computed together, once", "[ir]") {
  Syms s;
  const LoweredFunction f = lower(spec_of({sin(s.q0) + cos(s.q0), sin(s.q0) * cos(s.q0) * s.m}), s.bindings());
  CHECK(count(f.body, "std::sin(") == 1);
  CHECK(count(f.body, "std::cos(") == 1);
  CHECK(has(f.body, "const double s0 = std::sin(x[0]);\n  const double c0 = std::cos(x[0]);"));
  // Only the function that is used is emitted.
  const LoweredFunction g = lower(spec_of({sin(s.q1) * s.m}), s.bindings());
  CHECK(count(g.body, "std::sin(") == 1);
  CHECK(count(g.body, "std::cos(") == 0);
}

TEST_CASE("lower: trig of a computed argument follows the argument", "[ir]") {
  Syms s;
  const ex a = s.q0 + s.q1;
  const LoweredFunction f = lower(spec_of({s.m * s.l, sin(a) * s.l + cos(a) * s.m}), s.bindings());
  const auto arg = f.body.find("const double t0 = ");
  const auto sn = f.body.find("std::sin(t0)");
  const auto cs = f.body.find("std::cos(t0)");
  REQUIRE(arg != std::string::npos);
  REQUIRE(sn != std::string::npos);
  REQUIRE(cs != std::string::npos);
  CHECK(arg < sn);
  CHECK(sn < cs);
}

TEST_CASE("lower: operation counts match hand counts", "[ir]") {
  Syms s;
  // x0*x1 + x2            : 1 add, 1 mul
  // x0*x1*x2 - 2.0*p0     : 1 add, 3 muls
  // sin(x0) + cos(x0)     : 1 add, 2 calls
  // x0/x1                 : 1 div
  // x1*x1*x1              : 2 muls
  // std::sqrt(x2)         : 1 call
  const LoweredFunction f = lower(spec_of({s.q0 * s.q1 + s.q2, s.q0 * s.q1 * s.q2 - 2 * s.m, sin(s.q0) + cos(s.q0),
                                           s.q0 / s.q1, pow(s.q1, 3), sqrt(s.q2)}),
                                  s.bindings());
  INFO(f.body);
  CHECK(f.ops.adds == 3);
  CHECK(f.ops.muls == 6);
  CHECK(f.ops.divs == 1);
  CHECK(f.ops.calls == 3);
  CHECK(f.ops.solve_flops == 0);
  CHECK(f.ops.total() == 13);
}

TEST_CASE("lower: solve emission, flops and ordering", "[ir]") {
  Syms s;
  symbol X[6] = {symbol("X0"), symbol("X1"), symbol("X2"), symbol("X3"), symbol("X4"), symbol("X5")};
  FunctionSpec spec = spec_of({X[0] + X[5] * s.q0, sin(X[1]) * cos(X[1])});
  Solve solve;
  solve.label = "block B*";
  solve.n = 3;
  solve.k = 2;
  solve.A = {1 + s.q0 * s.q0, s.q1, 0, s.q1, 2, 0, 0, 0, 3};
  solve.B = {1, s.q0, s.q1, 1, s.m, s.l};
  solve.X = {X[0], X[1], X[2], X[3], X[4], X[5]};
  spec.steps.push_back(solve);
  const LoweredFunction f = lower(spec, s.bindings());
  INFO(f.body);
  CHECK(has(f.body, "  // solve A_0 X = B_0 (3x3, 2 columns): block B*\n  double A_0[9] = {"));
  CHECK(has(f.body, "  double B_0[6] = {"));
  CHECK(has(f.body, "  if (lu_solve<3, 2>(A_0, B_0) != 0) {\n    const double in_[4] = {p[0], p[1], x[0], x[1]};\n    return all_finite(A_0, 9) && all_finite(in_, 4) ? 1 : 2;\n  }"));
  CHECK(has(f.body, "B_0[5]*x[0]"));
  CHECK(f.body.find("lu_solve") < f.body.find("OUT[0]"));
  // sin/cos of a solve result right after the solve.
  CHECK(has(f.body, "? 1 : 2;\n  }\n  const double s0 = std::sin(B_0[1]);\n  const double c0 = std::cos(B_0[1]);\n"));
  CHECK(f.ops.solve_flops == 27);  // 27/3 + 9*2
}

TEST_CASE("lower: powers, quotients and negative terms print readably", "[ir]") {
  Syms s;
  const LoweredFunction f =
      lower(spec_of({pow(s.q0, 2), pow(s.q0, -1), pow(s.q0, -2), sqrt(s.q0), 1 / sqrt(s.q0), pow(s.q0, numeric(3, 2)),
                     pow(s.q0, 7), pow(s.q1 + s.q2, 2), s.q0 - 2 * s.q1 * s.q2, -s.q0, s.q0 / 2, ex(0), s.m / (s.l * s.q2)}),
            s.bindings());
  INFO(f.body);
  CHECK(has(f.body, "OUT[0] = x[0]*x[0];"));
  CHECK(has(f.body, "OUT[1] = 1.0/x[0];"));
  CHECK(has(f.body, "OUT[2] = 1.0/(x[0]*x[0]);"));
  CHECK(has(f.body, "OUT[3] = std::sqrt(x[0]);"));
  CHECK(has(f.body, "OUT[4] = 1.0/std::sqrt(x[0]);"));
  CHECK(has(f.body, "OUT[5] = std::pow(x[0], 1.5);"));
  CHECK(has(f.body, "OUT[6] = std::pow(x[0], 7.0);"));
  CHECK(has(f.body, "OUT[7] = t0*t0;"));
  CHECK((has(f.body, "OUT[8] = x[0] - 2.0*x[1]*x[2];") || has(f.body, "OUT[8] = x[0] - 2.0*x[2]*x[1];")));
  CHECK(has(f.body, "OUT[9] = -x[0];"));
  CHECK(has(f.body, "OUT[10] = 0.5*x[0];"));
  CHECK(has(f.body, "OUT[11] = 0.0;"));
  CHECK((has(f.body, "OUT[12] = p[0]/(p[1]*x[2]);") || has(f.body, "OUT[12] = p[0]/(x[2]*p[1]);")));
  CHECK_FALSE(has(f.body, "+ -"));
  CHECK_FALSE(has(f.body, "(-1.0)"));
  CHECK(has(f.body, "if (!all_finite(OUT, 13)) return 2;\n  return 0;"));
  CHECK(f.nout == 13);
}

TEST_CASE("lower: Define names are sanitised and made unique", "[ir]") {
  Syms s;
  symbol d1("omega.1"), d2("x"), d3("t0"), d4("v"), d5("v"), d6("int");
  FunctionSpec spec = spec_of({d1 * d2 * d3 * d4 * d5 * d6});
  spec.steps.push_back(Define{d1, s.q0 + s.q1});
  spec.steps.push_back(Define{d2, s.q1 + s.q2});
  spec.steps.push_back(Define{d3, s.q2 + s.m});
  spec.steps.push_back(Define{d4, s.m + s.l});
  spec.steps.push_back(Define{d5, s.l + s.q0});
  spec.steps.push_back(Define{d6, s.l + s.q1});
  const LoweredFunction f = lower(spec, s.bindings());
  INFO(f.body);
  CHECK(has(f.body, "const double omega_1 = "));
  CHECK(has(f.body, "const double x_1 = "));
  CHECK(has(f.body, "const double t0_1 = "));
  CHECK(has(f.body, "const double v = "));
  CHECK(has(f.body, "const double v_1 = "));
  CHECK(has(f.body, "const double int_1 = "));
}

TEST_CASE("lower: used arguments", "[ir]") {
  symbol q("q"), u0("u0"), k("k"), tt("t");
  const std::vector<Binding> b = {{q, "x[0]"}, {u0, "u[0]"}, {k, "p[2]"}, {tt, "t"}};
  CHECK(lower(spec_of({q * k}), b).used_args == std::vector<std::string>{"x", "p"});
  CHECK(lower(spec_of({tt + u0}), b).used_args == std::vector<std::string>{"t", "u"});
  CHECK(lower(spec_of({ex(1)}), b).used_args.empty());
  const LoweredFunction none = lower(spec_of({}), b);
  CHECK(none.nout == 0);
  CHECK(none.body == "  (void)OUT;\n  return 0;");
}

TEST_CASE("lower: errors", "[ir]") {
  Syms s;
  symbol stray("stray");
  CHECK_THROWS_WITH(lower(spec_of({s.q0 + stray}), s.bindings()), Catch::Contains("stray"));
  CHECK_THROWS_WITH(lower(spec_of({lgamma(s.q0)}), s.bindings()), Catch::Contains("lgamma"));
  // A Define reading the result of a later Solve.
  symbol d("d"), X0("X0");
  FunctionSpec spec = spec_of({d});
  spec.steps.push_back(Define{d, X0 + 1});
  Solve solve;
  solve.n = 1;
  solve.k = 1;
  solve.A = {s.q0};
  solve.B = {s.q1};
  solve.X = {X0};
  spec.steps.push_back(solve);
  CHECK_THROWS_AS(lower(spec, s.bindings()), std::runtime_error);
  // A symbol bound twice.
  std::vector<Binding> twice = s.bindings();
  twice.push_back({s.q0, "x[9]"});
  CHECK_THROWS_WITH(lower(spec_of({s.q0}), twice), Catch::Contains("twice"));
}

TEST_CASE("lower: constants and rationals print as doubles", "[ir]") {
  Syms s;
  const LoweredFunction f = lower(spec_of({Pi * s.q0, numeric(1, 3) + s.q0, ex(numeric(5))}), s.bindings());
  INFO(f.body);
  CHECK(has(f.body, "3.141592653589793*x[0]"));
  CHECK(has(f.body, "0.3333333333333333"));
  CHECK(has(f.body, "OUT[2] = 5.0;"));
}

TEST_CASE("lower: a named Define is a variable its readers refer to", "[ir]") {
  // e1 := -q0^2 l, e2 := e1 + q1 l (a recurrence), out = m (e2 - q2) and -m (q2 - e1):
  // readers must refer to e1 and e2 by name whatever sign GiNaC gives the sums.
  Syms s;
  symbol e1("e1"), e2("e2");
  FunctionSpec f = spec_of({s.m * (e2 - s.q2), -s.m * (s.q2 - e1)});
  f.steps.push_back(Define{e1, -s.q0 * s.q0 * s.l, true});
  f.steps.push_back(Define{e2, e1 + s.q1 * s.l, true});
  const LoweredFunction lf = lower(f, s.bindings());
  INFO(lf.body);
  CHECK(has(lf.body, "const double e1 = "));
  CHECK(has(lf.body, "const double e2 = "));
  CHECK(has(lf.body, "*p[1] + e1;"));
  CHECK(count(lf.body, "e1") == 3);  // defined once, read by e2 and by OUT[1]
  CHECK(count(lf.body, "e2") == 2);  // defined once, read by OUT[0]
  // An unreferenced named Define is dead.
  symbol unused("unused");
  FunctionSpec g = spec_of({s.q0 + s.q1});
  g.steps.push_back(Define{unused, s.q2 * s.q2, true});
  CHECK_FALSE(has(lower(g, s.bindings()).body, "unused"));
}

TEST_CASE("lower: mostly-zero outputs are one zero fill, then only the nonzero entries", "[ir]") {
  Syms s;
  // A 3x3 "Jacobian" with two nonzeros: the fill comes before the first output.
  const LoweredFunction f = lower(spec_of({0, 0, s.q0 * s.m, 0, 0, 0, 0, sin(s.q1), 0}), s.bindings());
  CHECK(count(f.body, "for (int i = 0; i < 9; ++i) OUT[i] = 0.0;") == 1);
  CHECK(count(f.body, "OUT[") == 3);  // the fill and the two entries
  CHECK(has(f.body, "OUT[2] = "));
  CHECK(has(f.body, "OUT[7] = "));
  CHECK(f.body.find("OUT[i] = 0.0") < f.body.find("OUT[2] = "));
  CHECK(has(f.body, "if (!all_finite(OUT, 9)) return 2;"));
  CHECK(f.nout == 9);
}

TEST_CASE("lower: a few zero outputs are still written one by one", "[ir]") {
  Syms s;
  // Half the outputs zero is not more than half: no fill.
  const LoweredFunction f = lower(spec_of({s.q0, 0, s.q1, 0}), s.bindings());
  CHECK_FALSE(has(f.body, "for (int i"));
  CHECK(has(f.body, "OUT[1] = 0.0;"));
  CHECK(has(f.body, "OUT[3] = 0.0;"));
  // A nonzero constant is an entry like any other, under the fill.
  const LoweredFunction g = lower(spec_of({0, 0, 0, -1, 2.5}), s.bindings());
  CHECK(has(g.body, "for (int i = 0; i < 5; ++i) OUT[i] = 0.0;"));
  CHECK(has(g.body, "OUT[3] = -1.0;"));
  CHECK(has(g.body, "OUT[4] = 2.5;"));
  CHECK_FALSE(has(g.body, "OUT[0] ="));
}
