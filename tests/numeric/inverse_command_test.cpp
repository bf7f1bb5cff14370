// SPDX-License-Identifier: GPL-2.0-or-later
// The core of `mbsc inverse` (src/run/inverse_command.cpp) on compiled models: the
// prescribed expressions, differentiated symbolically, give the same inputs as the
// runtime driven by hand-differentiated closed forms; bad options are clear errors.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "../../src/run/inverse_command.hpp"
#include "mbsc/runtime/inverse_dynamics.hpp"
#include "test_support.hpp"
#include "three_rrr/three_rrr.hpp"
#include "three_rrr_mult/three_rrr_mult.hpp"
#include "whitworth/whitworth.hpp"

using mbsc::run::InverseCommandOptions;
using mbsc::run::inverse_command;
using mbsc::runtime::ModelTable;

namespace {

constexpr double kPi = 3.14159265358979323846;

InverseCommandOptions three_rrr_options() {
  InverseCommandOptions o;
  o.prescribe = {{"platform.x", "-sin(pi*t/2)"}, {"platform.y", "sin(pi*t/4)"}, {"platform.theta", "pi/6*sin(pi*t/4)^4"}};
  o.unknowns = {"u1", "u2", "u3"};
  // The thesis's elbows (tests/numeric/inverse_dynamics_test.cpp).
  o.guess = {{"HA.proximal.theta", 2.0}, {"HB.proximal.theta", 3.8}, {"HC.proximal.theta", 6.0},
             {"HA.distal.theta", 1.0},   {"HB.distal.theta", 3.1},   {"HC.distal.theta", 5.2},
             {"HA.proximal.x", 3.0},     {"HB.proximal.x", -1.5},    {"HC.proximal.x", -1.5},
             {"HB.proximal.y", 1.5 * std::sqrt(3.0)}, {"HC.proximal.y", -1.5 * std::sqrt(3.0)}};
  o.t_end = 4.0;
  o.dt_out = 0.05;
  return o;
}

int column(const mbsc::run::InverseTable& t, const std::string& name) {
  for (std::size_t i = 0; i < t.columns.size(); ++i)
    if (t.columns[i] == name) return static_cast<int>(i);
  FAIL("no column " << name);
  return -1;
}

}  // namespace

TEST_CASE("mbsc inverse core: symbolic derivatives of the prescription match closed forms", "[numeric][inverse]") {
  namespace R = mbsc_gen::three_rrr;
  const ModelTable m = MBSC_MODEL_TABLE(R);
  const auto out = inverse_command(m, three_rrr_options(), "three_rrr.mbs");
  INFO(out.message);
  REQUIRE(out.exit_code == 0);
  REQUIRE(out.table.rows.size() == 81);
  REQUIRE(out.table.columns.size() == static_cast<std::size_t>(1 + R::kNx + R::kNin));

  // The same run through the runtime with the derivatives written by hand.
  auto ix = [](const char* n) { return mbsc_test::index_of(R::kStateNames, R::kNx, n); };
  const double w2 = kPi / 2, w4 = kPi / 4;
  std::vector<mbsc::runtime::Prescription> pres = {
      {ix("platform.x"), [=](double t, double& q, double& qd, double& qdd) {
         q = -std::sin(w2 * t), qd = -w2 * std::cos(w2 * t), qdd = w2 * w2 * std::sin(w2 * t);
       }},
      {ix("platform.y"), [=](double t, double& q, double& qd, double& qdd) {
         q = std::sin(w4 * t), qd = w4 * std::cos(w4 * t), qdd = -w4 * w4 * std::sin(w4 * t);
       }},
      {ix("platform.theta"), [=](double t, double& q, double& qd, double& qdd) {
         const double s = std::sin(w4 * t), c = std::cos(w4 * t), a = kPi / 6;
         q = a * s * s * s * s, qd = 4 * a * w4 * s * s * s * c, qdd = a * w4 * w4 * (12 * s * s * c * c - 4 * s * s * s * s);
       }}};
  mbsc::runtime::InverseDynamics inv(m, pres, {0, 1, 2}, std::vector<double>(R::kParamDefaults, R::kParamDefaults + R::kNp));
  std::vector<double> x(R::kNx, 0.0);
  for (const auto& [n, v] : three_rrr_options().guess) x[static_cast<std::size_t>(ix(n.c_str()))] = v;
  const int u1 = column(out.table, "u1");
  for (const auto& row : out.table.rows) {
    mbsc::runtime::InverseSample s;
    REQUIRE(inv.solve(row[0], x, s));
    for (int i = 0; i < R::kNx; ++i) CHECK(row[static_cast<std::size_t>(1 + i)] == Approx(s.x[static_cast<std::size_t>(i)]).margin(1e-10));
    for (int k = 0; k < 3; ++k) CHECK(row[static_cast<std::size_t>(u1 + k)] == Approx(s.inputs[static_cast<std::size_t>(k)]).margin(1e-9));
  }
}

TEST_CASE("mbsc inverse core: multipliers form adds reaction columns; CSV written", "[numeric][inverse]") {
  const ModelTable m = MBSC_MODEL_TABLE_MULTIPLIERS(mbsc_gen::three_rrr_mult);
  auto o = three_rrr_options();
  o.t_end = 1.0;
  o.dt_out = 0.25;
  o.output_csv = "inverse_command_test_out.csv";
  std::remove(o.output_csv.c_str());
  const auto out = inverse_command(m, o, "three_rrr.mbs");
  INFO(out.message);
  REQUIRE(out.exit_code == 0);
  REQUIRE(out.table.rows.size() == 5);
  CHECK(column(out.table, "reaction:platform.w") > 0);
  std::ifstream in(o.output_csv);
  std::stringstream text;
  text << in.rdbuf();
  CHECK(text.str() == mbsc::run::inverse_csv(out.table));
  CHECK(text.str().rfind("t,HA.proximal.x,", 0) == 0);
  std::remove(o.output_csv.c_str());
}

TEST_CASE("mbsc inverse core: the Whitworth line of the README", "[numeric][inverse]") {
  const ModelTable m = MBSC_MODEL_TABLE(mbsc_gen::whitworth);
  InverseCommandOptions o;
  o.prescribe = {{"crank.theta", "pi/4 + pi/2*t"}};
  o.unknowns = {"u1"};
  o.guess = {{"slider.x", 0.7}, {"rocker.theta", 1.3}, {"rod.theta", 3.4}};  // as docs/inverse_dynamics.md shows
  o.dt_out = 0.01;
  o.t_end = 16.0;
  const auto out = inverse_command(m, o, "whitworth.mbs");
  INFO(out.message);
  REQUIRE(out.exit_code == 0);
  CHECK(out.table.rows.front()[static_cast<std::size_t>(column(out.table, "slider.x"))] == Approx(0.8).margin(1e-9));
  CHECK(out.table.rows.back()[0] == 16.0);
}

TEST_CASE("mbsc inverse core: bad options are clear errors", "[numeric][inverse]") {
  const ModelTable m = MBSC_MODEL_TABLE(mbsc_gen::three_rrr);
  auto run = [&](InverseCommandOptions o) {
    o.output_csv = "inverse_command_test_bad.csv";
    std::remove(o.output_csv.c_str());
    auto out = inverse_command(m, o, "three_rrr.mbs");
    CHECK(out.exit_code == 1);
    CHECK_FALSE(std::ifstream(o.output_csv).good());  // nothing written
    return out.message;
  };
  auto o = three_rrr_options();
  o.prescribe[0].first = "platform.xx";
  CHECK_THAT(run(o), Catch::Contains("no coordinate 'platform.xx'") && Catch::Contains("platform.x"));
  o = three_rrr_options();
  o.prescribe[0].first = "platform.u";
  CHECK_THAT(run(o), Catch::Contains("it is a speed"));
  o = three_rrr_options();
  o.prescribe.pop_back();
  CHECK_THAT(run(o), Catch::Contains("exactly 3 coordinate(s)"));
  o = three_rrr_options();
  o.prescribe[1].second = "sin(pi*tt/4)";
  CHECK_THAT(run(o), Catch::StartsWith("--prescribe platform.y: error: 'sin(pi*tt/4)': column 8: unknown name 'tt'"));
  o = three_rrr_options();
  o.prescribe[1].second = "sin(pi*t/4";
  CHECK_THAT(run(o), Catch::StartsWith("--prescribe platform.y"));
  o = three_rrr_options();
  o.prescribe[1].second = "sinn(t)";
  CHECK_THAT(run(o), Catch::Contains("unknown function 'sinn'"));
  o = three_rrr_options();
  o.prescribe[1].second = "1\noutput y = 2";
  CHECK_THAT(run(o), Catch::Contains("expected the end of the expression"));
  o = three_rrr_options();
  o.unknowns = {"u1", "u4"};
  CHECK_THAT(run(o), Catch::Contains("no input 'u4'"));
  o = three_rrr_options();
  o.params = {{"m9", 1.0}};
  CHECK_THAT(run(o), Catch::Contains("no parameter 'm9'"));
  // A parameter in the expression is read with its --set value.
  o = three_rrr_options();
  o.prescribe[0].second = "-m1*sin(pi*t/2)";
  o.params = {{"m1", 1.0}};
  o.t_end = 0.1;
  CHECK(inverse_command(m, o, "three_rrr.mbs").exit_code == 0);
}

TEST_CASE("mbsc inverse core: a prescription undefined where it is evaluated is a bad option", "[numeric][inverse]") {
  // Every output time is evaluated before the solve: the motion, its first and second
  // derivatives must be finite there, or the option is refused (exit 1, nothing written)
  // naming the coordinate and the time; never an internal error or a NaN row.
  const ModelTable m = MBSC_MODEL_TABLE(mbsc_gen::three_rrr);
  struct Case {
    const char* expr;
    double t_start, t_end, dt_out;
    const char* expect;
  } cases[] = {
      {"log(t)", 0.0, 1.0, 0.1, "'log(t)': it is not finite at t = 0 (-inf)"},
      {"t^t^t", 0.0, 1.0, 0.1, "its first derivative is not finite at t = 0"},
      // Exact powers are guarded, not computed digit by digit: 10^(10^10).
      {"t^t^t", 10.0, 11.0, 0.5, "it is not finite at t = 10 (inf)"},
      {"t^t^t", 1.0, 5.0, 0.5, "it is not finite at t = 4.5 (inf)"},
      // abs is differentiable but at its kink, where an output time falls here.
      {"abs(t-1)", 0.0, 2.0, 0.5, "its first derivative is not finite at t = 1 (nan)"},
      {"sqrt(t)", 0.0, 1.0, 0.1, "its first derivative is not finite at t = 0 (inf)"},
      {"sqrt(t)^3", 0.0, 1.0, 0.1, "its second derivative is not finite at t = 0"},
      {"exp(exp(exp(5*t)))", 0.0, 1.0, 0.125, "it is not finite at t = 0.5 (inf)"},
  };
  for (const auto& k : cases) {
    auto o = three_rrr_options();
    o.prescribe[0].second = k.expr;
    o.t_start = k.t_start;
    o.t_end = k.t_end;
    o.dt_out = k.dt_out;
    o.output_csv = "inverse_command_test_undefined.csv";
    std::remove(o.output_csv.c_str());
    const auto out = inverse_command(m, o, "three_rrr.mbs");
    INFO(k.expr << ": " << out.message);
    CHECK(out.exit_code == 1);
    CHECK_THAT(out.message, Catch::StartsWith("--prescribe platform.x: error: ") && Catch::Contains(k.expect));
    CHECK(out.table.rows.empty());
    CHECK_FALSE(std::ifstream(o.output_csv).good());
  }
  // Away from its kink abs is differentiable: the grid 0, 0.3, 0.6 misses t = 0.5.
  auto o = three_rrr_options();
  o.prescribe[0].second = "-sin(pi*t/2) + abs(t - 0.5)/100";
  o.t_end = 0.6;
  o.dt_out = 0.3;
  const auto out = inverse_command(m, o, "three_rrr.mbs");
  INFO(out.message);
  CHECK(out.exit_code == 0);
  CHECK(out.table.rows.size() == 3);
}
