// SPDX-License-Identifier: GPL-2.0-or-later
// mbsc eig / linearize on the tadpole tricycle of Orsino's thesis, section 5.2
// (tests/data/linear/tadpole_tricycle.mbs, Table 5.1's data): the eigenvalues against
// the forward speed (the thesis's Fig 5.4) and the speeds where the weave and the capsize
// change stability.
//
// The thesis prints no numbers for Fig 5.4 (a chart); its text describes the modes, and
// that is what is checked against it: the castering root negative and falling with v;
// the weave born of two positive real roots at very low speed, turning stable at a
// transition speed with a rising frequency; the capsize root negative and nearly constant
// at low speeds, turning unstable at a higher speed, reaching a peak and falling back
// towards zero; a self-stable window between the two. The crossings are then checked for
// consistency with independent routes: the eigenvalue at the reported speed, formed again
// by `mbsc linearize`, lies on the imaginary axis; the roots of the lean-steer
// second-order form det(lambda^2 M + lambda v C1 + g K0 + v^2 K2) = 0 (formed through the
// tangent coordinates and the speed split) are the minimal state's eigenvalues; and eig's
// tracked modes equal linearize's eigenvalues at a grid point.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "json_arrays.hpp"
#include "run_command.hpp"

namespace {

using mbsc_test::json_numbers;

using cplx = std::complex<double>;

const std::filesystem::path& tricycle_cache() {
  static const std::filesystem::path dir = mbsc_test::fresh_dir("lin_tricycle");
  return dir;
}

const std::string kModel = std::string(MBSC_SOURCE_DIR) + "/tests/data/linear/tadpole_tricycle.mbs";
// Straight running at speed v: the rear wheel rolls at -v/rW, no lean or steer rate; the
// minimal state takes lean, steer and their rates first (as for the bicycle).
const std::string kReference = " --init 'theta_W_dot=-v/rW' --init rear_frame.wx=0 --init delta_dot=0"
                               " --keep rear_frame.theta,delta,rear_frame.wx,delta_dot";

// The nonzero eigenvalues of a linearize JSON answer (the zeros are the cyclic components).
std::vector<cplx> nonzero_eigenvalues(const std::string& json) {
  const auto e = json_numbers(json, "eigenvalues");
  std::vector<cplx> out;
  for (std::size_t k = 0; k + 1 < e.size(); k += 2)
    if (std::hypot(e[k], e[k + 1]) > 1e-6) out.emplace_back(e[k], e[k + 1]);
  return out;
}

// `mbsc linearize` at speed v (JSON, with the lean-steer second-order form split in v, g).
std::string linearize_at(double v) {
  std::ostringstream let;
  let.precision(17);
  let << v;
  const auto r = mbsc_test::run(std::string(MBSC_BINARY) + " linearize " + kModel + " --let v=" + let.str() + kReference +
                                " --second-order rear_frame.theta,delta --speed v --gravity g --format json -q --cache-dir " +
                                tricycle_cache().string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  return r.output;
}

// The CSV of `mbsc eig`: one row of numbers per grid point.
std::vector<std::vector<double>> read_csv(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);  // header
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::vector<double> row;
    for (std::size_t at = 0; at != std::string::npos; at = line.find(',', at + 1))
      row.push_back(std::strtod(line.c_str() + (at ? at + 1 : 0), nullptr));
    rows.push_back(row);
  }
  return rows;
}

}  // namespace

TEST_CASE("eig: the tadpole tricycle's modes and stability changes against speed (thesis Fig 5.4)", "[linear][tricycle]") {
  const auto csv = tricycle_cache() / "eig.csv";
  const auto r = mbsc_test::run(std::string(MBSC_BINARY) + " eig " + kModel + " --sweep v=0:10:0.5 --let v=5" + kReference +
                                " -q -o " + csv.string() + " --cache-dir " + tricycle_cache().string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);

  // "mode K becomes stable at v = X (eigenvalue RE +IMi)": the weave; "becomes unstable":
  // the capsize. Exactly these two changes.
  struct Crossing {
    double v, re, im;
  };
  auto crossing = [&](const std::string& what) {
    const auto at = r.output.find(what + " at v = ");
    REQUIRE(at != std::string::npos);
    const char* p = r.output.c_str() + at + what.size() + 7;
    char* end = nullptr;
    Crossing c{std::strtod(p, &end), 0, 0};
    const auto e = r.output.find("(eigenvalue ", static_cast<std::size_t>(end - r.output.c_str()));
    REQUIRE(e != std::string::npos);
    c.re = std::strtod(r.output.c_str() + e + 12, &end);
    c.im = std::strtod(end, nullptr);
    return c;
  };
  const Crossing weave = crossing("becomes stable"), capsize = crossing("becomes unstable");
  std::size_t count = 0;
  for (auto at = r.output.find(" becomes "); at != std::string::npos; at = r.output.find(" becomes ", at + 1)) ++count;
  CHECK(count == 2);
  // The self-stable window of the thesis's text: the weave stabilizes first.
  INFO("weave " << weave.v << " m/s, capsize " << capsize.v << " m/s");
  CHECK(weave.v > 0.5);
  CHECK(weave.v < capsize.v);
  CHECK(capsize.v < 10);
  // At the found speeds the eigenvalue's real part vanishes (root finding on the matrix).
  CHECK(std::fabs(weave.re) < 1e-9 * std::hypot(weave.re, weave.im));
  CHECK(weave.im > 0);
  CHECK(std::fabs(capsize.re) < 1e-9);
  CHECK(capsize.im == 0.0);

  // The tracked modes (ascending real part at v = 0): castering, capsize, weave's pair.
  const auto rows = read_csv(csv);
  REQUIRE(rows.size() == 21);
  for (const auto& row : rows) REQUIRE(row.size() >= 9);
  auto re = [&](std::size_t i, int mode) { return rows[i][static_cast<std::size_t>(2 * mode - 1)]; };
  auto im = [&](std::size_t i, int mode) { return rows[i][static_cast<std::size_t>(2 * mode)]; };
  // v = 0: the two pairs of opposite real roots of the standing tricycle (M q'' + g K0 q = 0).
  CHECK(re(0, 1) < re(0, 2));
  CHECK(re(0, 2) < 0);
  CHECK(std::fabs(re(0, 3) + re(0, 2)) < 1e-9 * std::fabs(re(0, 2)));
  CHECK(std::fabs(re(0, 4) + re(0, 1)) < 1e-9 * std::fabs(re(0, 1)));
  double capsize_peak = -1e300;
  std::size_t peak_at = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const double v = rows[i][0];
    INFO("v = " << v);
    // Castering: real, negative, falling with the speed.
    CHECK(im(i, 1) == 0.0);
    CHECK(re(i, 1) < 0);
    if (i > 0) CHECK(re(i, 1) < re(i - 1, 1));
    // Capsize: real; stable below its crossing, unstable above it.
    CHECK(im(i, 2) == 0.0);
    CHECK((re(i, 2) < 0) == (v < capsize.v));
    if (re(i, 2) > capsize_peak) capsize_peak = re(i, 2), peak_at = i;
    // Weave: a conjugate pair from very low speed on (by 0.5 m/s), unstable below its
    // crossing and stable above it, its frequency rising with the speed.
    if (v >= 0.5) {
      CHECK(re(i, 3) == re(i, 4));
      CHECK(im(i, 4) > 0);
      CHECK(im(i, 3) == -im(i, 4));
      CHECK((re(i, 4) > 0) == (v < weave.v));
      if (v > weave.v && i > 0) CHECK(im(i, 4) > im(i - 1, 4));
    }
  }
  // The capsize root "almost not varying at these low speeds" (within 5 % up to 2 m/s),
  // then a peak at a higher speed, after which it falls back towards zero.
  for (std::size_t i = 1; rows[i][0] <= 2.0; ++i) CHECK(std::fabs(re(i, 2) - re(0, 2)) < 0.05 * std::fabs(re(0, 2)));
  CHECK(rows[peak_at][0] > capsize.v);
  CHECK(peak_at < rows.size() - 1);
  CHECK(re(rows.size() - 1, 2) < capsize_peak);
  CHECK(re(rows.size() - 1, 2) > 0);

  SECTION("linearize agrees: the weave on the imaginary axis, eig's modes at 5 m/s, the second-order form's roots") {
    // Independently formed at the weave speed, one eigenvalue pair lies on the imaginary axis.
    const auto at_weave = nonzero_eigenvalues(linearize_at(weave.v));
    double closest = 1e300;
    for (const auto& l : at_weave) closest = std::min(closest, std::fabs(l.real()) / std::abs(l));
    CHECK(closest < 1e-9);

    // At v = 5 (a grid point: row 10) eig's four modes are linearize's nonzero eigenvalues.
    const auto json = linearize_at(5.0);
    const auto eig5 = nonzero_eigenvalues(json);
    REQUIRE(eig5.size() == 4);
    REQUIRE(rows[10][0] == 5.0);
    for (int mode = 1; mode <= 4; ++mode) {
      const cplx tracked(re(10, mode), im(10, mode));
      double best = 1e300;
      for (const auto& l : eig5) best = std::min(best, std::abs(l - tracked));
      INFO("mode " << mode << " = " << tracked);
      CHECK(best < 1e-9 * std::abs(tracked));
    }

    // The lean-steer form: decoupled from the rest at straight running, M symmetric, and
    // each eigenvalue a root of det(l^2 M + l v C1 + g K0 + v^2 K2) (scaled by the size of
    // the terms, so that rounding reads about 1e-16).
    const auto M = json_numbers(json, "M"), C1 = json_numbers(json, "C1"), K0 = json_numbers(json, "K0"),
               K2 = json_numbers(json, "K2");
    REQUIRE(M.size() == 4);
    REQUIRE(C1.size() == 4);
    REQUIRE(K0.size() == 4);
    REQUIRE(K2.size() == 4);
    const auto at = json.find("\"coupling\": ");
    REQUIRE(at != std::string::npos);
    CHECK(std::strtod(json.c_str() + at + 12, nullptr) < 1e-10);
    CHECK(std::fabs(M[1] - M[2]) < 1e-12 * M[0]);
    const double v = 5.0, g = 9.81;
    for (const auto& l : eig5) {
      cplx P[4], S[4];
      for (int k = 0; k < 4; ++k) {
        const auto i = static_cast<std::size_t>(k);
        P[k] = l * l * M[i] + l * v * C1[i] + g * K0[i] + v * v * K2[i];
        S[k] = std::norm(l) * std::fabs(M[i]) + std::abs(l) * v * std::fabs(C1[i]) + g * std::fabs(K0[i]) + v * v * std::fabs(K2[i]);
      }
      const double det = std::abs(P[0] * P[3] - P[1] * P[2]), scale = std::abs(S[0] * S[3]) + std::abs(S[1] * S[2]);
      INFO("eigenvalue " << l << ": |det| = " << det << " of " << scale);
      CHECK(det < 1e-9 * scale);
    }
  }
}
