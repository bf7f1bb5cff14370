// SPDX-License-Identifier: GPL-2.0-or-later
// The uniform thin disc of models/rolling_disc.mbs (the spatial `rolling` joint on the
// ground plane), compiled:
//  - rolling straight and upright at constant speed is an exact solution;
//  - a wobbling run with projection conserves energy, and the contact and no-slip rows
//    stay at the projection threshold;
//  - --state minimal agrees with the full state at random consistent states;
//  - the upright straight roll at spin Omega is stable exactly when Omega^2 > Omega_c^2 =
//    m g r A / (C (C + m r^2)) (docs/formulation.md, "Rolling contact in space"): with a
//    small lean rate eps the linearized lean is eps sinh(lambda t) / lambda below the
//    threshold and eps sin(mu t) / mu above it, with
//    (A + m r^2) lambda^2 = m g r - C (C + m r^2) Omega^2 / A = -(A + m r^2) mu^2;
//    runs at 0.9 and 1.1 Omega_c follow those curves.
//  - on the incline of models/rolling_disc_incline.mbs made thin (h = 0), upright rolling
//    straight down the slope is exact with the centre accelerating at g sin(alpha) /
//    (1 + C / (m r^2)) = 2/3 g sin(alpha).
// Both formulations agree at random assembled states in shipped_formulations_test.cpp.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "mbsc/runtime/dop853.hpp"
#include "mbsc/runtime/simulate.hpp"
#include "rolling_disc/rolling_disc.hpp"
#include "rolling_disc_incline/rolling_disc_incline.hpp"
#include "rolling_disc_min/rolling_disc_min.hpp"
#include "test_support.hpp"

namespace F = mbsc_gen::rolling_disc;
namespace M = mbsc_gen::rolling_disc_min;
using mbsc_test::index_of;

namespace {

constexpr double kQuarterTurn = 3.14159265358979323846 / 4;  // half of the -pi/2 turn about x

struct Params {
  double m, g, r, A, C;
};
Params params() {
  REQUIRE(std::string(F::kParamNames[0]) == "m");
  REQUIRE(std::string(F::kParamNames[1]) == "g");
  REQUIRE(std::string(F::kParamNames[2]) == "r");
  const double m = F::kParamDefaults[0], r = F::kParamDefaults[2];
  return {m, F::kParamDefaults[1], r, m * r * r / 4, m * r * r / 2};
}

std::size_t ix(const char* name) { return static_cast<std::size_t>(index_of(F::kStateNames, F::kNx, name)); }

/// Upright on the plane z = 0 with the spin axis (body z) along space y, rolling along +x
/// at spin Omega, with a lean rate eps about the direction of travel. Body x is space x,
/// body y is space -z, so the angular velocity in space is (wx, wz, -wy); the centre moves
/// with w x (r e_z) (the contact point is at rest).
std::vector<double> upright(double Omega, double eps, const Params& P) {
  std::vector<double> x(static_cast<std::size_t>(F::kNx), 0.0);
  x[ix("disc.e0")] = std::sqrt(0.5);
  x[ix("disc.e1")] = -std::sqrt(0.5);
  x[ix("disc.z")] = P.r;
  x[ix("disc.wx")] = eps;
  x[ix("disc.wz")] = Omega;
  x[ix("disc.u")] = P.r * Omega;
  x[ix("disc.v")] = -P.r * eps;
  return x;
}

/// The lean angle: the spin axis's elevation above the plane, asin(d_z), d = R e_z.
double lean(const std::vector<double>& x) {
  const double* e = &x[ix("disc.e0")];
  const double n2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3];
  return std::asin((e[0] * e[0] - e[1] * e[1] - e[2] * e[2] + e[3] * e[3]) / n2);
}

double critical_spin(const Params& P) { return std::sqrt(P.m * P.g * P.r * P.A / (P.C * (P.C + P.m * P.r * P.r))); }

/// Integrates the full-state model (dop853, tight) and samples the lean every dt.
std::vector<double> lean_history(std::vector<double> x, double t_end, double dt) {
  mbsc::runtime::StepperOptions o;
  o.rtol = o.atol = 1e-12;
  auto rhs = [](double t, const double* s, double* sd) { return F::rhs(t, s, nullptr, F::kParamDefaults, sd); };
  mbsc::runtime::Dop853 stepper(rhs, F::kNx, o);
  REQUIRE(stepper.reset(0.0, x) == mbsc::runtime::Stepper::Status::Ok);
  std::vector<double> out{lean(x)};
  for (int k = 1; k * dt <= t_end + 1e-12; ++k) {
    while (stepper.t() < k * dt) REQUIRE(stepper.step(k * dt) == mbsc::runtime::Stepper::Status::Ok);
    stepper.interpolate(k * dt, x);
    out.push_back(lean(x));
    if (std::fabs(out.back()) > 1.2) break;  // nearly flat: the rows' singularity ahead
  }
  return out;
}

}  // namespace

TEST_CASE("rolling disc: upright straight rolling at constant speed is exact", "[numeric][spatial_rolling]") {
  const Params P = params();
  const double Omega = 4.0;
  std::vector<double> x = upright(Omega, 0.0, P);
  std::vector<double> xd(x.size());
  REQUIRE(F::rhs(0.0, x.data(), nullptr, F::kParamDefaults, xd.data()) == 0);
  for (const char* s : {"disc.u", "disc.v", "disc.w", "disc.wx", "disc.wy", "disc.wz"}) {
    INFO(s << "' = " << xd[ix(s)]);
    CHECK(std::fabs(xd[ix(s)]) < 1e-12);
  }
  mbsc::runtime::StepperOptions o;
  o.rtol = o.atol = 1e-12;
  auto rhs = [](double t, const double* s, double* sd) { return F::rhs(t, s, nullptr, F::kParamDefaults, sd); };
  mbsc::runtime::Dop853 stepper(rhs, F::kNx, o);
  REQUIRE(stepper.reset(0.0, x) == mbsc::runtime::Stepper::Status::Ok);
  while (stepper.t() < 2.0) REQUIRE(stepper.step(2.0) == mbsc::runtime::Stepper::Status::Ok);
  stepper.interpolate(2.0, x);
  CHECK(x[ix("disc.x")] == Approx(P.r * Omega * 2.0).margin(1e-9));
  CHECK(std::fabs(x[ix("disc.y")]) < 1e-9);
  CHECK(x[ix("disc.z")] == Approx(P.r).margin(1e-9));
  CHECK(std::fabs(lean(x)) < 1e-9);
  CHECK(x[ix("disc.wz")] == Approx(Omega).margin(1e-9));
}

TEST_CASE("rolling disc: energy conserved, rows held by projection", "[numeric][spatial_rolling]") {
  const Params P = params();
  const auto model = MBSC_MODEL_TABLE(F);
  mbsc::runtime::StepperOptions so;
  so.rtol = 1e-10;
  so.atol = 1e-12;
  mbsc::runtime::SimulationOptions opt;
  opt.t_end = 10.0;
  opt.dt_out = 0.01;
  opt.unit_quaternions = {{static_cast<int>(ix("disc.e0")), static_cast<int>(ix("disc.e1")),
                           static_cast<int>(ix("disc.e2")), static_cast<int>(ix("disc.e3"))}};
  double worst_rows = 0.0, largest_lean = 0.0;
  auto observe = [&](double t, const std::vector<double>& x) {
    std::array<double, 1> g{};
    std::array<double, 3> v{};
    REQUIRE(F::position_constraints(t, x.data(), nullptr, F::kParamDefaults, g.data()) == 0);
    REQUIRE(F::velocity_constraints(t, x.data(), nullptr, F::kParamDefaults, v.data()) == 0);
    worst_rows = std::max({worst_rows, std::fabs(g[0]), std::fabs(v[0]), std::fabs(v[1]), std::fabs(v[2])});
    largest_lean = std::max(largest_lean, std::fabs(lean(x)));
  };
  // A wobbling roll: spin 5 rad/s (above Omega_c = 3.3) and a lean rate of 0.8 rad/s.
  const auto r = mbsc::runtime::simulate(model, "dop853", so, opt, upright(5.0, 0.8, P), {}, F::kParamDefaults, observe);
  INFO(r.message << "; energy drift " << r.energy_drift << " of " << r.energy_initial << "; rows " << worst_rows
                 << "; projections " << r.projections << "; largest lean " << largest_lean);
  REQUIRE(r.ok());
  CHECK(largest_lean > 0.1);  // a real wobble, not the upright roll
  CHECK(r.energy_defined);
  CHECK(r.energy_relative_drift < 1e-9);
  CHECK(worst_rows < 2e-9);
}

TEST_CASE("rolling disc: --state minimal agrees with the full state", "[numeric][spatial_rolling][minimal_state]") {
  // The minimal state keeps every coordinate but z (the contact row gives it) and the
  // three angular speeds; full_state rebuilds z and the centre's velocity.
  REQUIRE(M::kNq == F::kNq - 1);
  REQUIRE(M::kNu == 3);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<double> xm(static_cast<std::size_t>(M::kNx));
    for (double& v : xm) v = U(rng);
    // A unit quaternion near upright (lean and heading within about 0.5 rad).
    double e[4] = {std::sqrt(0.5) + 0.2 * U(rng), -std::sqrt(0.5) + 0.2 * U(rng), 0.2 * U(rng), 0.2 * U(rng)};
    const double n = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3]);
    for (int k = 0; k < 4; ++k)
      xm[static_cast<std::size_t>(index_of(M::kStateNames, M::kNx, ("disc.e" + std::to_string(k)).c_str()))] = e[k] / n;
    std::vector<double> xf(static_cast<std::size_t>(F::kNx)), df(xf.size()), dm(xm.size());
    REQUIRE(M::full_state(0.0, xm.data(), nullptr, M::kParamDefaults, xf.data()) == 0);
    REQUIRE(F::rhs(0.0, xf.data(), nullptr, F::kParamDefaults, df.data()) == 0);
    REQUIRE(M::rhs(0.0, xm.data(), nullptr, M::kParamDefaults, dm.data()) == 0);
    // The rebuilt state is consistent.
    std::array<double, 1> g{};
    std::array<double, 3> v{};
    REQUIRE(F::position_constraints(0.0, xf.data(), nullptr, F::kParamDefaults, g.data()) == 0);
    REQUIRE(F::velocity_constraints(0.0, xf.data(), nullptr, F::kParamDefaults, v.data()) == 0);
    CHECK(std::fabs(g[0]) < 1e-14);
    for (double r : v) CHECK(std::fabs(r) < 1e-13);
    for (int k = 0; k < M::kNx; ++k) {
      const std::size_t j = ix(M::kStateNames[k]);
      INFO(M::kStateNames[k] << " trial " << trial);
      CHECK(dm[static_cast<std::size_t>(k)] == Approx(df[j]).margin(1e-11));
    }
  }
}

TEST_CASE("rolling disc: upright rolling is stable above the closed-form spin", "[numeric][spatial_rolling]") {
  const Params P = params();
  const double Oc = critical_spin(P);
  CHECK(Oc * Oc == Approx(P.g / (3 * P.r)));  // the uniform thin disc: Omega_c^2 = g / (3 r)
  const double eps = 0.01, dt = 0.01;
  const double I = P.A + P.m * P.r * P.r;
  auto stiffness = [&](double Omega) { return (P.C * (P.C + P.m * P.r * P.r) * Omega * Omega / P.A - P.m * P.g * P.r) / I; };
  SECTION("below: 0.9 Omega_c, the lean grows as eps sinh(lambda t) / lambda and leaves the linear range") {
    const double Omega = 0.9 * Oc, lambda = std::sqrt(-stiffness(Omega));
    const auto h = lean_history(upright(Omega, eps, P), 6.0, dt);
    for (int k = 10; k <= 100; k += 10) {  // t = 0.1 .. 1 s: still linear (lean below 0.03)
      const double t = k * dt, linear = eps * std::sinh(lambda * t) / lambda;
      INFO("t = " << t << ": lean " << h[static_cast<std::size_t>(k)] << ", linearized " << linear);
      CHECK(h[static_cast<std::size_t>(k)] == Approx(linear).epsilon(0.03));
    }
    // Beyond the linear range the lean does not stay small: it grows past 0.1 rad (the
    // disc then swings through large leans while it turns; it need not fall flat).
    double largest = 0.0;
    for (double l : h) largest = std::max(largest, std::fabs(l));
    INFO("largest lean " << largest);
    CHECK(largest > 0.1);
  }
  SECTION("above: 1.1 Omega_c, the lean oscillates as eps sin(mu t) / mu and stays small") {
    const double Omega = 1.1 * Oc, mu = std::sqrt(stiffness(Omega));
    const auto h = lean_history(upright(Omega, eps, P), 6.0, dt);
    REQUIRE(h.size() == 601u);
    double largest = 0.0;
    for (double l : h) largest = std::max(largest, std::fabs(l));
    INFO("largest lean " << largest << ", linearized amplitude " << eps / mu);
    CHECK(largest == Approx(eps / mu).epsilon(0.03));
    for (int k = 10; k <= 100; k += 10) {
      const double t = k * dt, linear = eps * std::sin(mu * t) / mu;
      INFO("t = " << t << ": lean " << h[static_cast<std::size_t>(k)] << ", linearized " << linear);
      CHECK(h[static_cast<std::size_t>(k)] == Approx(linear).margin(0.03 * eps / mu));
    }
  }
}

TEST_CASE("rolling disc on the incline: thin and upright, it rolls straight down at 2/3 g sin(alpha)",
          "[numeric][spatial_rolling]") {
  namespace I = mbsc_gen::rolling_disc_incline;
  std::vector<double> p(I::kParamDefaults, I::kParamDefaults + I::kNp);
  auto param = [&](const char* name) -> double& {
    return p[static_cast<std::size_t>(index_of(I::kParamNames, I::kNp, name))];
  };
  param("h") = 0.0;  // thin: the contact circle is the mass centre's
  const double m = param("m"), g = param("g"), r = param("r"), alpha = param("alpha");
  const double C = m * r * r / 2, a = g * std::sin(alpha) / (1 + C / (m * r * r));
  REQUIRE(a == Approx(2.0 / 3.0 * g * std::sin(alpha)));
  auto at = [](std::vector<double>& x, const char* name) -> double& {
    return x[static_cast<std::size_t>(index_of(I::kStateNames, I::kNx, name))];
  };
  // Upright: Ry(alpha) Rx(-pi/2), the spin axis along y, the centre at r n above the
  // origin, moving downhill along t = (cos alpha, 0, -sin alpha) at V0 with spin V0 / r.
  const double V0 = 1.5, ca = std::cos(alpha / 2), sa = std::sin(alpha / 2), cb = std::cos(-kQuarterTurn),
               sb = std::sin(-kQuarterTurn);
  std::vector<double> x(static_cast<std::size_t>(I::kNx), 0.0);
  at(x, "coin.e0") = ca * cb, at(x, "coin.e1") = ca * sb, at(x, "coin.e2") = sa * cb, at(x, "coin.e3") = -sa * sb;
  at(x, "coin.x") = r * std::sin(alpha), at(x, "coin.z") = r * std::cos(alpha);
  at(x, "coin.u") = V0 * std::cos(alpha), at(x, "coin.w") = -V0 * std::sin(alpha);
  at(x, "coin.wz") = V0 / r;
  std::vector<double> xd(x.size());
  REQUIRE(I::rhs(0.0, x.data(), nullptr, p.data(), xd.data()) == 0);
  CHECK(at(xd, "coin.u") == Approx(a * std::cos(alpha)).margin(1e-12));
  CHECK(at(xd, "coin.v") == Approx(0.0).margin(1e-12));
  CHECK(at(xd, "coin.w") == Approx(-a * std::sin(alpha)).margin(1e-12));
  CHECK(at(xd, "coin.wx") == Approx(0.0).margin(1e-12));
  CHECK(at(xd, "coin.wy") == Approx(0.0).margin(1e-12));
  CHECK(at(xd, "coin.wz") == Approx(a / r).margin(1e-12));
  // And it stays so: after 1 s the centre has moved V0 + a/2 along the slope.
  mbsc::runtime::StepperOptions o;
  o.rtol = o.atol = 1e-12;
  auto rhs = [&p](double t, const double* s, double* sd) { return I::rhs(t, s, nullptr, p.data(), sd); };
  mbsc::runtime::Dop853 stepper(rhs, I::kNx, o);
  REQUIRE(stepper.reset(0.0, x) == mbsc::runtime::Stepper::Status::Ok);
  while (stepper.t() < 1.0) REQUIRE(stepper.step(1.0) == mbsc::runtime::Stepper::Status::Ok);
  stepper.interpolate(1.0, x);
  const double along = V0 + a / 2;
  CHECK(at(x, "coin.x") == Approx(r * std::sin(alpha) + along * std::cos(alpha)).margin(1e-9));
  CHECK(at(x, "coin.y") == Approx(0.0).margin(1e-9));
  CHECK(at(x, "coin.z") == Approx(r * std::cos(alpha) - along * std::sin(alpha)).margin(1e-9));
  CHECK(at(x, "coin.wz") == Approx((V0 + a) / r).margin(1e-9));
}
