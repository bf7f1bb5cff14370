// SPDX-License-Identifier: GPL-2.0-or-later
// mbsc linearize --symbolic: the linear model with parameters left as symbols, read back
// with GiNaC's parser and compared with closed forms exactly: the spherical pendulum at
// the bottom (A = [0 I; -g/r I 0]) and at the thesis's non-equilibrium reference of Ex 4.6
// (its matrix (k), here with g and r symbols), and the parallelogram with a redundant third
// crank, whose linear model is the compound pendulum's, through the least-squares path and
// equal to its non-redundant twin's. Also: the same text in every run, LaTeX, bad input.
#include <catch2/catch.hpp>
#include <ginac/ginac.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "json_arrays.hpp"
#include "run_command.hpp"

using namespace mbsc_test;

namespace {

const std::string kSource = MBSC_SOURCE_DIR;

const std::filesystem::path& cache() {
  static const std::filesystem::path dir = fresh_dir("lin_symbolic");
  return dir;
}

std::string linearize(const std::string& model, const std::string& args) {
  return std::string(MBSC_BINARY) + " linearize " + quote(kSource + "/" + model) + " " + args + " -q --cache-dir " +
         quote((cache() / "cache").string());
}

// The strings of the array after "key": (json_arrays.hpp), the key required.
std::vector<std::string> entries(const std::string& text, const std::string& key) {
  REQUIRE(text.find("\"" + key + "\":") != std::string::npos);
  return json_strings(text, key);
}

struct Symbols {
  GiNaC::symtab table;
  GiNaC::ex operator[](const std::string& name) {
    if (!table.count(name)) table[name] = GiNaC::symbol(name);
    return table[name];
  }
  GiNaC::ex parse(const std::string& text) {
    GiNaC::parser reader(table);
    return reader(text);
  }
};

// Every entry equal to the closed form exactly (their difference normalizes to zero).
void check_exact(Symbols& s, const std::vector<std::string>& got, const std::vector<GiNaC::ex>& expected) {
  REQUIRE(got.size() == expected.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    INFO("entry " << i << ": " << got[i] << ", expected " << expected[i]);
    CHECK(GiNaC::normal(s.parse(got[i]) - expected[i]).is_zero());
  }
}

}  // namespace

TEST_CASE("linearize --symbolic: the spherical pendulum's closed forms, g and r symbols", "[linear]") {
  Symbols s;
  const GiNaC::ex g = s["g"], r = s["r"], w = g / r;
  SECTION("at the bottom: A = [0 I; -g/r I 0]") {
    const auto res = run(linearize("models/spherical_pendulum_cartesian.mbs",
                                   "--init bob.x=r --init bob.y=0 --init bob.z=0 --init bob.v=0 --init bob.w=0 "
                                   "--symbolic all --format json"));
    INFO(res.output);
    REQUIRE(res.exit_code == 0);
    CHECK(res.output.find("\"state\": [\"bob.y\", \"bob.z\", \"bob.v\", \"bob.w\"]") != std::string::npos);
    CHECK(entries(res.output, "symbols") == std::vector<std::string>{"m", "r", "g"});
    check_exact(s, entries(res.output, "A"), {0, 0, 1, 0, 0, 0, 0, 1, -w, 0, 0, 0, 0, -w, 0, 0});
  }
  SECTION("thesis Ex 4.6: released from rest at (4/5, 3/5, 0) r, its matrix (k)") {
    const auto res = run(linearize("models/spherical_pendulum_extra_speed.mbs",
                                   "--state full --init bob.x=4*r/5 --init bob.y=3*r/5 --init bob.z=0 --init bob.u=0 "
                                   "--init bob.v=0 --init bob.w=0 --symbolic g,r --format json"));
    INFO(res.output);
    REQUIRE(res.exit_code == 0);
    const std::vector<std::string> A = entries(res.output, "A");
    REQUIRE(A.size() == 49);
    // x' = u, y' = v, z' = w and x'' = -72/125 g/r x + 96/125 g/r y, y'' = 21/125 g/r x -
    // 28/125 g/r y, z'' = -4/5 g/r z: the thesis's matrix (k), stated there for r = 1 (the
    // factor 1/r by dimensions; the extra speed's row depends on how the model defines it).
    const std::vector<GiNaC::ex> rows{0, 0, 0, 1, 0, 0, 0,  //
                                      0, 0, 0, 0, 1, 0, 0,  //
                                      0, 0, 0, 0, 0, 1, 0,  //
                                      GiNaC::numeric(-72, 125) * w, GiNaC::numeric(96, 125) * w, 0, 0, 0, 0, 0,
                                      GiNaC::numeric(21, 125) * w, GiNaC::numeric(-28, 125) * w, 0, 0, 0, 0, 0,
                                      0, 0, GiNaC::numeric(-4, 5) * w, 0, 0, 0, 0};
    check_exact(s, std::vector<std::string>(A.begin(), A.begin() + 42), rows);
  }
  SECTION("the same text in every run (GiNaC's term order is not)") {
    // The free body's entries are fractions of its six inertias: GiNaC would give their
    // denominators a run-dependent sign.
    const std::string cmd = linearize("models/free_body_quaternion.mbs", "--symbolic all");
    const auto first = run(cmd);
    REQUIRE(first.exit_code == 0);
    CHECK(first.output.find(")/(") != std::string::npos);
    for (int k = 0; k < 3; ++k) CHECK(run(cmd).output == first.output);
  }
  SECTION("LaTeX: the reference and A as a matrix") {
    const auto res = run(linearize("models/spherical_pendulum_cartesian.mbs",
                                   "--init bob.x=r --init bob.y=0 --init bob.z=0 --init bob.v=0 --init bob.w=0 "
                                   "--symbolic g,r --format latex"));
    INFO(res.output);
    REQUIRE(res.exit_code == 0);
    CHECK(res.output.find("\\mathbf{A} = \\begin{pmatrix}") != std::string::npos);
    CHECK(res.output.find("\\frac{g}{r}") != std::string::npos);
    CHECK(res.output.find("x_{\\mathrm{bob}} &= r") != std::string::npos);
  }
}

TEST_CASE("linearize --symbolic: redundant constraints, the compound pendulum exactly", "[linear]") {
  // Three cranks of length a = 3/10 and a translating coupler: (m_c + m_k) a phi'' =
  // -(3/2 m_c + m_k) g cos(phi) (tests/numeric/linear_model_test.cpp derives it), so about
  // the hanging equilibrium d(phi')' = -g (3/2 m_c + m_k) / ((m_c + m_k) a) d(phi).
  Symbols s;
  const GiNaC::ex g = s["g"], mc = s["m_crank"], mk = s["m_coupler"];
  const GiNaC::ex K = g * (GiNaC::numeric(3, 2) * mc + mk) / ((mc + mk) * GiNaC::numeric(3, 10));
  for (const char* model : {"tests/data/linear/parallelogram_redundant.mbs", "tests/data/linear/parallelogram_twin.mbs"}) {
    INFO(model);
    const auto res = run(linearize(model, "--init crank1.theta=-pi/2 --keep crank1.theta,crank1.w --symbolic g,m_crank,m_coupler "
                                          "--format json"));
    INFO(res.output);
    REQUIRE(res.exit_code == 0);
    CHECK(res.output.find("\"state\": [\"crank1.theta\", \"crank1.w\"]") != std::string::npos);
    check_exact(s, entries(res.output, "A"), {0, 1, -K, 0});
  }
  // Away from equilibrium (phi = -1, phi' = 1.3) the reference is known to rounding: the
  // entries agree with K sin(phi) to 1e-12 at other values of the symbols.
  const auto res = run(linearize("tests/data/linear/parallelogram_redundant.mbs",
                                 "--init crank1.theta=-1 --init crank1.w=1.3 --keep crank1.theta,crank1.w "
                                 "--symbolic g,m_crank,m_coupler --format json"));
  INFO(res.output);
  REQUIRE(res.exit_code == 0);
  const std::vector<std::string> A = entries(res.output, "A");
  REQUIRE(A.size() == 4);
  for (const auto& [gv, mcv, mkv] : std::vector<std::tuple<double, double, double>>{{9.81, 0.3, 0.5}, {1.62, 2.0, 0.1}}) {
    const GiNaC::exmap at{{g, gv}, {mc, mcv}, {mk, mkv}};
    auto value = [&](const GiNaC::ex& e) { return GiNaC::ex_to<GiNaC::numeric>(e.subs(at).evalf()).to_double(); };
    const double k = value(K);
    CHECK(std::fabs(value(s.parse(A[0]))) < 1e-12 * k);
    CHECK(value(s.parse(A[1])) == Approx(1.0).epsilon(1e-12));
    CHECK(value(s.parse(A[2])) == Approx(k * std::sin(-1.0)).epsilon(1e-12));
    CHECK(std::fabs(value(s.parse(A[3]))) < 1e-12 * k);
  }
}

TEST_CASE("linearize --symbolic: a symbol at zero, --set expressions, the second-order form", "[linear]") {
  // Each symbolic model equals the numeric one at values away from the nominal ones.
  SECTION("a parameter whose nominal value is 0 keeps its terms (the four-bar's torque tau0)") {
    const auto sym = run(linearize("models/four_bar.mbs", "--symbolic tau0 --format json"));
    INFO(sym.output);
    REQUIRE(sym.exit_code == 0);
    const std::vector<std::string> A = entries(sym.output, "A");
    REQUIRE(A.size() == 4);
    CHECK(A[2].find("tau0") != std::string::npos);
    const auto num = run(linearize("models/four_bar.mbs", "--set tau0=0.7 --format json"));
    REQUIRE(num.exit_code == 0);
    Symbols s;
    const GiNaC::ex tau0 = s["tau0"];  // before parsing: the parser then uses this symbol
    const GiNaC::ex e = s.parse(A[2]).subs(tau0 == GiNaC::numeric(7, 10)).evalf();
    CHECK(GiNaC::ex_to<GiNaC::numeric>(e).to_double() == Approx(json_numbers(num.output, "A").at(2)).epsilon(1e-10));
  }
  SECTION("--set m=k/2 with k symbolic: the parameter follows k") {
    const auto sym = run(linearize("models/heavy_top.mbs", "--let k=2 --set m=k/2 --symbolic k --format json"));
    INFO(sym.output);
    REQUIRE(sym.exit_code == 0);
    const std::vector<std::string> A = entries(sym.output, "A");
    const auto num = run(linearize("models/heavy_top.mbs", "--set m=2 --format json"));
    REQUIRE(num.exit_code == 0);
    Symbols s;
    const GiNaC::ex k = s["k"];
    double largest = 0;
    bool has_k = false;
    for (std::size_t i = 0; i < A.size(); ++i) {
      has_k = has_k || A[i].find('k') != std::string::npos;
      const double at4 = GiNaC::ex_to<GiNaC::numeric>(s.parse(A[i]).subs(k == 4).evalf()).to_double();
      const double want = json_numbers(num.output, "A").at(i);
      INFO("entry " << i << ": " << A[i]);
      CHECK(at4 == Approx(want).epsilon(1e-10).margin(1e-12));
      largest = std::max(largest, std::fabs(want));
    }
    CHECK(has_k);
    CHECK(largest > 0);
  }
  SECTION("the second-order form with the rest of the state coupled: the numeric one's") {
    const std::string steady = "--init th1=0.1 --init th2=0.1 --find th1,th2 --steady w1,w2 --second-order th1 --format json";
    const auto sym = run(linearize("models/double_pendulum.mbs", steady + " --symbolic m1"));
    INFO(sym.output);
    REQUIRE(sym.exit_code == 0);
    const auto num = run(linearize("models/double_pendulum.mbs", steady + " --set m1=1.7"));
    REQUIRE(num.exit_code == 0);
    Symbols s;
    const GiNaC::ex m1 = s["m1"];
    for (const char* key : {"M", "C", "K"}) {
      const std::vector<std::string> got = entries(sym.output, key);
      REQUIRE(got.size() == 1);
      const double at = GiNaC::ex_to<GiNaC::numeric>(s.parse(got[0]).subs(m1 == GiNaC::numeric(17, 10)).evalf()).to_double();
      const auto second = num.output.find("\"second_order\"");
      REQUIRE(second != std::string::npos);
      INFO(key << " = " << got[0]);
      CHECK(at == Approx(json_numbers(num.output.substr(second), key).at(0)).epsilon(1e-10).margin(1e-12));
    }
  }
}

TEST_CASE("linearize --symbolic: bad input names the problem, exit 1", "[linear]") {
  const std::string bottom = "--init bob.y=0 --init bob.z=0 --init bob.v=0 --init bob.w=0";
  struct Case {
    std::string args, message;
  };
  for (const Case& c : std::vector<Case>{
           {bottom + " --symbolic rr", "--symbolic: 'rr' is neither a parameter of the model nor a --let name (did you mean 'r'?)"},
           {bottom + " --symbolic r", "the reference value of bob.x changes with r but it is assembled or found numerically"},
           {bottom + " --init bob.x=1 --symbolic r", "--symbolic r: the reference at r = 1.001 (to see what depends on it)"},
           {bottom + " --format latex", "--format latex writes a symbolic model: name its symbols with --symbolic"},
           {bottom + " --symbolic g --format csv", "--symbolic writes text, latex or json (not --format csv)"},
           {bottom + " --symbolic ,", "--symbolic: no names given"}}) {
    const auto res = run(linearize("models/spherical_pendulum_cartesian.mbs", c.args));
    INFO(c.args << "\n" << res.output);
    CHECK(res.exit_code == 1);
    CHECK(res.output.find(c.message) != std::string::npos);
  }
}
