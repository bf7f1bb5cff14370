// SPDX-License-Identifier: GPL-2.0-or-later
// `mbsc linearize` as a user calls it: the spherical pendulum hanging at rest (two
// oscillators of frequency sqrt(g/r), g = 9.81, r = 1) in text, JSON and CSV, the full
// state, --keep, and bad input (exit 1, a message naming what is wrong, nothing written
// to the -o file). Tagged [run]: it compiles the model once (into the test's cache).
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>

#include "run_command.hpp"

namespace fs = std::filesystem;
using namespace mbsc_test;

namespace {

const std::string kMbsc = MBSC_BINARY;
const std::string kSource = MBSC_SOURCE_DIR;
const std::string kPendulum = kSource + "/models/spherical_pendulum_cartesian.mbs";
const std::string kBottom = " --init bob.x=1 --init bob.y=0 --init bob.z=0 --init bob.v=0 --init bob.w=0";
const double kOmega = std::sqrt(9.81);

/// One folder (and model cache) for every test here: the model is compiled once.
const fs::path& shared_dir() {
  static const fs::path dir = fresh_dir("linearize");
  return dir;
}

std::string linearize(const fs::path& dir, const std::string& args) {
  return kMbsc + " linearize " + quote(kPendulum) + " " + args + " -q --cache-dir " + quote((dir / "cache").string());
}

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Every number in `text`.
std::vector<double> numbers(const std::string& text) {
  static const std::regex number(R"([-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?)");
  std::vector<double> out;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), number); it != std::sregex_iterator(); ++it)
    out.push_back(std::stod(it->str()));
  return out;
}

/// The eigenvalues (re, im) of the text format: the lines after "eigenvalues:".
std::vector<std::pair<double, double>> text_eigenvalues(const std::string& out) {
  std::vector<std::pair<double, double>> ev;
  const auto at = out.find("eigenvalues:");
  REQUIRE(at != std::string::npos);
  std::stringstream s(out.substr(at + 12));
  std::string line;
  while (std::getline(s, line)) {
    if (line.find_first_not_of(' ') == std::string::npos) continue;
    // "  0 (xK: the cyclic components ...)": K exact zeros of components nothing reads.
    if (const auto cyc = line.find("0 (x"); cyc != std::string::npos && line.find("cyclic") != std::string::npos) {
      const int k = std::atoi(line.c_str() + cyc + 4);
      REQUIRE(k > 0);
      for (int z = 0; z < k; ++z) ev.emplace_back(0.0, 0.0);
      continue;
    }
    const std::vector<double> v = numbers(line);
    REQUIRE(v.size() == 2);
    REQUIRE(line.back() == 'i');
    ev.emplace_back(v[0], v[1]);
  }
  return ev;
}

/// The pendulum at the bottom: +-i sqrt(g/r), each twice, and (full state) two zeros.
void check_bottom_spectrum(const std::vector<std::pair<double, double>>& ev, int zeros) {
  int plus = 0, minus = 0, zero = 0;
  for (const auto& [re, im] : ev) {
    INFO(re << " + " << im << "i");
    CHECK(std::fabs(re) < 1e-9);
    if (std::fabs(im - kOmega) < 1e-9)
      ++plus;
    else if (std::fabs(im + kOmega) < 1e-9)
      ++minus;
    else if (std::fabs(im) < 1e-9)
      ++zero;
    else
      FAIL("unexpected eigenvalue");
  }
  CHECK(plus == 2);
  CHECK(minus == 2);
  CHECK(zero == zeros);
}

}  // namespace

TEST_CASE("mbsc linearize: the hanging spherical pendulum in text, JSON and CSV", "[cli][run][linearize]") {
  const fs::path dir = shared_dir();
  SECTION("text: the minimal state (y, z, v, w) and +-i sqrt(g/r) twice") {
    const auto r = run(linearize(dir, kBottom));
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    CHECK(r.output.find("minimal state, 4 of 6 components") != std::string::npos);
    check_bottom_spectrum(text_eigenvalues(r.output), 0);
  }
  SECTION("json: the numbers parse back") {
    const fs::path out = dir / "lin.json";
    const auto r = run(linearize(dir, kBottom + " --format json -o " + quote(out.string())));
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    const std::string json = read(out);
    INFO(json);
    const auto at = json.find("\"eigenvalues\":");
    REQUIRE(at != std::string::npos);
    const std::vector<double> v = numbers(json.substr(at, json.find('\n', at) - at));
    REQUIRE(v.size() == 8);
    std::vector<std::pair<double, double>> ev;
    for (std::size_t i = 0; i < 8; i += 2) ev.emplace_back(v[i], v[i + 1]);
    check_bottom_spectrum(ev, 0);
    // A = [0 I; -g/r I 0] in the state listed.
    CHECK(json.find("\"state\": [\"bob.y\", \"bob.z\", \"bob.v\", \"bob.w\"]") != std::string::npos);
    const auto a = json.find("\"A\":");
    REQUIRE(a != std::string::npos);
    const std::vector<double> A = numbers(json.substr(a, json.find("]\n  ]", a) - a));
    REQUIRE(A.size() == 16);
    const std::vector<double> expected{0, 0, 1, 0, 0, 0, 0, 1, -9.81, 0, 0, 0, 0, -9.81, 0, 0};
    for (std::size_t i = 0; i < 16; ++i) CHECK(std::fabs(A[i] - expected[i]) < 1e-12);
  }
  SECTION("csv: A = [0 I; -g/r I 0], whose eigenvalues are +-i sqrt(g/r) twice") {
    const auto r = run(linearize(dir, kBottom + " --format csv"));
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    std::stringstream s(r.output);
    std::string line;
    REQUIRE(std::getline(s, line));
    CHECK(line == "row,bob.y,bob.z,bob.v,bob.w");
    const std::vector<double> expected{0, 0, 1, 0, 0, 0, 0, 1, -9.81, 0, 0, 0, 0, -9.81, 0, 0};
    for (std::size_t i = 0; i < 4; ++i) {
      REQUIRE(std::getline(s, line));
      const std::vector<double> v = numbers(line.substr(line.find(',')));
      REQUIRE(v.size() == 4);
      for (std::size_t j = 0; j < 4; ++j) CHECK(std::fabs(v[j] - expected[4 * i + j]) < 1e-12);
    }
  }
  SECTION("--state full: the 6 x 6 A, the radial direction adding a double zero") {
    const auto r = run(linearize(dir, kBottom + " --state full"));
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    CHECK(r.output.find("bob.x                    bob.y                    bob.z                    bob.u") != std::string::npos);
    check_bottom_spectrum(text_eigenvalues(r.output), 2);
  }
  SECTION("--keep: the minimal state takes the named components first") {
    const auto r = run(linearize(dir, kBottom + " --keep bob.w,bob.z --format json"));
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    CHECK(r.output.find("\"state\": [\"bob.w\", \"bob.z\"") != std::string::npos);
    const auto at = r.output.find("\"eigenvalues\":");
    REQUIRE(at != std::string::npos);
    const std::vector<double> v = numbers(r.output.substr(at, r.output.find('\n', at) - at));
    REQUIRE(v.size() == 8);
    std::vector<std::pair<double, double>> ev;
    for (std::size_t i = 0; i < 8; i += 2) ev.emplace_back(v[i], v[i + 1]);
    check_bottom_spectrum(ev, 0);
  }
}

TEST_CASE("mbsc linearize: bad input is exit 1 with a message naming the problem, nothing written", "[cli][run][linearize]") {
  const fs::path dir = shared_dir();
  const fs::path out = dir / "bad.txt";
  struct Case {
    std::string args, message;
  };
  const std::vector<Case> cases{
      {"--init bob.x=1 --init bob.y=1 --init bob.z=0", "position constraint 'rod' cannot be satisfied"},
      {kBottom + " --set nope=3", "no parameter named 'nope'"},
      {kBottom + " --keep bob.q", "--keep: the model has no coordinate or speed named 'bob.q'"},
      {kBottom + " --input tau=1", "--input: the model has no inputs (got 'tau')"},
      {"--init bob.x=1 --init bob.y=0 --init bob.z=0 --init bob.v=0.5 --init bob.w=0 --equilibrium",
       "not at rest: the rate of bob.y is 0.5"},
  };
  for (const Case& c : cases) {
    const auto r = run(linearize(dir, c.args + " -o " + quote(out.string())));
    INFO(c.args << "\n" << r.output);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("error: ") != std::string::npos);
    CHECK(r.output.find(c.message) != std::string::npos);
    CHECK(!fs::exists(out));
  }
  // Coulomb friction: no linear model, said at the friction's place in the file.
  const std::string friction = kSource + "/tests/data/friction/cross_slide.mbs";
  const auto r = run(kMbsc + " linearize " + quote(friction) + " -q --cache-dir " + quote((dir / "cache").string()) + " -o " +
                     quote(out.string()));
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(std::regex_search(r.output, std::regex(R"(cross_slide\.mbs:\d+:\d+: error: .*Coulomb friction)")));
  CHECK(!fs::exists(out));
}

TEST_CASE("mbsc linearize --find: an unstable steady motion is noted, a stable one is not", "[cli][run][linearize]") {
  const fs::path& dir = shared_dir();
  const std::string crane = quote(kSource + "/models/gantry_crane.mbs");
  auto find = [&](const std::string& guess) {
    return run(kMbsc + " linearize " + crane + " --find theta --steady w --init theta=" + guess + " --cache-dir " +
               quote((dir / "cache").string()));
  };
  // From 3 rad the load's equilibrium found is upright (theta = pi): unstable.
  auto r = find("3");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("steady motion: theta = 3.14159265358979") != std::string::npos);
  CHECK(r.output.find("note: the steady motion found is unstable") != std::string::npos);
  // From 0.2 rad: hanging, stable, no note.
  r = find("0.2");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("steady motion: theta = ") != std::string::npos);
  CHECK(r.output.find("unstable") == std::string::npos);
}
