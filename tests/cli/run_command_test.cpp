// SPDX-License-Identifier: GPL-2.0-or-later
// `mbsc run` and `mbsc bench` as a user calls them: the CSV against the physics (the
// constraint and energy along the run), the cache, the initial state from the model and
// from --init, and every bad input of issue 10 (exit 1, nothing written) or numerical
// failure (exit 2, the rows up to it kept in a temporary file the message names).
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>

#include "run_command.hpp"

namespace fs = std::filesystem;
using namespace mbsc_test;

namespace {

const std::string kMbsc = MBSC_BINARY;


/// A pendulum on a rod of length l: the bob's Cartesian coordinates tied to the angle.
const char* kPendulum =
    "model pend\nparameter l = 1.5, m = 2, g = 9.81\ngravity (0, -g)\n"
    "body b : particle2d { mass m }\nsubsystem arm {\n  coordinate th\n  speed w = th'\n}\n"
    "constraint position { b.x - l*sin(arm.th) = 0; b.y + l*cos(arm.th) = 0 }\n"
    "independent arm.w\ninitial arm.th = 2.5\noutput angle = arm.th\noutput energy\n";

struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  int col(const std::string& name) const {
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return static_cast<int>(i);
    return -1;
  }
};

Csv read_csv(const fs::path& p) {
  Csv c;
  std::ifstream in(p);
  std::string line;
  while (std::getline(in, line)) {
    std::stringstream s(line);
    std::string cell;
    if (c.header.empty()) {
      while (std::getline(s, cell, ',')) c.header.push_back(cell);
    } else {
      std::vector<double> r;
      while (std::getline(s, cell, ',')) r.push_back(std::stod(cell));
      c.rows.push_back(r);
    }
  }
  return c;
}

std::string run_in(const fs::path& dir, const std::string& args) {
  return kMbsc + " " + args + " --cache-dir " + quote((dir / "cache").string());
}

}  // namespace

TEST_CASE("mbsc run: the CSV follows the constraints and conserves energy; the cache skips the compiler",
          "[cli][run]") {
  const fs::path dir = fresh_dir("run");
  write(dir / "pend.mbs", kPendulum);
  auto r = run(run_in(dir, "run " + quote((dir / "pend.mbs").string()) + " --t-end 3 --dt-out 0.01 --rtol 1e-10 -o " +
                               quote((dir / "out.csv").string())));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("compiled pend") != std::string::npos);
  CHECK(r.output.find("energy change") != std::string::npos);
  const Csv c = read_csv(dir / "out.csv");
  REQUIRE(c.rows.size() == 301);
  const int t = c.col("t"), th = c.col("arm.th"), bx = c.col("b.x"), by = c.col("b.y"), e = c.col("energy");
  REQUIRE((t == 0 && th > 0 && bx > 0 && by > 0 && e > 0));
  CHECK(c.rows.front()[static_cast<std::size_t>(th)] == 2.5);  // the model's `initial`
  CHECK(c.rows.back()[static_cast<std::size_t>(t)] == Approx(3.0));
  double worst_constraint = 0, worst_energy = 0;
  const double e0 = c.rows.front()[static_cast<std::size_t>(e)];
  CHECK(e0 == Approx(2 * 9.81 * -1.5 * std::cos(2.5)));  // at rest: potential m g y only
  for (const auto& row : c.rows) {
    worst_constraint = std::max(worst_constraint, std::fabs(row[static_cast<std::size_t>(bx)] -
                                                            1.5 * std::sin(row[static_cast<std::size_t>(th)])));
    worst_energy = std::max(worst_energy, std::fabs(row[static_cast<std::size_t>(e)] - e0));
  }
  CHECK(worst_constraint < 1e-8);
  CHECK(worst_energy < 1e-7 * std::fabs(e0));
  // The pendulum swings through the bottom: the angle changes sign.
  double lo = 10;
  for (const auto& row : c.rows) lo = std::min(lo, row[static_cast<std::size_t>(th)]);
  CHECK(lo < -2.0);
  // Same model, other options of the run only: no compilation; --init wins over `initial`.
  r = run(run_in(dir, "run " + quote((dir / "pend.mbs").string()) + " --t-end 0.1 --init arm.th=pi/2 --set l=2 -o " +
                           quote((dir / "out2.csv").string())));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("compiled") == std::string::npos);
  const Csv c2 = read_csv(dir / "out2.csv");
  CHECK(c2.rows.front()[static_cast<std::size_t>(c2.col("arm.th"))] == Approx(M_PI / 2));
  CHECK(c2.rows.front()[static_cast<std::size_t>(c2.col("b.x"))] == Approx(2.0));  // assembled with l = 2
  fs::remove_all(dir);
}

TEST_CASE("mbsc run --state minimal and --formulation multipliers follow the same motion", "[cli][run]") {
  const fs::path dir = fresh_dir("run_forms");
  write(dir / "pend.mbs", kPendulum);
  const std::string base = "run " + quote((dir / "pend.mbs").string()) + " --t-end 2 --rtol 1e-11 --atol 1e-13 -q";
  auto full = run(run_in(dir, base + " -o " + quote((dir / "full.csv").string())));
  auto minimal = run(run_in(dir, base + " --state minimal -o " + quote((dir / "min.csv").string())));
  auto mult = run(run_in(dir, base + " --formulation multipliers -o " + quote((dir / "mult.csv").string())));
  INFO(full.output << minimal.output << mult.output);
  REQUIRE((full.exit_code == 0 && minimal.exit_code == 0 && mult.exit_code == 0));
  const Csv a = read_csv(dir / "full.csv"), b = read_csv(dir / "min.csv"), c = read_csv(dir / "mult.csv");
  REQUIRE(a.header == b.header);  // the minimal run's CSV shows every coordinate and speed too
  REQUIRE(a.header == c.header);
  REQUIRE((a.rows.size() == b.rows.size() && a.rows.size() == c.rows.size()));
  for (const char* name : {"arm.th", "arm.w", "b.x", "b.v"}) {
    const auto k = static_cast<std::size_t>(a.col(name));
    INFO(name);
    CHECK(b.rows.back()[k] == Approx(a.rows.back()[k]).margin(1e-7));
    CHECK(c.rows.back()[k] == Approx(a.rows.back()[k]).margin(1e-6));
  }
  fs::remove_all(dir);
}

TEST_CASE("mbsc run: a plot and chosen columns", "[cli][run]") {
  const fs::path dir = fresh_dir("run_plot");
  write(dir / "pend.mbs", kPendulum);
  auto r = run(run_in(dir, "run " + quote((dir / "pend.mbs").string()) + " --t-end 1 --columns arm.th,energy -o " +
                               quote((dir / "o.csv").string()) + " --plot " + quote((dir / "p.svg").string())));
  INFO(r.output);
  if (r.output.find("gnuplot is needed") != std::string::npos) {
    WARN("gnuplot not installed: plot check skipped");
    return;
  }
  REQUIRE(r.exit_code == 0);
  const Csv c = read_csv(dir / "o.csv");
  CHECK(c.header == std::vector<std::string>{"t", "arm.th", "energy"});
  std::ifstream svg(dir / "p.svg");
  std::stringstream s;
  s << svg.rdbuf();
  CHECK(s.str().find("<svg") != std::string::npos);
  CHECK(s.str().find("energy") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("mbsc run: bad input is exit 1 with nothing written", "[cli][run]") {
  const fs::path dir = fresh_dir("run_bad");
  write(dir / "pend.mbs", kPendulum);
  const std::string model = quote((dir / "pend.mbs").string());
  const std::string csv = quote((dir / "x.csv").string());
  struct Case {
    std::string args, expect;
  } cases[] = {
      {"--init arm.thx=1", "no coordinate or speed named 'arm.thx' (did you mean 'arm.th'?)"},
      {"--set ll=1", "no parameter named 'll' (did you mean 'l'?) (its parameters: l, m and g)"},
      {"--init th=1", "no coordinate or speed named 'th' (did you mean 'arm.th'?)"},
      {"--init b.x=5", "position constraint"},  // |b| = 5 on a rod of 1.5
      {"--set l=abc", "--set l"},
      {"--integrator dopri", "unknown method 'dopri' (did you mean 'dopri5'?)"},
      {"--input f=t", "no input named 'f'"},
      {"--t-end -1", "--t-end"},
      {"--plot x.pdf", ".svg or .png"},
      {"--columns t,angl", "no column named 'angl' (did you mean 'angle'?)"},
      {"--dt-out 0", "--dt-out"},
      {"--dt-out nan", "--dt-out"},
      {"--rtol 1e-20", "--rtol"},
      {"--init arm.th=1 --init arm.th=2", "given twice"},
  };
  for (const auto& c : cases) {
    auto r = run(run_in(dir, "run " + model + " -o " + csv + " " + c.args));
    INFO(c.args << "\n" << r.output);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find(c.expect) != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "x.csv"));
  }
  {
    const std::string same = quote((dir / "same.svg").string());
    auto r = run(run_in(dir, "run " + model + " -o " + same + " --plot " + same));
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("name the same file") != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "same.svg"));
  }
  // Never the model file (also through a link), never a folder.
  const std::string before = [&] {
    std::ifstream in(dir / "pend.mbs");
    std::stringstream t;
    t << in.rdbuf();
    return t.str();
  }();
  fs::create_symlink(dir / "pend.mbs", dir / "link.csv");
  for (const std::string& target : {model, quote((dir / "link.csv").string()), quote(dir.string())}) {
    auto r = run(run_in(dir, "run " + model + " -o " + target));
    INFO(target << "\n" << r.output);
    CHECK(r.exit_code == 1);
    CHECK((r.output.find("will not overwrite") != std::string::npos || r.output.find("is a folder") != std::string::npos));
  }
  for (const char* cmd : {"bench", "inverse"}) {
    auto r = run(run_in(dir, std::string(cmd) + " " + model + " --prescribe arm.th=t -o " + model));
    INFO(r.output);
    CHECK(r.exit_code == 1);
  }
  {
    std::ifstream in(dir / "pend.mbs");
    std::stringstream t;
    t << in.rdbuf();
    CHECK(t.str() == before);
  }
  // A compiler that hangs is stopped by the budget (and a model text the cache lacks).
  write(dir / "hang.sh", "#!/bin/sh\nif [ \"$1\" = --version ]; then echo hang 1; exit 0; fi\nsleep 600\n");
  fs::permissions(dir / "hang.sh", fs::perms::owner_all);
  write(dir / "pend3.mbs", std::string(kPendulum) + "# a third text\n");
  auto hang = run("MBSC_CXX=" + quote((dir / "hang.sh").string()) + " " +
                  run_in(dir, "run " + quote((dir / "pend3.mbs").string()) + " --budget 3 -o " + csv));
  INFO(hang.output);
  CHECK(hang.exit_code == 1);
  CHECK(hang.output.find("time budget") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "x.csv"));
  // An unwritable output path.
  auto r = run(run_in(dir, "run " + model + " -o " + quote((dir / "no" / "such" / "x.csv").string())));
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("cannot write") != std::string::npos);
  // A model with an error: file:line:col, exit 1.
  write(dir / "bad.mbs", "model bad\nparameter m = 1\nbody b : particle2d { mass mm }\n");
  r = run(run_in(dir, "run " + quote((dir / "bad.mbs").string()) + " -o " + csv));
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("bad.mbs:3:") != std::string::npos);
  // A compiler that fails (another model text, so the cache cannot serve it).
  write(dir / "pend2.mbs", std::string(kPendulum) + "# another text\n");
  r = run("CXX=false " + run_in(dir, "run " + quote((dir / "pend2.mbs").string()) + " -o " + csv));
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("compiler") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "x.csv"));
  fs::remove_all(dir);
}

TEST_CASE("mbsc run: a quaternion starts at unit norm or at the identity, never at zero", "[cli][run]") {
  // A quaternion's scale is no rotation: --init b.e0=2 (with the model's e1 = e2 = e3 = 0)
  // starts the body level, e = (1, 0, 0, 0), and says so; all four given as zero is no
  // attitude; none given is the identity.
  const fs::path dir = fresh_dir("run_quaternion");
  const std::string model = quote(std::string(MBSC_SOURCE_DIR) + "/models/free_body_quaternion.mbs");
  const std::string csv = quote((dir / "q.csv").string());
  auto r = run(run_in(dir, "run " + model + " --t-end 0.1 -o " + csv + " --init b.e0=2"));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("b.e0, b.e1, b.e2, b.e3 (norm 2) starts off unit norm") != std::string::npos);
  const Csv c = read_csv(dir / "q.csv");
  REQUIRE(c.col("b.e0") >= 0);
  REQUIRE_FALSE(c.rows.empty());
  CHECK(c.rows[0][static_cast<std::size_t>(c.col("b.e0"))] == 1.0);
  r = run(run_in(dir, "run " + model + " -o " + quote((dir / "z.csv").string()) + " --init b.e0=0"));
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("the quaternion (b.e0, b.e1, b.e2, b.e3) is all zero at the start") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "z.csv"));
  // A quaternion that nothing gives starts at the identity.
  write(dir / "spin.mbs", "model spin\nbody b : rigid3d {\n  mass 1\n  inertia (1, 2, 3)\n}\ninitial b.wx = 1\n");
  r = run(run_in(dir, "run " + quote((dir / "spin.mbs").string()) + " --t-end 0.1 -o " + quote((dir / "s.csv").string())));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const Csv spin = read_csv(dir / "s.csv");
  REQUIRE(spin.col("b.e0") >= 0);
  REQUIRE_FALSE(spin.rows.empty());
  CHECK(spin.rows[0][static_cast<std::size_t>(spin.col("b.e0"))] == 1.0);
  CHECK(spin.rows[0][static_cast<std::size_t>(spin.col("b.e1"))] == 0.0);
  fs::remove_all(dir);
}

TEST_CASE("mbsc run: a numerical failure is exit 2 and keeps the rows before it", "[cli][run]") {
  const fs::path dir = fresh_dir("run_fail");
  // A force that blows up at t = 0.5.
  write(dir / "push.mbs", "model push\nparameter m = 1\ninput f\nbody b : particle2d { mass m }\nforce b.u : f\n");
  auto r = run(run_in(dir, "run " + quote((dir / "push.mbs").string()) + " --t-end 1 --dt-out 0.01 --input 'f=1/(t-0.5)^2' -o " +
                               quote((dir / "f.csv").string())));
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("the run failed at t = ") != std::string::npos);
  // The destination is not written; the rows up to the failure are in the temporary
  // file the message names.
  CHECK_FALSE(fs::exists(dir / "f.csv"));
  const auto at = r.output.find("are in ");
  REQUIRE(at != std::string::npos);
  const Csv c = read_csv(r.output.substr(at + 7, r.output.find('\n', at) - at - 7));
  CHECK(c.rows.size() >= 40);
  CHECK(c.rows.size() <= 51);
  fs::remove_all(dir);
}

TEST_CASE("mbsc bench: errors against the reference shrink with the tolerance", "[cli][run]") {
  const fs::path dir = fresh_dir("bench");
  write(dir / "pend.mbs", kPendulum);
  auto r = run(run_in(dir, "bench " + quote((dir / "pend.mbs").string()) +
                               " --t-end 2 --integrators dopri5 --tolerances 1e-5,1e-9 --min-cpu 0.001 -o " +
                               quote((dir / "b.csv").string())));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  std::ifstream in(dir / "b.csv");
  std::string header, line;
  std::getline(in, header);
  CHECK(header.find("err_final") != std::string::npos);
  std::vector<std::pair<std::string, double>> errors;  // formulation, final error
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream s(line);
    std::string cell;
    while (std::getline(s, cell, ',')) cells.push_back(cell);
    REQUIRE(cells.size() >= 14);
    CHECK(cells[13] == "ok");
    errors.emplace_back(cells[2], std::stod(cells[8]));
  }
  REQUIRE(errors.size() == 4);  // 2 formulations x 2 tolerances
  for (std::size_t k = 0; k < 4; k += 2) {
    INFO(errors[k].first);
    CHECK(errors[k].second < 1e-2);
    CHECK(errors[k + 1].second < errors[k].second / 100);  // 1e-4 tighter: much smaller error
  }
  fs::remove_all(dir);
}

TEST_CASE("mbsc inverse: the thesis's Whitworth run from the command line, and its bad input", "[cli][run]") {
  const fs::path dir = fresh_dir("inverse");
  const std::string model = quote(std::string(MBSC_SOURCE_DIR) + "/models/whitworth.mbs");
  auto r = run(run_in(dir, "inverse " + model + " --prescribe 'crank.theta=pi/4 + pi/2*t' --unknowns u1 --t-end 4 "
                                               "--dt-out 0.05 -o " + quote((dir / "si.csv").string())));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const Csv c = read_csv(dir / "si.csv");
  REQUIRE(c.rows.size() == 81);
  const auto th = static_cast<std::size_t>(c.col("crank.theta")), w = static_cast<std::size_t>(c.col("crank.w")),
             x = static_cast<std::size_t>(c.col("slider.x")), u1 = static_cast<std::size_t>(c.col("u1"));
  double peak = 0;
  for (const auto& row : c.rows) {
    CHECK(row[th] == Approx(M_PI / 4 + M_PI / 2 * row[0]).margin(1e-9));
    CHECK(row[w] == Approx(M_PI / 2).margin(1e-9));
    peak = std::max(peak, std::fabs(row[u1]));
  }
  CHECK(c.rows.front()[x] == Approx(0.8).margin(1e-9));  // the thesis's start, from the model's guesses
  CHECK(peak > 0.5);  // the quick return's torque peaks (about 1 N m)
  struct Case {
    std::string args, expect;
  } cases[] = {
      {"--prescribe 'crank.thetax=t'", "crank.thetax"},
      {"--prescribe 'crank.theta=t' --prescribe 'rocker.theta=t'", "degree(s) of freedom"},
      {"--prescribe 'crank.theta=t' --unknowns u2", "u2"},
      {"--prescribe 'crank.theta=t*tt'", "tt"},
      {"", "--prescribe"},
      // Undefined, or not twice differentiable, at an output time: a bad option, not an
      // internal error or a NaN row (tests/numeric/inverse_command_test.cpp has more).
      {"--prescribe 'crank.theta=log(t)' --unknowns u1", "--prescribe crank.theta: error: 'log(t)': it is not finite at t = 0"},
      {"--prescribe 'crank.theta=abs(t-1)' --unknowns u1 --dt-out 0.25", "its first derivative is not finite at t = 1"},
      {"--prescribe 'crank.theta=t^t^t' --unknowns u1", "is not finite at t = 0"},
  };
  for (const auto& k : cases) {
    r = run(run_in(dir, "inverse " + model + " " + k.args + " -o " + quote((dir / "bad.csv").string())));
    INFO(k.args << "\n" << r.output);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find(k.expect) != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "bad.csv"));
  }
  // A forcing not affine in its input (u1^2): several inputs give one motion; refused.
  r = run(run_in(dir, "inverse " + quote(std::string(MBSC_SOURCE_DIR) + "/tests/data/inverse/input_squared.mbs") +
                          " --prescribe 's.x=t' -o " + quote((dir / "bad.csv").string())));
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("is not affine in its inputs") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "bad.csv"));
  fs::remove_all(dir);
}

TEST_CASE("mbsc inverse: Coulomb friction closed in the rhs (thesis Ex 4.5)", "[cli][inverse]") {
  // The thesis's prescribed slide; the torque and the friction are solved together
  // (tests/numeric/slider_crank_3d_test.cpp checks them against a closure outside the
  // generated code). Here: the command takes the model, keeps the quaternions unit while
  // it assembles, and the torque jumps where the slider reverses (t = 1/4).
  const fs::path dir = fresh_dir("inverse_friction");
  const std::string model = quote(std::string(MBSC_SOURCE_DIR) + "/models/slider_crank_3d.mbs");
  const std::string branch = " --init crank.e0=0.95 --init crank.e1=0.3";  // the crank's angle > 0
  auto r = run(run_in(dir, "inverse " + model + " --prescribe 'slider.x=l2-(1-gamma2)*l2*(1+8*sin(2*pi*t)^2)/10'" + branch +
                               " --t-end 0.5 --dt-out 0.01 -q -o " + quote((dir / "f.csv").string())));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const Csv c = read_csv(dir / "f.csv");
  REQUIRE(c.rows.size() == 51);
  const auto u1 = static_cast<std::size_t>(c.col("u1"));
  const auto e0 = static_cast<std::size_t>(c.col("crank.e0")), e1 = static_cast<std::size_t>(c.col("crank.e1"));
  for (const auto& row : c.rows) {
    CHECK(row[e0] * row[e0] + row[e1] * row[e1] == Approx(1.0).margin(1e-12));
    CHECK(std::isfinite(row[u1]));
  }
  // Either side of the reversal the friction turns round: the torque, extrapolated to
  // t = 1/4 from each side, jumps by what the closure outside the generated code gives
  // there (-49.3 -> -58.4 N m, tests/numeric/slider_crank_3d_test.cpp), within the
  // extrapolation's error.
  const double left = 2 * c.rows[24][u1] - c.rows[23][u1], right = 2 * c.rows[26][u1] - c.rows[27][u1];
  CHECK(left - right == Approx(58.4 - 49.3).margin(0.5));
  // Held at rest, the friction may be anything up to mu |N|: the inputs are not determined.
  r = run(run_in(dir, "inverse " + model + " --prescribe 'slider.x=1.3'" + branch + " --t-end 0.5 -o " +
                          quote((dir / "rest.csv").string())));
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("holds joint 'guide' at rest") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "rest.csv"));
  fs::remove_all(dir);
}

TEST_CASE("mbsc run --continuation: the parallelogram chain through its flat poses stays a parallelogram",
          "[cli][run]") {
  // The shipped chain starts off its flat pose at 12 rad/s: about 40 flat poses in 20 s.
  // Without continuation the run leaves the branch (the cranks stop being parallel).
  const fs::path dir = fresh_dir("run_chain");
  const std::string model = quote(std::string(MBSC_SOURCE_DIR) + "/models/parallelogram_chain.mbs");
  for (const char* tol : {"1e-7", "1e-9"}) {
    auto r = run(run_in(dir, "run " + model + " --t-end 20 --continuation -q --rtol " + tol + " -o " +
                                 quote((dir / "c.csv").string())));
    INFO(tol << "\n" << r.output);
    REQUIRE(r.exit_code == 0);
    const Csv c = read_csv(dir / "c.csv");
    std::vector<std::size_t> cranks;
    for (std::size_t k = 0; k < c.header.size(); ++k)
      if (c.header[k].rfind("crank_", 0) == 0 && c.header[k].size() > 6 &&
          c.header[k].substr(c.header[k].size() - 6) == ".theta")
        cranks.push_back(k);
    REQUIRE(cranks.size() == 4);
    const auto e = static_cast<std::size_t>(c.col("energy"));
    const double e0 = c.rows.front()[e];
    double parallel = 0, drift = 0, turned = 0;
    for (const auto& row : c.rows) {
      for (auto k : cranks) parallel = std::max(parallel, std::fabs(row[k] - row[cranks[0]]));
      drift = std::max(drift, std::fabs(row[e] - e0));
      turned = std::max(turned, std::fabs(row[cranks[0]] - c.rows.front()[cranks[0]]));
    }
    CHECK(turned > 40 * M_PI);  // over the top about 40 times: through every flat pose
    CHECK(parallel < 1e-4);
    CHECK(drift < 1e-3 * std::fabs(e0));
  }
  fs::remove_all(dir);
}

TEST_CASE("mbsc run keeps a rigid3d body's quaternion at unit norm, unless --projection off", "[cli][run]") {
  // |e| = 1 is an invariant of the kinematics only: the integrator's error moves it step
  // after step. With the normalization the drift stays one step's error; without it, it
  // grows over the 200 s run (measured: 2e-6 against 2.9e-5 at rtol 1e-6).
  const fs::path dir = fresh_dir("run_quaternion");
  const std::string model = quote(std::string(MBSC_SOURCE_DIR) + "/models/free_body_quaternion.mbs");
  double end_drift[2] = {0.0, 0.0};
  for (int off = 0; off < 2; ++off) {
    const fs::path csv = dir / (off ? "off.csv" : "on.csv");
    auto r = run(run_in(dir, "run " + model + " --t-end 200 --rtol 1e-6 --atol 1e-8 -q -o " + quote(csv.string()) +
                                 (off ? " --projection off" : "")));
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    const Csv c = read_csv(csv);
    const int n = c.col("quaternion_norm");
    REQUIRE(n >= 0);
    REQUIRE(c.rows.size() > 100);
    double worst = 0.0;
    for (const auto& row : c.rows) worst = std::max(worst, std::fabs(row[static_cast<std::size_t>(n)] - 1.0));
    end_drift[off] = std::fabs(c.rows.back()[static_cast<std::size_t>(n)] - 1.0);
    if (!off) CHECK(worst < 1e-5);
  }
  INFO("|e| - 1 at t = 200 s: " << end_drift[0] << " normalized, " << end_drift[1] << " free");
  CHECK(end_drift[0] < 1e-6);
  CHECK(end_drift[1] > 10.0 * end_drift[0]);
}

TEST_CASE("mbsc run --integrator bdf: a stiff constrained model to its tolerance, on its manifold", "[cli][run]") {
  // tests/data/stiff/stiff_pendulums.mbs: two pendulums in absolute coordinates tied by a
  // spring of 8e5 N/m and a damper of 4e4 N s/m. BDF projects inside CVODE (issue 26,
  // item 3): its final error follows rtol, and rtol 1e-12 no longer collapses the step.
  const fs::path dir = fresh_dir("stiff_bdf");
  const std::string model = quote(std::string(MBSC_SOURCE_DIR) + "/tests/data/stiff/stiff_pendulums.mbs");
  auto r = run(run_in(dir, "run " + model + " --t-end 2 --integrator dop853 --rtol 1e-12 --atol 1e-14 -o " +
                               quote((dir / "ref.csv").string())));
  REQUIRE(r.exit_code == 0);
  const Csv ref = read_csv(dir / "ref.csv");
  const std::vector<std::string> state = {"bar1.x", "bar1.y", "bar1.theta", "bar2.x", "bar2.y", "bar2.theta",
                                          "bar1.u", "bar1.v", "bar1.w", "bar2.u", "bar2.v", "bar2.w"};
  auto final_error = [&](const Csv& c) {
    double e = 0.0;
    for (const auto& name : state) {
      REQUIRE(c.col(name) >= 0);
      e = std::max(e, std::fabs(c.rows.back()[static_cast<std::size_t>(c.col(name))] -
                                ref.rows.back()[static_cast<std::size_t>(ref.col(name))]));
    }
    return e;
  };
  r = run(run_in(dir, "run " + model + " --integrator bdf --rtol 1e-6 -o " + quote((dir / "probe.csv").string())));
  if (r.exit_code != 0 && r.output.find("bdf") != std::string::npos && r.output.find("integrator") != std::string::npos) {
    WARN("built without SUNDIALS: " << r.output);
    return;
  }
  std::vector<double> errors;
  const std::vector<std::pair<std::string, std::string>> tolerances = {
      {"1e-6", "1e-8"}, {"1e-8", "1e-10"}, {"1e-10", "1e-12"}, {"1e-12", "1e-14"}};
  for (const auto& [tol, atol] : tolerances) {
    r = run(run_in(dir, "run " + model + " --t-end 2 --integrator bdf --rtol " + tol + " --atol " + atol + " -o " +
                            quote((dir / "bdf.csv").string())));
    INFO("rtol " << tol << ": " << r.output);
    REQUIRE(r.exit_code == 0);
    CHECK(r.output.find("projected by the method (CVODE)") != std::string::npos);
    const Csv c = read_csv(dir / "bdf.csv");
    REQUIRE(c.rows.back()[0] == Approx(2.0));
    errors.push_back(final_error(c));
    WARN("bdf, rtol " << tol << ": final error " << errors.back());
  }
  CHECK(errors[1] < 100 * 1e-8);         // without the projection: 4.7e-6
  CHECK(errors[0] > 100 * errors[2]);    // the error follows the tolerance
  CHECK(errors[3] < 1e-9);
  fs::remove_all(dir);
}

TEST_CASE("mbsc run --newton-jacobian: the generated Jacobian gives the differences' motion", "[cli][run]") {
  // models/stiff_spring_damper.mbs (fastest mode -3.3e4 1/s): bdf and ark-dirk with the
  // Newton matrix from the generated rhs_jacobian, from forward differences and from
  // SUNDIALS' own quotients reach the same final state to the tolerance, with Jacobians
  // counted in the summary line.
  const fs::path dir = fresh_dir("newton_jacobian");
  const std::string model = quote(std::string(MBSC_SOURCE_DIR) + "/models/stiff_spring_damper.mbs");
  auto r = run(run_in(dir, "run " + model + " --t-end 0.5 --integrator dop853 --rtol 1e-12 --atol 1e-14 -o " +
                               quote((dir / "ref.csv").string())));
  REQUIRE(r.exit_code == 0);
  const Csv ref = read_csv(dir / "ref.csv");
  for (const char* method : {"bdf", "ark-dirk"}) {
    for (const char* source : {"generated", "differences", "sundials"}) {
      r = run(run_in(dir, std::string("run ") + model + " --t-end 0.5 --integrator " + method +
                              " --rtol 1e-9 --atol 1e-11 --newton-jacobian " + source + " -o " +
                              quote((dir / "run.csv").string())));
      INFO(method << " with " << source << ": " << r.output);
      if (r.exit_code != 0 && r.output.find("integrator") != std::string::npos) {
        WARN("built without SUNDIALS: " << r.output);
        return;
      }
      REQUIRE(r.exit_code == 0);
      // "S steps (...), R rhs evaluations, J Jacobians, I Newton iterations, F Newton failures"
      std::smatch got;
      REQUIRE(std::regex_search(r.output, got, std::regex(R"(([0-9]+) steps \(.*\), ([0-9]+) rhs evaluations, ([0-9]+) )"
                                                            R"(Jacobians, ([0-9]+) Newton iterations, ([0-9]+) Newton failures)")));
      const long steps = std::stol(got[1]), rhs = std::stol(got[2]), jacobians = std::stol(got[3]),
                 newton = std::stol(got[4]);
      REQUIRE(jacobians > 0);
      if (std::string(method) == "bdf") {
        // One rhs per Newton iteration; difference Jacobians add n = 8 each, the
        // generated one none (no " (k by differences)": it never fell back).
        if (std::string(source) == "generated") CHECK(rhs - newton < 8 * jacobians);
        else CHECK(rhs - newton >= 8 * jacobians);
        // An exact Newton matrix converges in about one iteration per step (a wrong one,
        // a transposed J for one, takes many more or fails).
        CHECK(newton < 3 * steps / 2);
      }
      const Csv c = read_csv(dir / "run.csv");
      REQUIRE(c.rows.back()[0] == Approx(0.5));
      double e = 0.0;
      for (std::size_t k = 1; k < ref.header.size(); ++k) {
        const int at = c.col(ref.header[k]);
        REQUIRE(at >= 0);
        e = std::max(e, std::fabs(c.rows.back()[static_cast<std::size_t>(at)] - ref.rows.back()[k]));
      }
      WARN(method << " with " << source << ": final error " << e);
      // The global error at rtol 1e-9 (bdf: 2e-7 to 1.2e-6 measured, the step sequences
      // differ with the Jacobian; ark-dirk: 2e-10); a wrong Jacobian stalls Newton or
      // drifts by orders more.
      CHECK(e < 1e-5);
    }
  }
  r = run(run_in(dir, "run " + model + " --integrator bdf --newton-jacobian exact"));
  CHECK(r.exit_code == 1);
  fs::remove_all(dir);
}

TEST_CASE("mbsc run --input NAME=@FILE: the torques mbsc inverse wrote drive the arm back along its motion",
          "[cli][run]") {
  const fs::path dir = fresh_dir("run_table_input");
  const std::string model = quote(std::string(MBSC_SOURCE_DIR) + "/models/spatial_arm.mbs");
  const std::string torques = (dir / "torques.csv").string();
  // The motion, its torques by inverse dynamics, then the forward run fed with them.
  auto r = run(run_in(dir, "inverse " + model + " --prescribe 'q1=0.8*sin(t)' --prescribe 'q2=2.6+0.4*(1-cos(2*t))' "
                               "--t-end 3 --dt-out 0.01 -o " + quote(torques)));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  double error[2] = {0, 0};
  const char* how[2] = {"linear", "cubic"};
  for (int k = 0; k < 2; ++k) {
    const fs::path out = dir / (std::string(how[k]) + ".csv");
    r = run(run_in(dir, "run " + model + " --input tau1=@" + quote(torques) + " --input tau2=@" + quote(torques) +
                            ":tau2 --input-interpolation " + how[k] +
                            " --init w1=0.8 --t-end 3 --dt-out 0.01 --rtol 1e-10 --atol 1e-12 -o " + quote(out.string())));
    INFO(how[k] << ": " << r.output);
    REQUIRE(r.exit_code == 0);
    const Csv c = read_csv(out);
    REQUIRE(c.rows.size() == 301);
    for (const auto& row : c.rows) {
      const double t = row[static_cast<std::size_t>(c.col("t"))];
      const double e1 = std::abs(row[static_cast<std::size_t>(c.col("q1"))] - 0.8 * std::sin(t));
      const double e2 = std::abs(row[static_cast<std::size_t>(c.col("q2"))] - (2.6 + 0.4 * (1 - std::cos(2 * t))));
      error[k] = std::max({error[k], e1, e2});
      // The input columns are the table's values at the output times (its knots).
      if (row == c.rows.back()) {
        const Csv table = read_csv(torques);
        CHECK(std::abs(row[static_cast<std::size_t>(c.col("tau2"))] -
                       table.rows.back()[static_cast<std::size_t>(table.col("tau2"))]) < 1e-12);
      }
    }
  }
  // Linear interpolation is second order in the table's step, the cubic spline fourth.
  CHECK(error[0] < 1e-3);
  CHECK(error[1] < 1e-6);
  CHECK(error[1] < error[0] / 100);

  // Bad tables: a positioned error, exit 1, no CSV.
  write(dir / "bad_number.csv", "t,tau1\n0,1\n0.5,x1\n");
  write(dir / "not_increasing.csv", "t,tau1\n0,1\n0.5,2\n0.5,3\n");
  write(dir / "short.csv", "t,tau1\n0,1\n0.5,2\n");
  write(dir / "no_t.csv", "time,tau1\n0,1\n1,2\n");
  const std::string csv = quote((dir / "x.csv").string());
  struct Case {
    std::string args, expect;
  } cases[] = {
      {"--input tau1=@" + quote((dir / "bad_number.csv").string()), "bad_number.csv:3:5: error: 'x1' in column 'tau1' is not a finite number"},
      {"--input tau1=@" + quote((dir / "not_increasing.csv").string()), "not_increasing.csv:4:1: error: the times must increase"},
      {"--input tau1=@" + quote((dir / "short.csv").string()), "covers t = 0 .. 0.5, and the run needs t = 0 .. 1"},
      {"--input tau1=@" + quote((dir / "no_t.csv").string()), "no_t.csv:1:1: error: the table for --input tau1 has no column 't'"},
      {"--input tau1=@" + quote(torques) + ":tau9", "has no column 'tau9' (its columns: upper.x"},
      {"--input tau1=@" + quote((dir / "missing.csv").string()), "--input tau1: cannot read the table"},
      {"--input tau3=@" + quote(torques), "the model has no input named 'tau3' (its inputs: tau1, tau2)"},
      {"--input tau1=@" + quote(torques) + " --input-interpolation spline", "--input-interpolation"},
      {"--input tau1=-10*w1", "'w1' is part of the state, and an input is a function of t only"},
  };
  for (const auto& c : cases) {
    r = run(run_in(dir, "run " + model + " -o " + csv + " --t-end 1 " + c.args));
    INFO(c.args << "\n" << r.output);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find(c.expect) != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "x.csv"));
  }
  fs::remove_all(dir);
}

TEST_CASE("mbsc run: names as the model writes them, loop instances included", "[cli][run]") {
  const fs::path dir = fresh_dir("run_written_names");
  write(dir / "blocks.mbs",
        "model blocks\nparameter k = 10, m = 1\nfor i = 1 to 2 {\n  body blk[i] : particle2d { mass m }\n}\n"
        "spring s blk[1] blk[2] stiffness k\ninitial blk[2].x = 1\n");
  const fs::path out = dir / "o.csv";
  const auto r = run(run_in(dir, "run " + quote((dir / "blocks.mbs").string()) + " --init 'blk[1].x=0.5' --t-end 1 "
                                 "--columns 't,blk[1].x,blk[2].x' -o " + quote(out.string())));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const Csv c = read_csv(out);
  REQUIRE(c.header == std::vector<std::string>{"t", "blk_1.x", "blk_2.x"});
  CHECK(c.rows.front()[1] == 0.5);
  CHECK(c.rows.front()[2] == 1.0);
  // The spring pulls them together and keeps their mass centre: (0.5 + 1) / 2.
  for (const auto& row : c.rows) CHECK(std::abs((row[1] + row[2]) / 2 - 0.75) < 1e-7);
  fs::remove_all(dir);
}

TEST_CASE("mbsc run: a start where the rhs is not finite names the force and writes nothing", "[cli][run]") {
  const fs::path dir = fresh_dir("run_start_nan");
  // Two blocks at one point, a spring with a rest length between them: its direction is 0/0.
  write(dir / "pair.mbs", "model pair\nparameter k = 10, m = 1\nbody a : particle2d { mass m }\n"
                          "body b : particle2d { mass m }\nspring s a b stiffness k length 1\n");
  const fs::path out = dir / "o.csv";
  auto r = run(run_in(dir, "run " + quote((dir / "pair.mbs").string()) + " --t-end 1 -o " + quote(out.string())));
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("pair.mbs:5:1: error: the rhs is not finite at the start (t = 0): the force of 'spring s a b "
                      "stiffness k length 1' on") != std::string::npos);
  CHECK(r.output.find(" steps (") == std::string::npos);  // no summary of a run that did not start
  CHECK_FALSE(fs::exists(out));
  // Apart, it runs.
  r = run(run_in(dir, "run " + quote((dir / "pair.mbs").string()) + " --init b.x=0.5 --t-end 1 -o " + quote(out.string())));
  CHECK(r.exit_code == 0);
  // An input that is not finite at t = 0 is the cause itself (no force judged with it).
  fs::remove(out);
  r = run(run_in(dir, "run " + quote(std::string(MBSC_SOURCE_DIR) + "/models/gantry_crane.mbs") +
                          " --input 'F=1/t' --t-end 1 -o " + quote(out.string())));
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("the rhs is not finite at the start (t = 0): the input 'F' is inf there") != std::string::npos);
  CHECK(r.output.find("internal error") == std::string::npos);
  CHECK_FALSE(fs::exists(out));
  fs::remove_all(dir);
}
