// SPDX-License-Identifier: GPL-2.0-or-later
// mbsc linearize on the benchmark bicycle: the second-order form M q'' + v C1 q' +
// (g K0 + v^2 K2) q = T in lean and steer, and the eigenvalues at 5 m/s, against the values
// published by Meijaard, Papadopoulos, Ruina and Schwab (Proc. R. Soc. A 463 (2007)
// 1955-1982, their equations (A 19)-(A 21) / Table 2), the acceptance test of issue 13.
#include <catch2/catch.hpp>
#include <ginac/ginac.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <cstdlib>
#include <string>
#include <vector>

#include "json_arrays.hpp"
#include "run_command.hpp"

namespace {

using mbsc_test::json_numbers;

// Entry by entry: relative `rel` where the published value is not zero, else absolute `abs`.
void check_matrix(const std::string& name, const std::vector<double>& got, const std::vector<double>& published, double rel,
                  double abs) {
  REQUIRE(got.size() == published.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    INFO(name << "[" << i << "] = " << got[i] << ", published " << published[i]);
    if (published[i] == 0.0) CHECK(std::fabs(got[i]) <= abs);
    else CHECK(std::fabs(got[i] - published[i]) <= rel * std::fabs(published[i]));
  }
}

}  // namespace

// One cache for this file's commands: the bicycle is compiled once.
const std::filesystem::path& bicycle_cache() {
  static const std::filesystem::path dir = mbsc_test::fresh_dir("lin_bicycle");
  return dir;
}

// mbsc linearize at 5 m/s, upright, in lean and steer: the second-order form split in v
// and g, as JSON.
static std::string bicycle_linearize() {
  return std::string(MBSC_BINARY) + " linearize " + MBSC_SOURCE_DIR +
         "/models/whipple_bicycle_joints.mbs --let v=5 --init 'theta_R_dot=-v/rR' --init rear_frame.wx=0"
         " --init delta_dot=0 --keep rear_frame.theta,delta --second-order rear_frame.theta,delta"
         " --speed v --gravity g --format json -q --cache-dir " +
         bicycle_cache().string();
}

TEST_CASE("linearize: the benchmark bicycle's M, C1, K0, K2 and eigenvalues are the published ones", "[linear]") {
  const auto r = mbsc_test::run(bicycle_linearize());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  // The paper's (A 19)-(A 21), 14 significant digits. Its lean is our rear frame's roll
  // angle theta (positive to the right), its steer our delta.
  check_matrix("M", json_numbers(r.output, "M"), {80.81722, 2.31941332208709, 2.31941332208709, 0.29784188199686}, 1e-12, 0);
  check_matrix("C1", json_numbers(r.output, "C1"), {0, 33.86641391492494, -0.85035641456978, 1.68540397397560}, 1e-12, 1e-11);
  check_matrix("K0", json_numbers(r.output, "K0"), {-80.95, -2.59951685249872, -2.59951685249872, -0.80329488458618}, 1e-12,
               0);
  check_matrix("K2", json_numbers(r.output, "K2"), {0, 76.59734589573222, 0, 2.65431523794604}, 1e-12, 1e-11);
  // Lean and steer evolve by themselves at straight running.
  const auto at = r.output.find("\"coupling\": ");
  REQUIRE(at != std::string::npos);
  CHECK(std::strtod(r.output.c_str() + at + 12, nullptr) < 1e-12);
  // Table 2 at v = 5 m/s: castering, weave, capsize (by real part); the other eigenvalues
  // of the minimal state (heading, position, wheel angles, forward speed) are zero.
  const auto eig = json_numbers(r.output, "eigenvalues");
  REQUIRE(eig.size() % 2 == 0);
  std::vector<std::pair<double, double>> nonzero;
  for (std::size_t k = 0; k < eig.size() / 2; ++k) {
    INFO("eigenvalue " << eig[2 * k] << " + " << eig[2 * k + 1] << "i");
    if (std::hypot(eig[2 * k], eig[2 * k + 1]) > 1e-5) nonzero.emplace_back(eig[2 * k], eig[2 * k + 1]);
    else CHECK(std::hypot(eig[2 * k], eig[2 * k + 1]) < 1e-7);  // a zero (exact where cyclic)
  }
  const std::vector<std::pair<double, double>> published = {
      {-14.07838969279822, 0}, {-0.77534188219585, -4.46486771378823}, {-0.77534188219585, 4.46486771378823},
      {-0.32286642900409, 0}};
  REQUIRE(nonzero.size() == published.size());
  for (std::size_t k = 0; k < published.size(); ++k) {
    const double re = nonzero[k].first, im = nonzero[k].second;
    INFO("eigenvalue " << re << " + " << im << "i, published " << published[k].first << " + " << published[k].second << "i");
    CHECK(std::fabs(re - published[k].first) <= 1e-11 * std::fabs(published[k].first));
    CHECK(std::fabs(im - published[k].second) <= 1e-11 * std::max(1.0, std::fabs(published[k].second)));
  }
  // The cyclic components are named.
  CHECK(r.output.find("\"cyclic\": [\"") != std::string::npos);
}

// Its own ctest entry (linearize_symbolic_bicycle), left to the Release run: scripts/sanitize.sh.
TEST_CASE("linearize --symbolic v,g: the bicycle's form is exactly M q'' + v C1 q' + (g K0 + v^2 K2) q",
          "[linear_symbolic_bicycle]") {
  // The same reference with v and g left as symbols: the exact elimination gives M, C and
  // K as expressions, and C1, K0, K2 are read off them (no differences of three points):
  // they are the published ones, and A is polynomial in v and g (degree 2 and 1) and equals
  // the numeric A at v = 5, g = 9.81 (the other test's command, also run here).
  const std::string common = bicycle_linearize();
  const auto r = mbsc_test::run(common + " --symbolic v,g");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("\"split\": \"M q'' + v C1 q' + (g K0 + v^2 K2) q = T exactly\"") != std::string::npos);
  GiNaC::symtab table;
  const GiNaC::symbol v("v"), g("g");
  table["v"] = v, table["g"] = g;
  // The entries of a matrix read back (the key required).
  auto strings = [&](const std::string& key) {
    REQUIRE(r.output.find("\"" + key + "\":") != std::string::npos);
    std::vector<GiNaC::ex> out;
    for (const auto& entry : mbsc_test::json_strings(r.output, key)) {
      GiNaC::parser reader(table);
      out.push_back(reader(entry));
    }
    return out;
  };
  auto numbers = [&](const std::string& key) {
    std::vector<double> out;
    for (const auto& e : strings(key)) {
      REQUIRE(GiNaC::is_a<GiNaC::numeric>(e.evalf()));
      out.push_back(GiNaC::ex_to<GiNaC::numeric>(e.evalf()).to_double());
    }
    return out;
  };
  check_matrix("M", numbers("M"), {80.81722, 2.31941332208709, 2.31941332208709, 0.29784188199686}, 1e-12, 0);
  check_matrix("C1", numbers("C1"), {0, 33.86641391492494, -0.85035641456978, 1.68540397397560}, 1e-12, 1e-11);
  check_matrix("K0", numbers("K0"), {-80.95, -2.59951685249872, -2.59951685249872, -0.80329488458618}, 1e-12, 0);
  check_matrix("K2", numbers("K2"), {0, 76.59734589573222, 0, 2.65431523794604}, 1e-12, 1e-11);
  const auto numeric = mbsc_test::run(common);
  REQUIRE(numeric.exit_code == 0);
  const std::vector<double> A5 = json_numbers(numeric.output, "A");
  const std::vector<GiNaC::ex> A = strings("A");
  REQUIRE(A.size() == A5.size());
  double scale = 0;
  for (double a : A5) scale = std::max(scale, std::fabs(a));
  for (std::size_t i = 0; i < A.size(); ++i) {
    INFO("A entry " << i << " = " << A[i] << ", numeric " << A5[i]);
    const GiNaC::ex e = GiNaC::normal(A[i]);
    CHECK(!e.denom().has(v));
    CHECK(!e.denom().has(g));
    CHECK(e.numer().expand().degree(v) <= 2);
    CHECK(e.numer().expand().degree(g) <= 1);
    const double at5 = GiNaC::ex_to<GiNaC::numeric>(e.subs(GiNaC::lst{v == 5, g == 9.81}).evalf()).to_double();
    CHECK(std::fabs(at5 - A5[i]) <= 1e-12 * scale);
  }
}

TEST_CASE("eig: the benchmark bicycle's weave and capsize speeds are the published ones", "[linear]") {
  const auto csv = bicycle_cache() / "eig.csv";
  const std::string cmd = std::string(MBSC_BINARY) + " eig " + MBSC_SOURCE_DIR +
                          "/models/whipple_bicycle_joints.mbs --sweep v=0:10:0.05 --let v=5 --init 'theta_R_dot=-v/rR'"
                          " --init rear_frame.wx=0 --init delta_dot=0 --ratio delta/rear_frame.theta -q -o " +
                          csv.string() + " --cache-dir " + bicycle_cache().string();
  const auto r = mbsc_test::run(cmd);
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  // "mode K becomes stable at v = X (...)": the weave; "becomes unstable": the capsize.
  auto speed = [&](const std::string& what) {
    const auto at = r.output.find(what + " at v = ");
    REQUIRE(at != std::string::npos);
    return std::strtod(r.output.c_str() + at + what.size() + 7, nullptr);
  };
  // Meijaard et al. (2007), section 5: v_w = 4.29238253634111, v_c = 6.02426201538837 m/s.
  CHECK(std::fabs(speed("becomes stable") - 4.29238253634111) < 1e-9);
  CHECK(std::fabs(speed("becomes unstable") - 6.02426201538837) < 1e-9);
  // Two stability changes, no more (the cyclic zeros are left out, not crossings).
  std::size_t count = 0;
  for (auto at = r.output.find(" becomes "); at != std::string::npos; at = r.output.find(" becomes ", at + 1)) ++count;
  CHECK(count == 2);
  // The CSV: 201 rows of the 4 lateral modes and the ratio columns; at v = 0 the paper's
  // real eigenvalues +-3.13164324790656, +-5.53094371765393.
  std::ifstream in(csv);
  std::string header, first;
  REQUIRE(std::getline(in, header));
  REQUIRE(std::getline(in, first));
  CHECK(header.rfind("v,re_1,im_1,re_2,im_2,re_3,im_3,re_4,im_4,abs(delta/rear_frame.theta)_1", 0) == 0);
  std::vector<double> row;
  for (std::size_t at = 0; at != std::string::npos; at = first.find(',', at + 1))
    row.push_back(std::strtod(first.c_str() + (at ? at + 1 : 0), nullptr));
  REQUIRE(row.size() >= 9);
  const std::vector<double> published = {-5.53094371765393, -3.13164324790656, 3.13164324790656, 5.53094371765393};
  for (int k = 0; k < 4; ++k) {
    CHECK(std::fabs(row[static_cast<std::size_t>(1 + 2 * k)] - published[static_cast<std::size_t>(k)]) < 1e-11);
    CHECK(row[static_cast<std::size_t>(2 + 2 * k)] == 0.0);
  }
  std::size_t lines = 2;
  for (std::string line; std::getline(in, line);) ++lines;
  CHECK(lines == 202);
}
