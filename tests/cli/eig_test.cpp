// SPDX-License-Identifier: GPL-2.0-or-later
// mbsc eig against closed forms: the upright rolling disc's critical spin (a real pair
// meeting at zero and leaving as an imaginary pair), the ring-disc's steady motions found
// at every incline (thesis Ex 4.2/4.7), and bad input.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "run_command.hpp"

namespace {

const std::filesystem::path& cache() {
  static const std::filesystem::path dir = mbsc_test::fresh_dir("eig");
  return dir;
}

std::string eig(const std::string& model, const std::string& options) {
  return std::string(MBSC_BINARY) + " eig " + MBSC_SOURCE_DIR + "/" + model + " " + options + " -q --cache-dir " +
         cache().string();
}

std::vector<std::vector<double>> csv_rows(const std::filesystem::path& path, std::string& header) {
  std::ifstream in(path);
  std::vector<std::vector<double>> rows;
  std::getline(in, header);
  for (std::string line; std::getline(in, line);) {
    std::vector<double> row;
    std::stringstream s(line);
    for (std::string cell; std::getline(s, cell, ',');) row.push_back(std::strtod(cell.c_str(), nullptr));
    rows.push_back(row);
  }
  return rows;
}

}  // namespace

TEST_CASE("eig: the upright rolling disc turns stable at the closed-form spin sqrt(g / 3r)", "[linear]") {
  // tests/data/linear/rolling_disc_euler.mbs: m g r A / (C (C + m r^2)) = g / (3 r) for a
  // uniform thin disc, g = 9.81, r = 0.3. Below it a real pair +-sigma (one unstable),
  // above it imaginary pairs (marginally stable: the model is conservative).
  const auto out = cache() / "disc.csv";
  const auto r = mbsc_test::run(eig("tests/data/linear/rolling_disc_euler.mbs",
                                    "--sweep W=2:5:0.01 --let W=5 --init disc.wx=0 --init 'disc.wy=W' --init disc.wz=0 -o " +
                                        out.string()));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto at = r.output.find("becomes marginally stable at W = ");
  REQUIRE(at != std::string::npos);
  const double found = std::strtod(r.output.c_str() + at + 33, nullptr);
  // The heading's double zero (a symmetry, not a cyclic component) meets the pair at the
  // critical spin: rounding splits that block by eps^(1/4), which bounds the root's accuracy
  // near 1e-9 (docs/linearization.md); measured 4.8e-10.
  CHECK(std::fabs(found - std::sqrt(9.81 / (3 * 0.3))) < 1e-9);
  CHECK(r.output.find("becomes unstable") == std::string::npos);
  CHECK(r.output.find(" becomes stable") == std::string::npos);
}

TEST_CASE("eig: the ring-disc's steady motions along the incline satisfy the thesis's relation", "[linear]") {
  const auto out = cache() / "ring_disc.csv";
  const auto r = mbsc_test::run(eig("models/ring_disc.mbs",
                                    "--sweep xi=0.1:1.2:0.1 --init theta=0.05 --find theta --steady dtheta -o " +
                                        out.string()));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  std::string header;
  const auto rows = csv_rows(out, header);
  REQUIRE(header.rfind("xi,theta,re_1,im_1,re_2,im_2", 0) == 0);
  REQUIRE(rows.size() == 12);
  const double m1 = 0.67, m2 = 0.08, g = 9.8, r1 = 1.0, r2 = 0.3;
  for (const auto& row : rows) {
    const double X = row[0], T = row[1];
    INFO("xi = " << X << ", theta = " << T);
    // Thesis Ex 4.2 (h): m2/m1 = sin T / (2 sin X cos(T - X) - 3 sin T + sin X) - 1.
    CHECK(std::fabs(std::sin(T) / (2 * std::sin(X) * std::cos(T - X) - 3 * std::sin(T) + std::sin(X)) - 1 - m2 / m1) < 1e-9);
    // Ex 4.7: omega^2 = -G_{theta', theta} (closed form).
    const double G = 2 * g * (std::cos(T) + 2 * std::cos(X)) * std::sin(X) /
                     ((2 * std::cos(T - X) + 1) *
                      (2 * std::sin(T) + 3 * std::sin(2 * T - X) - 2 * std::sin(X) + 2 * std::sin(T - 2 * X) + std::sin(2 * T - 3 * X)) *
                      (r1 - r2));
    CHECK(std::fabs(row[2]) < 1e-9);
    CHECK(std::fabs(std::fabs(row[3]) - std::sqrt(-G)) < 1e-9 * std::sqrt(-G));
  }
}

TEST_CASE("eig: bad sweeps are refused with a clear message and nothing written", "[linear]") {
  const auto out = cache() / "bad.csv";
  struct Case {
    std::string options, message;
  };
  const std::vector<Case> cases = {
      {"--sweep v=0:10:-1", "--sweep v: the range 0:10 with step -1 is empty"},
      {"--sweep v=0:10:0", "is empty"},
      {"--sweep v=3:3:0.1", "is empty"},
      {"--sweep v=0:10", "--sweep expects NAME=FROM:TO:STEP"},
      {"--sweep gg=0:10:1", "--sweep: 'gg' is not a --let name, a parameter or a coordinate or speed of the model"},
      {"--sweep g=1:2:0.5 --set nope=1", "--set: the model has no parameter named 'nope'"},
      {"--sweep g=1:2:0.5 --ratio a/b", "--ratio a/b: expects NUM/DEN, two components of the minimal state"},
  };
  for (const auto& c : cases) {
    std::filesystem::remove(out);
    const auto r = mbsc_test::run(eig("models/spherical_pendulum_cartesian.mbs",
                                      c.options + " --init bob.y=0 --init bob.z=0 -o " + out.string()));
    INFO(c.options << "\n" << r.output);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find(c.message) != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(out));
  }
}
