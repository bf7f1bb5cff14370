// SPDX-License-Identifier: GPL-2.0-or-later
// The sphere on the parabolic trough z = y^2 / 2 of models/sphere_trough.mbs (the spatial
// `rolling_sphere` joint, thesis Ex 2.5 and Ex 4.4), compiled:
//  - with the thesis's oscillating electric field, a run with projection keeps the contact
//    and no-slip rows and the quaternion norm to 1e-9, and the field moves the sphere
//    along the trough (x), the only active force along x;
//  - without the field, a small oscillation across the trough: the energy is conserved,
//    z oscillates at twice the frequency of y (thesis Ex 4.4), and y's period is the
//    closed form of a sphere rolling in a cylinder of radius R = 1 (the trough's radius of
//    curvature at the bottom): T = 2 pi sqrt((R - r) (1 + J / (m r^2)) / g), J = 2/5 m r^2;
//  - --state minimal agrees with the full state at random consistent states.
// Both formulations agree at random assembled states in shipped_formulations_test.cpp.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "mbsc/runtime/simulate.hpp"
#include "sphere_trough/sphere_trough.hpp"
#include "sphere_trough_min/sphere_trough_min.hpp"
#include "test_support.hpp"

namespace F = mbsc_gen::sphere_trough;
namespace M = mbsc_gen::sphere_trough_min;
using mbsc_test::index_of;

namespace {

constexpr double kPi = 3.14159265358979323846;

std::size_t ix(const char* name) { return static_cast<std::size_t>(index_of(F::kStateNames, F::kNx, name)); }

std::vector<double> params_with(const char* name, double value) {
  std::vector<double> p(F::kParamDefaults, F::kParamDefaults + F::kNp);
  p[static_cast<std::size_t>(index_of(F::kParamNames, F::kNp, name))] = value;
  return p;
}
double param(const char* name) { return F::kParamDefaults[index_of(F::kParamNames, F::kNp, name)]; }

/// At rest with the contact point at (0, y0, y0^2 / 2), the identity attitude: the centre
/// is r along the unit normal (0, -y0, 1) / sqrt(1 + y0^2) (an assembled state).
std::vector<double> at_rest(double y0) {
  const double r = param("r"), N = std::sqrt(1 + y0 * y0);
  std::vector<double> x(static_cast<std::size_t>(F::kNx), 0.0);
  x[ix("ball.e0")] = 1.0;
  x[ix("roll.yc")] = y0;
  x[ix("ball.y")] = y0 - r * y0 / N;
  x[ix("ball.z")] = y0 * y0 / 2 + r / N;
  return x;
}

struct Run {
  mbsc::runtime::SimulationResult result;
  double worst_rows = 0.0, worst_norm = 0.0;
  std::vector<double> t, x, y, z;
};

Run run(const std::vector<double>& p, double y0, double t_end) {
  const auto model = MBSC_MODEL_TABLE(F);
  mbsc::runtime::StepperOptions so;
  so.rtol = 1e-12;
  so.atol = 1e-14;
  mbsc::runtime::SimulationOptions opt;
  opt.t_end = t_end;
  opt.dt_out = 0.002;
  opt.unit_quaternions = mbsc::runtime::unit_quaternions_of(F::kQuaternionIndices, F::kNquaternions);
  REQUIRE(opt.unit_quaternions.size() == 1u);
  Run out;
  auto observe = [&](double t, const std::vector<double>& x) {
    std::array<double, F::kNposc> g{};
    std::array<double, F::kNc> v{};
    REQUIRE(F::position_constraints(t, x.data(), nullptr, p.data(), g.data()) == 0);
    REQUIRE(F::velocity_constraints(t, x.data(), nullptr, p.data(), v.data()) == 0);
    for (double e : g) out.worst_rows = std::max(out.worst_rows, std::fabs(e));
    for (double e : v) out.worst_rows = std::max(out.worst_rows, std::fabs(e));
    const double* e = &x[ix("ball.e0")];
    out.worst_norm = std::max(out.worst_norm, std::fabs(e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3] - 1));
    out.t.push_back(t);
    out.x.push_back(x[ix("ball.x")]);
    out.y.push_back(x[ix("ball.y")]);
    out.z.push_back(x[ix("ball.z")]);
  };
  out.result = mbsc::runtime::simulate(model, "dop853", so, opt, at_rest(y0), {}, p.data(), observe);
  return out;
}

/// Mean period of s from its upward crossings of `level` (linear interpolation).
double period(const std::vector<double>& t, const std::vector<double>& s, double level) {
  std::vector<double> up;
  for (std::size_t k = 1; k < s.size(); ++k) {
    const double a = s[k - 1] - level, b = s[k] - level;
    if (a < 0 && b >= 0) up.push_back(t[k - 1] + (t[k] - t[k - 1]) * (-a) / (b - a));
  }
  REQUIRE(up.size() >= 3u);
  return (up.back() - up.front()) / static_cast<double>(up.size() - 1);
}

}  // namespace

TEST_CASE("sphere trough: with the field, rows and quaternion norm held by projection", "[numeric][rolling_sphere]") {
  const std::vector<double> p(F::kParamDefaults, F::kParamDefaults + F::kNp);
  const Run r = run(p, 0.1, 20.0);
  INFO(r.result.message << "; rows " << r.worst_rows << "; norm " << r.worst_norm);
  REQUIRE(r.result.ok());
  CHECK(r.worst_rows < 1e-9);
  CHECK(r.worst_norm < 1e-9);
  // The field is the only force along x: without it x stays 0 (next case), with it the
  // sphere moves along the trough.
  double largest_x = 0.0;
  for (double x : r.x) largest_x = std::max(largest_x, std::fabs(x));
  INFO("largest |x| " << largest_x);
  CHECK(largest_x > 1e-3);
}

TEST_CASE("sphere trough: without the field, energy is conserved and z oscillates at twice y's frequency",
          "[numeric][rolling_sphere]") {
  const std::vector<double> p = params_with("E0", 0.0);
  const Run r = run(p, 0.02, 12.0);
  INFO(r.result.message << "; energy drift " << r.result.energy_relative_drift << "; rows " << r.worst_rows);
  REQUIRE(r.result.ok());
  CHECK(r.result.energy_defined);
  CHECK(r.result.energy_relative_drift < 1e-9);
  CHECK(r.worst_rows < 1e-9);
  CHECK(r.worst_norm < 1e-9);
  for (double x : r.x) CHECK(std::fabs(x) < 1e-12);
  double z_mean = 0.0;
  for (double z : r.z) z_mean += z / static_cast<double>(r.z.size());
  const double Ty = period(r.t, r.y, 0.0), Tz = period(r.t, r.z, z_mean);
  const double rad = param("r"), g = param("g");
  const double closed = 2 * kPi * std::sqrt((1.0 - rad) * (1.0 + 0.4) / g);
  INFO("T_y " << Ty << ", T_z " << Tz << ", small-oscillation closed form " << closed);
  CHECK(Ty / Tz == Approx(2.0).epsilon(1e-3));
  CHECK(Ty == Approx(closed).epsilon(2e-3));
}

TEST_CASE("sphere trough: --state minimal agrees with the full state", "[numeric][rolling_sphere][minimal_state]") {
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<double> xm(static_cast<std::size_t>(M::kNx));
    for (double& v : xm) v = U(rng);
    double e[4] = {1 + U(rng), U(rng), U(rng), U(rng)};
    const double n = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3]);
    for (int k = 0; k < 4; ++k)
      xm[static_cast<std::size_t>(index_of(M::kStateNames, M::kNx, ("ball.e" + std::to_string(k)).c_str()))] = e[k] / n;
    std::vector<double> xf(static_cast<std::size_t>(F::kNx)), df(xf.size()), dm(xm.size());
    REQUIRE(M::full_state(0.3, xm.data(), nullptr, M::kParamDefaults, xf.data()) == 0);
    REQUIRE(F::rhs(0.3, xf.data(), nullptr, F::kParamDefaults, df.data()) == 0);
    REQUIRE(M::rhs(0.3, xm.data(), nullptr, M::kParamDefaults, dm.data()) == 0);
    std::array<double, F::kNposc> g{};
    std::array<double, F::kNc> v{};
    REQUIRE(F::position_constraints(0.3, xf.data(), nullptr, F::kParamDefaults, g.data()) == 0);
    REQUIRE(F::velocity_constraints(0.3, xf.data(), nullptr, F::kParamDefaults, v.data()) == 0);
    for (double x : g) CHECK(std::fabs(x) < 1e-14);
    for (double x : v) CHECK(std::fabs(x) < 1e-13);
    for (int k = 0; k < M::kNx; ++k) {
      const std::size_t j = ix(M::kStateNames[k]);
      INFO(M::kStateNames[k] << " trial " << trial);
      CHECK(dm[static_cast<std::size_t>(k)] == Approx(df[j]).margin(1e-11));
    }
  }
}
