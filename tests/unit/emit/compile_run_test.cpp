// SPDX-License-Identifier: GPL-2.0-or-later
// End to end: lower + emit, compile the generated files with a driver, run it, and compare
// with GiNaC's evaluation of the same expressions (and GiNaC's own linear solve).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "compile_helpers.hpp"
#include "mbsc/emit/generated_model.hpp"
#include "mbsc/ir/program.hpp"

using namespace GiNaC;
using mbsc::ir::Binding;
using mbsc::ir::Define;
using mbsc::ir::FunctionSpec;
using mbsc::ir::Solve;

namespace {

struct Case {
  symbol tt{"t"}, q0{"q0"}, q1{"q1"}, q2{"q2"}, u0{"u0"}, m{"m"}, g{"g"};
  std::vector<Binding> bindings() const {
    return {{tt, "t"}, {q0, "x[0]"}, {q1, "x[1]"}, {q2, "x[2]"}, {u0, "u[0]"}, {m, "p[0]"}, {g, "p[1]"}};
  }
};

// The values the driver receives, and GiNaC's substitution of the same doubles.
const double kT = 0.5;
const double kX[3] = {0.3, 0.7, 1.1};
const double kU[1] = {0.25};
const double kP[2] = {2.0, 9.81};

exmap values(const Case& c) {
  exmap v;
  v[c.tt] = numeric(kT);
  v[c.q0] = numeric(kX[0]);
  v[c.q1] = numeric(kX[1]);
  v[c.q2] = numeric(kX[2]);
  v[c.u0] = numeric(kU[0]);
  v[c.m] = numeric(kP[0]);
  v[c.g] = numeric(kP[1]);
  return v;
}

double eval_at(const ex& e, const exmap& v) {
  const ex r = e.subs(v).evalf();
  REQUIRE(is_a<numeric>(r));
  return ex_to<numeric>(r).to_double();
}

std::vector<double> parse_doubles(const std::string& line) {
  std::istringstream in(line);
  std::vector<double> out;
  std::string tok;
  while (in >> tok) out.push_back(std::strtod(tok.c_str(), nullptr));
  return out;
}

const char* kDriver = R"cpp(#include "e2e.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

// Prints "status out..." for each function, then whether the C wrappers agree.
static void show(int status, const double* out, int n) {
  std::printf("%d", status);
  for (int i = 0; i < n; ++i) std::printf(" %.17g", out[i]);
  std::printf("\n");
}

int main(int argc, char** argv) {
  if (argc != 8) return 99;
  const double t = std::strtod(argv[1], nullptr);
  double x[3] = {std::strtod(argv[2], nullptr), std::strtod(argv[3], nullptr), std::strtod(argv[4], nullptr)};
  const double u[1] = {std::strtod(argv[5], nullptr)};
  const double p[2] = {std::strtod(argv[6], nullptr), std::strtod(argv[7], nullptr)};
  double out[8] = {0};
  show(mbsc_gen::e2e::f(t, x, u, p, out), out, 5);
  double out_c[8] = {0};
  const int sc = mbsc_e2e_f(t, x, u, p, out_c);
  int same = sc == mbsc_gen::e2e::f(t, x, u, p, out) ? 1 : 0;
  for (int i = 0; i < 5; ++i) same = same && out[i] == out_c[i];
  std::printf("%d\n", same);
  show(mbsc_gen::e2e::singular(t, x, u, p, out), out, 1);
  x[0] = 0.0;
  show(mbsc_gen::e2e::divide(t, x, u, p, out), out, 1);
  return 0;
}
)cpp";

}  // namespace

TEST_CASE("end to end: generated code matches GiNaC to 1e-12", "[emit]") {
  Case c;
  const auto b = c.bindings();

  // f: a Define, an unused Define, a 3x3 solve with 2 right-hand sides whose matrix
  // depends on x, and outputs mixing X with the supported functions.
  symbol s("s"), dead("dead");
  std::vector<symbol> X;
  for (int i = 0; i < 6; ++i) X.emplace_back("X" + std::to_string(i));
  FunctionSpec f;
  f.name = "f";
  f.doc = "end-to-end test function";
  f.out_name = "y";
  f.out_shape = "5";
  const ex s_value = sin(c.q0) * c.m + c.q1 * c.q1;
  f.steps.push_back(Define{s, s_value});
  f.steps.push_back(Define{dead, exp(c.q2) * lgamma(c.q1)});  // unsupported, but dead: never printed
  Solve solve;
  solve.label = "test block";
  solve.n = 3;
  solve.k = 2;
  solve.A = {2 + pow(sin(c.q0), 2), c.q1, 0,  //
             c.q1, 3 + cos(c.q1), c.q2 * c.m,    //
             1, c.q2 * c.m, 4 + c.q0 * c.q0};
  solve.B = {s, 1, c.u0, c.tt, c.g, c.q0 * c.q1};
  solve.X = {X[0], X[1], X[2], X[3], X[4], X[5]};
  f.steps.push_back(solve);
  f.outputs = {
      X[0] + X[3] * cos(c.q0),
      X[5] * s - sqrt(c.m) * X[2] / (1 + c.q2 * c.q2),
      atan2(c.q0, c.q1) + pow(c.q2, 5) - 2 * c.tt * c.u0 + pow(c.q1, numeric(3, 2)) - pow(c.q2, -3),
      exp(-c.q0) * tanh(c.q1) + abs(c.q2 - 2) + log(c.m) + asin(c.q0 / 10) + acos(c.q1 / 10) + atan(c.q2) +
          sinh(c.q0) + cosh(c.q1) + tan(c.q2) + Pi * numeric(1, 3),
      pow(c.q0 + c.q1, 2) * s - pow(c.q0 + c.q1, -2) + 1 / sqrt(c.q2 + c.g),
  };

  // singular: A = [[q0, q1], [2 q0, 2 q1]] is singular for every x.
  symbol Y("Y");
  FunctionSpec sing;
  sing.name = "singular";
  Solve ss;
  ss.n = 2;
  ss.k = 1;
  ss.A = {c.q0, c.q1, 2 * c.q0, 2 * c.q1};
  ss.B = {1, c.q2};
  symbol Y1("Y1");
  ss.X = {Y, Y1};
  sing.steps.push_back(ss);
  sing.outputs = {Y};

  // divide: 1/q0, called with q0 = 0.
  FunctionSpec divide;
  divide.name = "divide";
  divide.outputs = {c.m / c.q0};

  mbsc::emit::GeneratedModel model;
  model.name = "e2e";
  model.source_hash = "feedface";
  model.tool_version = "0.1.0";
  model.int_constants = {{"kNx", 3}, {"kNu", 1}, {"kNp", 2}};
  model.functions = {mbsc::ir::lower(f, b), mbsc::ir::lower(sing, b), mbsc::ir::lower(divide, b)};
  const mbsc::emit::GeneratedFiles files = mbsc::emit::emit(model);
  INFO(files.source);
  REQUIRE(files.source.find("dead") == std::string::npos);

  mbsc::test::ScratchDir dir("e2e");
  mbsc::test::write_file(dir.file("e2e.hpp"), files.header);
  mbsc::test::write_file(dir.file("e2e.cpp"), files.source);
  mbsc::test::write_file(dir.file("driver.cpp"), kDriver);
  std::string log;
  const int rc = mbsc::test::run_command("cd " + dir.path().string() + " && g++ " + mbsc::test::strict_flags() +
                                             " -O1 -o driver driver.cpp e2e.cpp",
                                         log);
  INFO(log);
  REQUIRE(rc == 0);
  char args[256];
  std::snprintf(args, sizeof args, " %.17g %.17g %.17g %.17g %.17g %.17g %.17g", kT, kX[0], kX[1], kX[2], kU[0], kP[0],
                kP[1]);
  std::string out;
  REQUIRE(mbsc::test::run_command(dir.file("driver") + args, out) == 0);
  INFO(out);
  std::vector<std::string> lines;
  {
    std::istringstream in(out);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
  }
  REQUIRE(lines.size() == 4);

  // Reference: GiNaC with 30 digits; X from GiNaC's solve of the numeric system.
  const int saved_digits = Digits;
  Digits = 30;
  const exmap v = values(c);
  matrix A(3, 3), B(3, 2), Xs(3, 2);
  for (unsigned i = 0; i < 9; ++i) A(i / 3, i % 3) = solve.A[i].subs(v).subs(s == s_value.subs(v)).evalf();
  for (unsigned i = 0; i < 6; ++i) {
    B(i / 2, i % 2) = solve.B[i].subs(s == s_value).subs(v).evalf();
    Xs(i / 2, i % 2) = X[i];
  }
  const matrix Xv = A.solve(Xs, B);
  exmap all = v;
  for (unsigned i = 0; i < 6; ++i) all[X[i]] = Xv(i / 2, i % 2);
  all[s] = s_value.subs(v).evalf();
  const std::vector<double> got = parse_doubles(lines[0]);
  REQUIRE(got.size() == 6);
  CHECK(got[0] == 0.0);  // status
  for (std::size_t i = 0; i < f.outputs.size(); ++i) {
    const double ref = eval_at(f.outputs[i].subs(all), all);
    INFO("output " << i << ": generated " << got[i + 1] << ", GiNaC " << ref);
    CHECK(std::fabs(got[i + 1] - ref) <= 1e-12 * std::max(1.0, std::fabs(ref)));
  }
  Digits = saved_digits;

  CHECK(lines[1] == "1");  // the C wrapper agrees bit for bit
  CHECK(parse_doubles(lines[2]).at(0) == 1.0);  // singular solve: status 1
  const std::vector<double> div = parse_doubles(lines[3]);
  CHECK(div.at(0) == 2.0);  // m/0 = inf: status 2
}

namespace {

// Deterministic random expressions over q0..q3 and two Define'd symbols, with much sharing.
// Well conditioned, so that double evaluation must agree with GiNaC's 30 digits: trig and
// power arguments pass through tanh (bounded, derivative <= 1), exp only of sin/cos.
class RandomExpressions {
 public:
  RandomExpressions(const std::vector<ex>& leaves) : pool_(leaves) {}

  ex next(int depth) {
    if (depth == 0 || pick(6) == 0) return pool_[static_cast<std::size_t>(pick(static_cast<int>(pool_.size())))];
    ex e;
    switch (pick(8)) {
      case 0:
      case 1: {
        e = 0;
        const int n = 2 + pick(3);
        for (int i = 0; i < n; ++i) e += numeric(pick(7) - 3, 1 + pick(2)) * next(depth - 1) + (i == 0 ? ex(pick(3)) : ex(0));
        break;
      }
      case 2:
        e = tanh(next(depth - 1)) * next(depth - 1);
        break;
      case 3: {
        static const numeric exps[] = {numeric(-3), numeric(-2), numeric(-1), numeric(2), numeric(3),
                                       numeric(1, 2), numeric(-1, 2), numeric(3, 2), numeric(5)};
        const ex b = tanh(next(depth - 1));
        e = pow(1 + b * b, exps[pick(9)]);
        break;
      }
      case 4:
        e = pick(2) ? sin(tanh(next(depth - 1))) : cos(tanh(next(depth - 1)));
        break;
      case 5:
        e = exp(sin(next(depth - 1)));
        break;
      case 6:
        e = atan2(next(depth - 1), 2 + cos(tanh(next(depth - 1))));
        break;
      default:
        e = -tanh(next(depth - 1)) * next(depth - 1) + next(depth - 1) / (3 + sin(tanh(next(depth - 1))));
        break;
    }
    pool_.push_back(e);
    return e;
  }

 private:
  int pick(int n) {
    state_ = state_ * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<int>((state_ >> 33) % static_cast<unsigned long long>(n));
  }
  std::vector<ex> pool_;
  unsigned long long state_ = 12345;
};

}  // namespace

TEST_CASE("end to end: random shared expressions match GiNaC", "[emit]") {
  symbol q0("q0"), q1("q1"), q2("q2"), q3("q3"), d0("d0"), d1("d1");
  const std::vector<Binding> b = {{q0, "x[0]"}, {q1, "x[1]"}, {q2, "x[2]"}, {q3, "p[0]"}};
  RandomExpressions gen({q0, q1, q2, q3});
  FunctionSpec f;
  f.name = "g";
  const ex d0_value = gen.next(3);
  const ex d1_value = gen.next(3);
  f.steps.push_back(Define{d0, d0_value});
  f.steps.push_back(Define{d1, d1_value + d0});
  RandomExpressions gen2({q0, q1, q2, q3, d0, d1});
  const int nout = 40;
  for (int i = 0; i < nout; ++i) f.outputs.push_back(gen2.next(3));

  mbsc::emit::GeneratedModel model;
  model.name = "rnd";
  model.source_hash = "0";
  model.tool_version = "0.1.0";
  model.functions = {mbsc::ir::lower(f, b)};
  const mbsc::emit::GeneratedFiles files = mbsc::emit::emit(model);

  mbsc::test::ScratchDir dir("rnd");
  mbsc::test::write_file(dir.file("rnd.hpp"), files.header);
  mbsc::test::write_file(dir.file("rnd.cpp"), files.source);
  mbsc::test::write_file(dir.file("driver.cpp"), R"cpp(#include "rnd.hpp"
#include <cstdio>
int main() {
  const double x[3] = {0.3, -0.7, 1.1};
  const double p[1] = {0.45};
  double out[40];
  const int st = mbsc_gen::rnd::g(0.0, x, nullptr, p, out);
  std::printf("%d", st);
  for (double v : out) std::printf(" %.17g", v);
  std::printf("\n");
}
)cpp");
  std::string log;
  const int rc = mbsc::test::run_command("cd " + dir.path().string() + " && g++ " + mbsc::test::strict_flags() +
                                             " -O1 -o driver driver.cpp rnd.cpp",
                                         log);
  INFO(files.source);
  INFO(log);
  REQUIRE(rc == 0);
  std::string out;
  REQUIRE(mbsc::test::run_command(dir.file("driver"), out) == 0);
  const std::vector<double> got = parse_doubles(out);
  REQUIRE(got.size() == static_cast<std::size_t>(nout + 1));
  CHECK(got[0] == 0.0);

  const int saved_digits = Digits;
  Digits = 30;
  exmap v;
  v[q0] = numeric(0.3);
  v[q1] = numeric(-0.7);
  v[q2] = numeric(1.1);
  v[q3] = numeric(0.45);
  v[d0] = d0_value.subs(v).evalf();
  v[d1] = (d1_value + d0).subs(v).evalf();
  for (int i = 0; i < nout; ++i) {
    const double ref = eval_at(f.outputs[static_cast<std::size_t>(i)], v);
    INFO("output " << i << ": generated " << got[static_cast<std::size_t>(i) + 1] << ", GiNaC " << ref);
    CHECK(std::fabs(got[static_cast<std::size_t>(i) + 1] - ref) <= 1e-11 * (1.0 + std::fabs(ref)));
  }
  Digits = saved_digits;
}

TEST_CASE("end to end: Cholesky solve of a symmetric positive definite block", "[emit]") {
  Case c;
  const auto b = c.bindings();
  // spd: A = [[4 + q0^2, q1, 0], [q1, 3, q2], [0, q2, 5]] (diagonally dominant at the
  // driver's x), two right-hand sides; indefinite: A = [[1, 2], [2, 1]] has eigenvalue -1.
  std::vector<symbol> X;
  for (int i = 0; i < 6; ++i) X.emplace_back("X" + std::to_string(i));
  Solve s;
  s.label = "spd block";
  s.spd = true;
  s.n = 3;
  s.k = 2;
  s.A = {4 + c.q0 * c.q0, c.q1, 0, c.q1, 3, c.q2, 0, c.q2, 5};
  s.B = {1, c.m, c.q2, c.g, c.u0, c.q0 * c.q1};
  s.X = {X[0], X[1], X[2], X[3], X[4], X[5]};
  FunctionSpec spd;
  spd.name = "spd";
  spd.steps.push_back(s);
  for (const auto& x : X) spd.outputs.push_back(x);
  symbol Y0("Y0"), Y1("Y1");
  Solve bad;
  bad.spd = true;
  bad.n = 2;
  bad.k = 1;
  bad.A = {1, 2, 2, 1};
  bad.B = {c.q0, c.q1};
  bad.X = {Y0, Y1};
  FunctionSpec indefinite;
  indefinite.name = "indefinite";
  indefinite.steps.push_back(bad);
  indefinite.outputs = {Y0};

  mbsc::emit::GeneratedModel model;
  model.name = "chol";
  model.source_hash = "c0ffee";
  model.tool_version = "0.1.0";
  model.functions = {mbsc::ir::lower(spd, b), mbsc::ir::lower(indefinite, b)};
  const mbsc::emit::GeneratedFiles files = mbsc::emit::emit(model);
  REQUIRE(files.source.find("chol_solve<3, 2>(") != std::string::npos);
  REQUIRE(files.source.find("lu_solve") == std::string::npos);  // only the solver in use is emitted

  mbsc::test::ScratchDir dir("chol");
  mbsc::test::write_file(dir.file("chol.hpp"), files.header);
  mbsc::test::write_file(dir.file("chol.cpp"), files.source);
  mbsc::test::write_file(dir.file("driver.cpp"), R"cpp(#include "chol.hpp"
#include <cstdio>
int main() {
  const double x[3] = {0.3, 0.7, 1.1}, u[1] = {0.25}, p[2] = {2.0, 9.81};
  double out[6] = {0};
  int s = mbsc_gen::chol::spd(0.5, x, u, p, out);
  std::printf("%d", s);
  for (double v : out) std::printf(" %.17g", v);
  std::printf("\n%d\n", mbsc_gen::chol::indefinite(0.5, x, u, p, out));
  return 0;
}
)cpp");
  std::string log;
  REQUIRE(mbsc::test::run_command("cd " + dir.path().string() + " && g++ " + mbsc::test::strict_flags() +
                                      " -O1 -o driver driver.cpp chol.cpp",
                                  log) == 0);
  std::string out;
  REQUIRE(mbsc::test::run_command(dir.file("driver"), out) == 0);
  std::istringstream in(out);
  std::string first, second;
  std::getline(in, first);
  std::getline(in, second);
  const std::vector<double> got = parse_doubles(first);
  REQUIRE(got.size() == 7);
  CHECK(got[0] == 0.0);
  // Reference: GiNaC's exact solve of the same numeric system.
  const exmap v = values(c);
  matrix A(3, 3), B(3, 2), Xs(3, 2);
  for (unsigned i = 0; i < 9; ++i) A(i / 3, i % 3) = s.A[i].subs(v);
  for (unsigned i = 0; i < 6; ++i) {
    B(i / 2, i % 2) = s.B[i].subs(v);
    Xs(i / 2, i % 2) = X[i];
  }
  const matrix Xv = A.solve(Xs, B);
  for (unsigned i = 0; i < 6; ++i) {
    const double ref = ex_to<numeric>(Xv(i / 2, i % 2).evalf()).to_double();
    CHECK(std::fabs(got[i + 1] - ref) <= 1e-13 * std::max(1.0, std::fabs(ref)));
  }
  CHECK(second == "1");  // not positive definite: status 1
}
