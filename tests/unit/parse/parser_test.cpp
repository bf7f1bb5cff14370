// SPDX-License-Identifier: GPL-2.0-or-later
// Unit tests of the parser: the tree it builds for valid models.
#include <catch2/catch.hpp>

#include <string>

#include "mbsc/parse/parse.hpp"

using mbsc::Diagnostics;
using mbsc::SourcePos;
using mbsc::ast::Expr;
using mbsc::ast::ExprPtr;
using mbsc::ast::File;
using mbsc::ast::Statement;
using Kind = mbsc::ast::Statement::Kind;

namespace {

/// An expression written back fully parenthesised: binary "(a+b)", unary "(-a)",
/// calls "f(a, b)", primes "x''", names and numbers as written.
std::string show(const ExprPtr& e) {
  if (!e) return "<null>";
  switch (e->kind) {
    case Expr::Kind::Number:
    case Expr::Kind::Name: return e->text;
    case Expr::Kind::Call: {
      std::string out = e->text + "(";
      for (std::size_t i = 0; i < e->args.size(); ++i) out += (i ? ", " : "") + show(e->args[i]);
      return out + ")";
    }
    case Expr::Kind::Unary: return "(" + e->text + show(e->args.at(0)) + ")";
    case Expr::Kind::Binary: return "(" + show(e->args.at(0)) + e->text + show(e->args.at(1)) + ")";
    case Expr::Kind::Sum:
    case Expr::Kind::Product: {  // flat in the tree, written back left-associated
      std::string out = show(e->args.at(0));
      for (std::size_t i = 1; i < e->args.size(); ++i) out = "(" + out + e->text.at(i - 1) + show(e->args[i]) + ")";
      return out;
    }
    case Expr::Kind::Prime: return show(e->args.at(0)) + "'";
  }
  return "?";
}

std::string at(const SourcePos& p) { return std::to_string(p.line) + ":" + std::to_string(p.col); }

File parse_ok(const std::string& text) {
  Diagnostics diags;
  auto file = mbsc::parse::parse_text(text, "t.mbs", diags);
  INFO(diags.format());
  REQUIRE(file.has_value());
  REQUIRE_FALSE(diags.has_errors());
  return *file;
}

/// The value of `output y = <expr>`, written back.
std::string expr(const std::string& text) {
  const File f = parse_ok("output y = " + text);
  REQUIRE(f.statements.size() == 1);
  return show(f.statements[0]->value);
}

}  // namespace

TEST_CASE("parser: precedence and associativity", "[parse]") {
  CHECK(expr("a + b * c") == "(a+(b*c))");
  CHECK(expr("a * b + c") == "((a*b)+c)");
  CHECK(expr("a - b - c") == "((a-b)-c)");
  CHECK(expr("a - b + c") == "((a-b)+c)");
  CHECK(expr("a / b / c") == "((a/b)/c)");
  CHECK(expr("a * b / c * d") == "(((a*b)/c)*d)");
  CHECK(expr("a ^ b ^ c") == "(a^(b^c))");
  CHECK(expr("a * b ^ c") == "(a*(b^c))");
  CHECK(expr("a ^ b * c") == "((a^b)*c)");
  CHECK(expr("(a + b) * c") == "((a+b)*c)");
  CHECK(expr("((a))") == "a");
}

TEST_CASE("parser: unary operators", "[parse]") {
  CHECK(expr("-x^2") == "(-(x^2))");
  CHECK(expr("-x*y") == "((-x)*y)");
  CHECK(expr("a*-b") == "(a*(-b))");
  CHECK(expr("a - -b") == "(a-(-b))");
  CHECK(expr("2^-x") == "(2^(-x))");
  CHECK(expr("2^-x^2") == "(2^(-(x^2)))");
  CHECK(expr("+a") == "(+a)");
  CHECK(expr("- -a") == "(-(-a))");
  CHECK(expr("-1") == "(-1)");
  CHECK(expr("(-x)^2") == "((-x)^2)");
}

TEST_CASE("parser: primes are postfix time derivatives of names", "[parse]") {
  CHECK(expr("x'") == "x'");
  CHECK(expr("x''") == "x''");
  CHECK(expr("x'^2") == "(x'^2)");
  CHECK(expr("-x'") == "(-x')");
  CHECK(expr("I*w' - b*w") == "((I*w')-(b*w))");
  CHECK(expr("left.upper.theta'") == "left.upper.theta'");
  CHECK(expr("x'*cos(th) + y'*sin(th)") == "((x'*cos(th))+(y'*sin(th)))");

  const File f = parse_ok("speed v = x''");
  const ExprPtr& e = f.statements[0]->value;
  REQUIRE(e->kind == Expr::Kind::Prime);
  REQUIRE(e->args.size() == 1);
  REQUIRE(e->args[0]->kind == Expr::Kind::Prime);
  REQUIRE(e->args[0]->args[0]->kind == Expr::Kind::Name);
  CHECK(e->args[0]->args[0]->text == "x");
  CHECK(at(e->pos) == "1:11");
  CHECK(at(e->args[0]->pos) == "1:11");
}

TEST_CASE("parser: numbers, names, paths and calls", "[parse]") {
  CHECK(expr("1 + 0.5 + .5 + 1e-3 + 2.5E+2") == "((((1+0.5)+.5)+1e-3)+2.5E+2)");
  CHECK(expr("R.w*r1") == "(R.w*r1)");
  CHECK(expr("sin(xi - theta)") == "sin((xi-theta))");
  CHECK(expr("atan2(y, x)") == "atan2(y, x)");
  CHECK(expr("f()") == "f()");
  CHECK(expr("f(g(h(t)), -1)") == "f(g(h(t)), (-1))");
  CHECK(expr("cos(xi-theta)*dtheta*(r1 - r2)") == "((cos((xi-theta))*dtheta)*(r1-r2))");

  const File f = parse_ok("output y = 0.15 + left.upper.theta * sin(t)");
  const ExprPtr& e = f.statements[0]->value;
  REQUIRE(e->kind == Expr::Kind::Sum);
  CHECK(e->text == "+");
  const ExprPtr& num = e->args[0];
  CHECK(num->kind == Expr::Kind::Number);
  CHECK(num->text == "0.15");
  const ExprPtr& prod = e->args[1];
  REQUIRE(prod->kind == Expr::Kind::Product);
  CHECK(prod->text == "*");
  CHECK(prod->args[0]->kind == Expr::Kind::Name);
  CHECK(prod->args[0]->text == "left.upper.theta");
  CHECK(prod->args[1]->kind == Expr::Kind::Call);
  CHECK(prod->args[1]->text == "sin");
  REQUIRE(prod->args[1]->args.size() == 1);
  CHECK(prod->args[1]->args[0]->text == "t");
}

TEST_CASE("parser: expression positions are those of the first token", "[parse]") {
  //                      1234567890123456789012345678
  const File f = parse_ok("mass (a + b)*c - -sin(d)^2");
  const ExprPtr& e = f.statements[0]->value;  // ((a+b)*c) - (-(sin(d)^2))
  CHECK(at(e->pos) == "1:6");
  CHECK(at(e->args[0]->pos) == "1:6");           // (a+b)*c starts at '('
  CHECK(at(e->args[0]->args[0]->pos) == "1:7");  // a+b itself starts at a
  CHECK(at(e->args[0]->args[1]->pos) == "1:14");
  const ExprPtr& neg = e->args[1];
  CHECK(neg->kind == Expr::Kind::Unary);
  CHECK(at(neg->pos) == "1:18");
  CHECK(at(neg->args[0]->pos) == "1:19");           // sin(d)^2
  CHECK(at(neg->args[0]->args[0]->pos) == "1:19");  // sin(d)
  CHECK(at(neg->args[0]->args[0]->args[0]->pos) == "1:23");
  CHECK(at(neg->args[0]->args[1]->pos) == "1:26");
  CHECK(e->pos.file == "t.mbs");
}

TEST_CASE("parser: declarations", "[parse]") {
  const File f = parse_ok(
      "model slider_crank\n"
      "parameter r = 0.15, l, m1 = 2*r\n"
      "input tau, v_left\n"
      "gravity (0, -g)\n"
      "gravity (gx, gy, gz)\n"
      "coordinate x, y\n"
      "speed u = x', w\n");
  const auto& s = f.statements;
  REQUIRE(s.size() == 12);
  CHECK(f.path == "t.mbs");

  CHECK(s[0]->kind == Kind::Model);
  CHECK(s[0]->name == "slider_crank");
  CHECK(at(s[0]->pos) == "1:1");
  CHECK(at(s[0]->name_pos) == "1:7");

  CHECK(s[1]->kind == Kind::Parameter);
  CHECK(s[1]->name == "r");
  CHECK(show(s[1]->value) == "0.15");
  CHECK(at(s[1]->pos) == "2:1");
  CHECK(at(s[1]->name_pos) == "2:11");
  CHECK(s[2]->kind == Kind::Parameter);
  CHECK(s[2]->name == "l");
  CHECK(s[2]->value == nullptr);
  CHECK(at(s[2]->pos) == "2:1");
  CHECK(at(s[2]->name_pos) == "2:21");
  CHECK(s[3]->name == "m1");
  CHECK(show(s[3]->value) == "(2*r)");
  CHECK(at(s[3]->value->pos) == "2:29");

  CHECK(s[4]->kind == Kind::Input);
  CHECK(s[4]->name == "tau");
  CHECK(s[5]->kind == Kind::Input);
  CHECK(s[5]->name == "v_left");
  CHECK(at(s[5]->pos) == "3:1");
  CHECK(at(s[5]->name_pos) == "3:12");

  CHECK(s[6]->kind == Kind::Gravity);
  REQUIRE(s[6]->exprs.size() == 2);
  CHECK(show(s[6]->exprs[0]) == "0");
  CHECK(show(s[6]->exprs[1]) == "(-g)");
  CHECK(s[7]->kind == Kind::Gravity);
  REQUIRE(s[7]->exprs.size() == 3);
  CHECK(show(s[7]->exprs[2]) == "gz");

  CHECK(s[8]->kind == Kind::Coordinate);
  CHECK(s[8]->name == "x");
  CHECK(s[9]->kind == Kind::Coordinate);
  CHECK(s[9]->name == "y");
  CHECK(at(s[9]->name_pos) == "6:15");

  CHECK(s[10]->kind == Kind::Speed);
  CHECK(s[10]->name == "u");
  CHECK(show(s[10]->value) == "x'");
  CHECK(s[11]->kind == Kind::Speed);
  CHECK(s[11]->name == "w");
  CHECK(s[11]->value == nullptr);
  CHECK(at(s[11]->name_pos) == "7:15");
}

TEST_CASE("parser: element statements", "[parse]") {
  const File f = parse_ok(
      "mass m1\n"
      "inertia m1*r1^2\n"
      "kinetic m*v^2/2\n"
      "potential m*g*y\n"
      "force motor.w : k*eta*i - I*w' - b*w\n"
      "independent dtheta, D.w\n"
      "output slider_x = slider.x\n"
      "output energy\n"
      "include \"lib/arm.mbs\"\n");
  const auto& s = f.statements;
  REQUIRE(s.size() == 9);
  CHECK(s[0]->kind == Kind::Mass);
  CHECK(show(s[0]->value) == "m1");
  CHECK(s[1]->kind == Kind::Inertia);
  CHECK(show(s[1]->value) == "(m1*(r1^2))");
  CHECK(s[2]->kind == Kind::Kinetic);
  CHECK(show(s[2]->value) == "((m*(v^2))/2)");
  CHECK(s[3]->kind == Kind::Potential);
  CHECK(show(s[3]->value) == "((m*g)*y)");
  CHECK(at(s[3]->pos) == "4:1");

  CHECK(s[4]->kind == Kind::Force);
  CHECK(s[4]->path.text == "motor.w");
  CHECK(at(s[4]->path.pos) == "5:7");
  CHECK(show(s[4]->value) == "((((k*eta)*i)-(I*w'))-(b*w))");

  CHECK(s[5]->kind == Kind::Independent);
  REQUIRE(s[5]->paths.size() == 2);
  CHECK(s[5]->paths[0].text == "dtheta");
  CHECK(s[5]->paths[1].text == "D.w");
  CHECK(at(s[5]->paths[1].pos) == "6:21");

  CHECK(s[6]->kind == Kind::Output);
  CHECK(s[6]->name == "slider_x");
  CHECK(at(s[6]->name_pos) == "7:8");
  CHECK(show(s[6]->value) == "slider.x");
  CHECK(s[7]->kind == Kind::Output);
  CHECK(s[7]->name == "energy");
  CHECK(s[7]->value == nullptr);
  CHECK(at(s[7]->name_pos) == "8:8");

  CHECK(s[8]->kind == Kind::Include);
  CHECK(s[8]->name == "lib/arm.mbs");
  CHECK(at(s[8]->pos) == "9:1");
  CHECK(at(s[8]->name_pos) == "9:9");
}

TEST_CASE("parser: subsystems and bodies", "[parse]") {
  const File f = parse_ok(
      "subsystem plain\n"
      "subsystem R : rigid2d { mass m1  inertia m1*r1^2 }\n"
      "body slider : particle2d\n"
      "subsystem left : Arm(mUL, 2*mBL, aUL)\n"
      "subsystem empty_args : Arm()\n"
      "subsystem node {\n"
      "  coordinate theta\n"
      "\n"
      "  body D : rigid2d {\n"
      "    mass m2; inertia m2*r2^2/2\n"
      "  }\n"
      "}\n"
      "subsystem allman : custom\n"
      "{\n"
      "  speed w\n"
      "}\n");
  const auto& s = f.statements;
  REQUIRE(s.size() == 7);

  CHECK(s[0]->kind == Kind::Subsystem);
  CHECK(s[0]->name == "plain");
  CHECK(s[0]->kind_name.empty());
  CHECK_FALSE(s[0]->has_body);
  CHECK(s[0]->body.empty());

  CHECK(s[1]->name == "R");
  CHECK(s[1]->kind_name == "rigid2d");
  CHECK(at(s[1]->kind_pos) == "2:15");
  CHECK(s[1]->has_body);
  REQUIRE(s[1]->body.size() == 2);
  CHECK(s[1]->body[0]->kind == Kind::Mass);
  CHECK(s[1]->body[1]->kind == Kind::Inertia);
  CHECK(at(s[1]->body[1]->pos) == "2:34");

  CHECK(s[2]->kind == Kind::Subsystem);  // 'body' is a synonym
  CHECK(s[2]->name == "slider");
  CHECK(s[2]->kind_name == "particle2d");
  CHECK(at(s[2]->pos) == "3:1");
  CHECK(at(s[2]->name_pos) == "3:6");
  CHECK_FALSE(s[2]->has_body);

  CHECK(s[3]->kind_name == "Arm");
  REQUIRE(s[3]->exprs.size() == 3);
  CHECK(show(s[3]->exprs[0]) == "mUL");
  CHECK(show(s[3]->exprs[1]) == "(2*mBL)");
  CHECK(at(s[3]->exprs[2]->pos) == "4:34");

  CHECK(s[4]->kind_name == "Arm");
  CHECK(s[4]->exprs.empty());

  CHECK(s[5]->name == "node");
  CHECK(s[5]->kind_name.empty());
  CHECK(s[5]->has_body);
  REQUIRE(s[5]->body.size() == 2);
  CHECK(s[5]->body[0]->kind == Kind::Coordinate);
  const auto& d = s[5]->body[1];
  CHECK(d->kind == Kind::Subsystem);
  CHECK(d->name == "D");
  CHECK(at(d->pos) == "9:3");
  REQUIRE(d->body.size() == 2);
  CHECK(show(d->body[1]->value) == "((m2*(r2^2))/2)");

  CHECK(s[6]->name == "allman");
  CHECK(s[6]->has_body);
  REQUIRE(s[6]->body.size() == 1);
  CHECK(s[6]->body[0]->kind == Kind::Speed);
}

TEST_CASE("parser: components", "[parse]") {
  const File f = parse_ok(
      "component Arm(m_upper, m_lower) {\n"
      "  body upper : rigid2d { mass m_upper }\n"
      "  body lower : rigid2d { mass m_lower }\n"
      "}\n"
      "component Empty() {}\n");
  const auto& s = f.statements;
  REQUIRE(s.size() == 2);
  CHECK(s[0]->kind == Kind::Component);
  CHECK(s[0]->name == "Arm");
  CHECK(at(s[0]->name_pos) == "1:11");
  REQUIRE(s[0]->formals.size() == 2);
  CHECK(s[0]->formals[0] == "m_upper");
  CHECK(s[0]->formals[1] == "m_lower");
  REQUIRE(s[0]->formal_pos.size() == 2);
  CHECK(at(s[0]->formal_pos[0]) == "1:15");
  CHECK(at(s[0]->formal_pos[1]) == "1:24");
  CHECK(s[0]->has_body);
  REQUIRE(s[0]->body.size() == 2);
  CHECK(s[0]->body[1]->name == "lower");
  REQUIRE(s[0]->body[1]->body.size() == 1);
  CHECK(show(s[0]->body[1]->body[0]->value) == "m_lower");

  CHECK(s[1]->name == "Empty");
  CHECK(s[1]->formals.empty());
  CHECK(s[1]->has_body);
  CHECK(s[1]->body.empty());
}

TEST_CASE("parser: constraint blocks", "[parse]") {
  const File f = parse_ok(
      "constraint velocity {\n"
      "  R.u + R.w*r1 = 0\n"
      "  roll: R.v = 0; D.u = R.u\n"
      "}\n"
      "constraint position nonlinear { x^2 + y^2 = l^2 }\n"
      "constraint position {}\n");
  const auto& s = f.statements;
  REQUIRE(s.size() == 3);
  CHECK(s[0]->kind == Kind::Constraint);
  CHECK(s[0]->level == "velocity");
  CHECK_FALSE(s[0]->nonlinear);
  REQUIRE(s[0]->equations.size() == 3);
  const auto& e0 = s[0]->equations[0];
  CHECK(e0.label.empty());
  CHECK(show(e0.lhs) == "(R.u+(R.w*r1))");
  CHECK(show(e0.rhs) == "0");
  CHECK(at(e0.pos) == "2:3");
  const auto& e1 = s[0]->equations[1];
  CHECK(e1.label == "roll");
  CHECK(at(e1.pos) == "3:3");
  CHECK(show(e1.lhs) == "R.v");
  CHECK(at(e1.lhs->pos) == "3:9");
  const auto& e2 = s[0]->equations[2];
  CHECK(show(e2.lhs) == "D.u");
  CHECK(show(e2.rhs) == "R.u");
  CHECK(at(e2.pos) == "3:18");

  CHECK(s[1]->level == "position");
  CHECK(s[1]->nonlinear);
  REQUIRE(s[1]->equations.size() == 1);
  CHECK(show(s[1]->equations[0].lhs) == "((x^2)+(y^2))");
  CHECK(show(s[1]->equations[0].rhs) == "(l^2)");

  CHECK(s[2]->equations.empty());
}

TEST_CASE("parser: separators, comments and line continuation", "[parse]") {
  const File f = parse_ok(
      "# a comment line\n"
      "\n"
      "parameter a = 1; parameter b = 2   # trailing comment\n"
      ";;\n"
      "output y = a +\n"
      "           b *   # operator at the end of the line\n"
      "\n"
      "           c\n"
      "output z = f(a,\n"
      "             b)\n"
      "output w = (a\n"
      "            - b)\n"
      "parameter p,\n"
      "          q = 3\r\n"
      "gravity (0,\n"
      "         -g)\n"
      "speed v =\n"
      "  x'\n"
      "mass m inertia J\n");
  const auto& s = f.statements;
  REQUIRE(s.size() == 11);
  CHECK(s[0]->name == "a");
  CHECK(s[1]->name == "b");
  CHECK(at(s[1]->pos) == "3:18");
  CHECK(show(s[2]->value) == "(a+(b*c))");
  CHECK(at(s[2]->value->args[1]->args[1]->pos) == "8:12");
  CHECK(show(s[3]->value) == "f(a, b)");
  CHECK(show(s[4]->value) == "(a-b)");
  CHECK(s[5]->name == "p");
  CHECK(s[6]->name == "q");
  CHECK(at(s[6]->name_pos) == "14:11");
  CHECK(s[7]->exprs.size() == 2);
  CHECK(show(s[8]->value) == "x'");
  CHECK(s[9]->kind == Kind::Mass);
  CHECK(s[10]->kind == Kind::Inertia);
}

TEST_CASE("parser: an empty file and a comment-only file are valid", "[parse]") {
  CHECK(parse_ok("").statements.empty());
  CHECK(parse_ok("# nothing\n\n").statements.empty());
}

TEST_CASE("parser: the ring-and-disc model of the design sketch", "[parse]") {
  const File f = parse_ok(R"(model ring_disc
parameter m1, m2, r1, r2, g, xi
gravity (g*sin(xi), -g*cos(xi))

subsystem R : rigid2d { mass m1  inertia m1*r1^2 }     # speeds R.u, R.v, R.w
subsystem D : rigid2d { mass m2  inertia m2*r2^2/2 }

coordinate theta
speed      dtheta = theta'
constraint velocity {
  R.u + R.w*r1 = 0
  R.v = 0
  R.u - D.u + cos(xi-theta)*(R.w*r1 - D.w*r2) = 0
  R.v - D.v + sin(xi-theta)*(R.w*r1 - D.w*r2) = 0
  D.u - R.u + cos(xi-theta)*dtheta*(r1 - r2) = 0
}
independent dtheta, D.w
)");
  const auto& s = f.statements;
  REQUIRE(s.size() == 14);
  CHECK(s[0]->kind == Kind::Model);
  for (int i = 1; i <= 6; ++i) CHECK(s[i]->kind == Kind::Parameter);
  CHECK(s[6]->name == "xi");
  CHECK(show(s[7]->exprs[0]) == "(g*sin(xi))");
  CHECK(show(s[7]->exprs[1]) == "((-g)*cos(xi))");
  CHECK(s[8]->name == "R");
  CHECK(s[9]->name == "D");
  CHECK(at(s[9]->pos) == "6:1");
  CHECK(s[10]->kind == Kind::Coordinate);
  CHECK(s[11]->kind == Kind::Speed);
  CHECK(at(s[11]->name_pos) == "9:12");
  CHECK(s[12]->kind == Kind::Constraint);
  REQUIRE(s[12]->equations.size() == 5);
  CHECK(show(s[12]->equations[2].lhs) == "((R.u-D.u)+(cos((xi-theta))*((R.w*r1)-(D.w*r2))))");
  CHECK(at(s[12]->equations[4].pos) == "15:3");
  CHECK(s[13]->kind == Kind::Independent);
}

TEST_CASE("parser: a custom leaf inside a component", "[parse]") {
  const File f = parse_ok(R"(component Motor(k, eta, I, b, L, R, kappa) {
  subsystem m : custom {
    speed w, i
    force w : k*eta*i - I*w' - b*w
    force i : v - L*i' - R*i - kappa*eta*w
  }
}
subsystem motor_left : Motor(1, 2, 3, 4, 5, 6, 7)
)");
  REQUIRE(f.statements.size() == 2);
  const auto& m = f.statements[0]->body.at(0);
  REQUIRE(m->body.size() == 4);
  CHECK(m->body[2]->kind == Kind::Force);
  CHECK(m->body[3]->path.text == "i");
  CHECK(show(m->body[3]->value) == "(((v-(L*i'))-(R*i))-((kappa*eta)*w))");
  CHECK(f.statements[1]->exprs.size() == 7);
}
