// SPDX-License-Identifier: GPL-2.0-or-later
// Force elements in space (src/model/spatial_forces.cpp) on compiled models:
//  - tests/data/spatial_forces/spring_pair.mbs (two free bodies): each spring's and the
//    damper's generalized forces, isolated as forcing(element on) - forcing(all off),
//    give the virtual power of the element at random states: Q . z = -dV/dt for a spring
//    (V its potential, from the energy output, differentiated numerically along the
//    motion), Q . z = -c L'^2 for the damper (L from a zero-length spring on the same
//    points); energy is conserved with springs and gravity over a run; coinciding points
//    make the rhs report a non-finite value (status 2), not a NaN;
//  - tests/data/spatial_forces/hinge.mbs (a pendulum on a spatial revolute joint): the
//    angular acceleration with the actuator torque, the torsional spring, the torsional
//    damper and gravity at once is the closed form J theta'' = tau - kr (theta - th0) -
//    cr theta' - m g d sin(theta) at random states, in both formulations and with
//    --state minimal; small oscillations have the closed-form period; energy (spring
//    included) is conserved;
//    with a rest angle near pi the torque is continuous across theta = pi and the energy
//    is conserved through a swing across it (the angle wraps opposite the rest angle);
//  - tests/data/spatial_forces/hinge_pair_{ab,ba}.mbs (two free bodies on a revolute
//    joint, the moving body a first, then b first): the virtual power of the joint's
//    torque, the rotational spring and the rotational damper, each alone, at random
//    consistent states: tau (w2 - w1).n, -dV/dt, -c ((w2 - w1).n)^2 (the reaction on the
//    first body has the right sign);
//  - tests/data/spatial_forces/slider.mbs: prismatic and cylindrical actuators give the
//    closed-form accelerations along and about the axis.
#include <catch2/catch.hpp>
#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "hinge/hinge.hpp"
#include "hinge_pair_ab/hinge_pair_ab.hpp"
#include "hinge_pair_ba/hinge_pair_ba.hpp"
#include "hinge_min/hinge_min.hpp"
#include "hinge_mult/hinge_mult.hpp"
#include "mbsc/runtime/dop853.hpp"
#include "mbsc/runtime/model_table.hpp"
#include "slider/slider.hpp"
#include "slider_min/slider_min.hpp"
#include "slider_mult/slider_mult.hpp"
#include "spring_pair/spring_pair.hpp"
#include "test_support.hpp"

using mbsc_test::index_of;

namespace {

constexpr double kPi = 3.14159265358979323846;

/// An angle taken into (-pi, pi].
double wrap(double a) { return std::atan2(std::sin(a), std::cos(a)); }

using mbsc::runtime::ModelTable;

/// Sets the state entry `name` when the state has it (a minimal state lacks some).
void put(const ModelTable& M, std::vector<double>& x, const std::string& name, double v) {
  const int i = ModelTable::find(M.state_names, M.nx, name.c_str());
  if (i >= 0) x[static_cast<std::size_t>(i)] = v;
}
double& param(const ModelTable& M, std::vector<double>& p, const char* name) {
  return p[static_cast<std::size_t>(index_of(M.param_names, M.np, name))];
}
std::vector<double> defaults(const ModelTable& M) { return {M.param_defaults, M.param_defaults + M.np}; }

// ---- spring_pair ----
namespace SP = mbsc_gen::spring_pair;
const ModelTable kPair = MBSC_MODEL_TABLE(SP);

/// Parameters with every force element and gravity off.
std::vector<double> all_off() {
  std::vector<double> p(SP::kParamDefaults, SP::kParamDefaults + SP::kNp);
  for (const char* n : {"g", "k1", "k0", "c", "k2"}) param(kPair, p, n) = 0;
  return p;
}

/// A random state of the two free bodies (unit quaternion for a, moderate angles for b).
std::vector<double> random_pair_state(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> x(static_cast<std::size_t>(SP::kNx));
  for (double& v : x) v = u(rng);
  std::array<double, 4> e{};
  double n = 0;
  for (double& v : e) v = u(rng), n += v * v;
  const char* names[] = {"a.e0", "a.e1", "a.e2", "a.e3"};
  for (int k = 0; k < 4; ++k) put(kPair, x, names[k], e[static_cast<std::size_t>(k)] / std::sqrt(n));
  put(kPair, x, "b.x", 0.7 + 0.2 * u(rng));  // keep the points of each element apart
  return x;
}

/// Potential energy at x with parameters p.
double potential(const std::vector<double>& x, const std::vector<double>& p) {
  std::array<double, 3> e{};
  REQUIRE(SP::energy(0.0, x.data(), nullptr, p.data(), e.data()) == 0);
  return e[1];
}

/// d/dt of f(x) along the motion: central difference along xdot = rhs(x).
template <class F>
double rate_along(const std::vector<double>& x, const std::vector<double>& p, F f) {
  std::vector<double> xd(x.size());
  REQUIRE(SP::rhs(0.0, x.data(), nullptr, p.data(), xd.data()) == 0);
  const double h = 1e-6;
  std::vector<double> xp = x, xm = x;
  for (std::size_t i = 0; i < x.size(); ++i) xp[i] += h * xd[i], xm[i] -= h * xd[i];
  return (f(xp) - f(xm)) / (2 * h);
}

/// The virtual power of the element switched on by p_on: (h_on - h_off) . z.
double element_power(const std::vector<double>& x, const std::vector<double>& p_on) {
  const std::vector<double> p_off = all_off();
  std::vector<double> h_on(static_cast<std::size_t>(SP::kNdof)), h_off(h_on.size());
  REQUIRE(SP::forcing(0.0, x.data(), nullptr, p_on.data(), h_on.data()) == 0);
  REQUIRE(SP::forcing(0.0, x.data(), nullptr, p_off.data(), h_off.data()) == 0);
  double P = 0;
  for (int i = 0; i < SP::kNdof; ++i)
    P += (h_on[static_cast<std::size_t>(i)] - h_off[static_cast<std::size_t>(i)]) *
         x[static_cast<std::size_t>(index_of(SP::kStateNames, SP::kNx, SP::kDofNames[i]))];
  return P;
}

}  // namespace

TEST_CASE("spatial springs: generalized forces give the virtual power -dV/dt", "[numeric][spatial_forces]") {
  std::mt19937 rng(12);
  for (const char* k : {"k1", "k0", "k2"}) {
    std::vector<double> p = all_off();
    param(kPair, p, k) = SP::kParamDefaults[index_of(SP::kParamNames, SP::kNp, k)];
    for (int trial = 0; trial < 20; ++trial) {
      const auto x = random_pair_state(rng);
      const double P = element_power(x, p);
      const double dV = rate_along(x, p, [&](const std::vector<double>& s) { return potential(s, p); });
      INFO("spring " << k << " trial " << trial << ": Q.z = " << P << ", -dV/dt = " << -dV);
      CHECK(std::fabs(P + dV) < 1e-6 * (1 + std::fabs(dV)));
      CHECK(std::fabs(dV) > 1e-3);  // the state moves the spring: the check is not 0 = 0
    }
  }
}

TEST_CASE("spatial damper: generalized forces give the virtual power -c L'^2", "[numeric][spatial_forces]") {
  std::mt19937 rng(7);
  std::vector<double> p = all_off(), p0 = all_off();
  const double c = SP::kParamDefaults[index_of(SP::kParamNames, SP::kNp, "c")];
  const double k0 = SP::kParamDefaults[index_of(SP::kParamNames, SP::kNp, "k0")];
  param(kPair, p, "c") = c;
  param(kPair, p0, "k0") = k0;  // a zero-length spring on the damper's points: V = k0 L^2 / 2
  for (int trial = 0; trial < 20; ++trial) {
    const auto x = random_pair_state(rng);
    const double P = element_power(x, p);
    const double Ld =
        rate_along(x, p, [&](const std::vector<double>& s) { return std::sqrt(2 * potential(s, p0) / k0); });
    INFO("trial " << trial << ": Q.z = " << P << ", -c L'^2 = " << -c * Ld * Ld);
    CHECK(std::fabs(P + c * Ld * Ld) < 1e-6 * (1 + c * Ld * Ld));
    CHECK(c * Ld * Ld > 1e-4);
  }
}

TEST_CASE("spatial springs: energy with spring potentials is conserved", "[numeric][spatial_forces]") {
  std::vector<double> p(SP::kParamDefaults, SP::kParamDefaults + SP::kNp);
  param(kPair, p, "c") = 0;
  std::mt19937 rng(3);
  auto x = random_pair_state(rng);
  mbsc::runtime::StepperOptions o;
  o.rtol = o.atol = 1e-12;
  auto rhs = [&](double t, const double* s, double* sd) { return SP::rhs(t, s, nullptr, p.data(), sd); };
  mbsc::runtime::Dop853 stepper(rhs, SP::kNx, o);
  REQUIRE(stepper.reset(0.0, x) == mbsc::runtime::Stepper::Status::Ok);
  std::array<double, 3> e0{}, e{};
  REQUIRE(SP::energy(0.0, x.data(), nullptr, p.data(), e0.data()) == 0);
  double worst = 0, swing = 0;
  while (stepper.t() < 2.0) {
    REQUIRE(stepper.step(2.0) == mbsc::runtime::Stepper::Status::Ok);
    std::vector<double> s(static_cast<std::size_t>(SP::kNx));
    stepper.interpolate(stepper.t(), s);
    // The quaternion's norm drifts by the integrator's error only; the energy reads it.
    REQUIRE(SP::energy(stepper.t(), s.data(), nullptr, p.data(), e.data()) == 0);
    worst = std::max(worst, std::fabs(e[2] - e0[2]));
    swing = std::max(swing, std::fabs(e[1] - e0[1]));
  }
  INFO("energy drift " << worst << ", potential swing " << swing);
  CHECK(worst < 1e-7);
  CHECK(swing > 0.1);  // energy really moves between kinetic and potential
}

TEST_CASE("spatial spring and damper at zero length report a non-finite value", "[numeric][spatial_forces]") {
  // Identity attitudes; b placed so that the damper's points a.R and b.S coincide:
  // a.R - a.com = (-0.15, 0.2, 0.1), b.S = (0.1, -0.1, 0.2).
  std::vector<double> x(static_cast<std::size_t>(SP::kNx), 0.0), xd(x.size());
  put(kPair, x, "a.e0", 1);
  put(kPair, x, "b.x", -0.25), put(kPair, x, "b.y", 0.3), put(kPair, x, "b.z", -0.1);
  put(kPair, x, "a.u", 0.3), put(kPair, x, "b.w", -0.2);
  std::vector<double> p(SP::kParamDefaults, SP::kParamDefaults + SP::kNp);
  CHECK(SP::rhs(0.0, x.data(), nullptr, p.data(), xd.data()) == 2);
  // The spring with a rest length, a.P on b.Q: a.P - a.com = (0.25, 0.1, 0), b.Q = (-0.2, 0, 0.05).
  put(kPair, x, "b.x", 0.45), put(kPair, x, "b.y", 0.1), put(kPair, x, "b.z", -0.05);
  param(kPair, p, "c") = 0;
  CHECK(SP::rhs(0.0, x.data(), nullptr, p.data(), xd.data()) == 2);
}

// ---- hinge ----

namespace {

/// A state of the pendulum at angle th about x, rate w: the hinge point (0, 0, d) of the
/// body stays at the origin.
std::vector<double> hinge_state(const ModelTable& M, double th, double w, double d) {
  std::vector<double> x(static_cast<std::size_t>(M.nx), 0.0);
  put(M, x, "p.e0", std::cos(th / 2));
  put(M, x, "p.e1", std::sin(th / 2));
  put(M, x, "p.wx", w);
  put(M, x, "p.y", d * std::sin(th));
  put(M, x, "p.z", -d * std::cos(th));
  put(M, x, "p.v", d * std::cos(th) * w);
  put(M, x, "p.w", d * std::sin(th) * w);
  return x;
}

void check_hinge_closed_form(const ModelTable& M, const char* label) {
  std::vector<double> p = defaults(M);
  param(M, p, "tau") = 0.7;
  param(M, p, "th0") = 0.2;
  param(M, p, "cr") = 0.15;
  const double m = param(M, p, "m"), g = param(M, p, "g"), d = param(M, p, "d");
  const double J = param(M, p, "Ixx") + m * d * d;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 20; ++trial) {
    const double th = 3.0 * u(rng), w = 2 * u(rng);  // the angle stays in (-pi, pi)
    auto x = hinge_state(M, th, w, d);
    std::vector<double> xd(x.size());
    REQUIRE(M.rhs(0.0, x.data(), nullptr, p.data(), xd.data()) == 0);
    // The spring's twist theta - th0 is taken in (-pi, pi]: it wraps opposite the rest angle.
    const double expected = (0.7 - param(M, p, "kr") * wrap(th - 0.2) - 0.15 * w - m * g * d * std::sin(th)) / J;
    const double got = xd[static_cast<std::size_t>(index_of(M.state_names, M.nx, "p.wx"))];
    INFO(label << " theta = " << th << " w = " << w);
    CHECK(got == Approx(expected).epsilon(1e-10).margin(1e-10));
  }
}

}  // namespace

TEST_CASE("spatial revolute: torque, torsional spring and damper give the closed-form acceleration",
          "[numeric][spatial_forces]") {
  check_hinge_closed_form(MBSC_MODEL_TABLE(mbsc_gen::hinge), "complement");
  check_hinge_closed_form(MBSC_MODEL_TABLE_MULTIPLIERS(mbsc_gen::hinge_mult), "multipliers");
  check_hinge_closed_form(MBSC_MODEL_TABLE(mbsc_gen::hinge_min), "minimal");
}

TEST_CASE("spatial revolute pendulum with a torsional spring: closed-form period, energy conserved",
          "[numeric][spatial_forces]") {
  namespace H = mbsc_gen::hinge;
  const ModelTable M = MBSC_MODEL_TABLE(H);
  std::vector<double> p = defaults(M);
  const double m = param(M, p, "m"), g = param(M, p, "g"), d = param(M, p, "d"), kr = param(M, p, "kr");
  const double J = param(M, p, "Ixx") + m * d * d;
  const double period = 2 * kPi * std::sqrt(J / (kr + m * g * d));
  for (const double amplitude : {1e-4, 1.0}) {
    auto x = hinge_state(M, amplitude, 0.0, d);
    mbsc::runtime::StepperOptions o;
    o.rtol = o.atol = 1e-12;
    auto rhs = [&](double t, const double* s, double* sd) { return H::rhs(t, s, nullptr, p.data(), sd); };
    mbsc::runtime::Dop853 stepper(rhs, H::kNx, o);
    REQUIRE(stepper.reset(0.0, x) == mbsc::runtime::Stepper::Status::Ok);
    std::array<double, 3> e0{}, e{};
    REQUIRE(H::energy(0.0, x.data(), nullptr, p.data(), e0.data()) == 0);
    // Times where the rate wx changes sign from - to + (the turning points at -amplitude)
    // and then + to -: successive + to - crossings are one period apart.
    const std::size_t iw = static_cast<std::size_t>(index_of(H::kStateNames, H::kNx, "p.wx"));
    std::vector<double> s(x.size()), crossings;
    double prev_t = 0, prev_w = 0, worst = 0;
    while (stepper.t() < 2.5 * period && crossings.size() < 2) {
      REQUIRE(stepper.step(3 * period) == mbsc::runtime::Stepper::Status::Ok);
      stepper.interpolate(stepper.t(), s);
      REQUIRE(H::energy(stepper.t(), s.data(), nullptr, p.data(), e.data()) == 0);
      worst = std::max(worst, std::fabs(e[2] - e0[2]));
      const double w = s[iw];
      if (prev_w > 0 && w <= 0) {  // bisect the crossing on the dense output
        double lo = prev_t, hi = stepper.t();
        for (int k = 0; k < 60; ++k) {
          const double mid = (lo + hi) / 2;
          stepper.interpolate(mid, s);
          (s[iw] > 0 ? lo : hi) = mid;
        }
        crossings.push_back((lo + hi) / 2);
      }
      prev_t = stepper.t(), prev_w = w;
    }
    REQUIRE(crossings.size() == 2);
    const double measured = crossings[1] - crossings[0];
    INFO("amplitude " << amplitude << ": period " << measured << " closed form (small angles) " << period
                      << ", energy drift " << worst);
    if (amplitude < 1e-3) CHECK(measured == Approx(period).epsilon(1e-7));
    else CHECK(measured > period * 1.01);  // gravity's sin softens the large swing: longer
    CHECK(worst < 1e-9 * (1 + std::fabs(e0[2])));
  }
}

TEST_CASE("spatial rotational spring with a rest angle near pi: torque continuous across pi, energy conserved",
          "[numeric][spatial_forces]") {
  namespace H = mbsc_gen::hinge;
  const ModelTable M = MBSC_MODEL_TABLE(H);
  std::vector<double> p = defaults(M);
  param(M, p, "g") = 0;  // the spring alone: a harmonic swing about th0
  param(M, p, "th0") = 3.0;
  const double kr = param(M, p, "kr"), m = param(M, p, "m"), d = param(M, p, "d");
  const double J = param(M, p, "Ixx") + m * d * d;
  const std::size_t iw = static_cast<std::size_t>(index_of(H::kStateNames, H::kNx, "p.wx"));
  auto accel = [&](double th) {
    auto x = hinge_state(M, th, 0.0, d);
    std::vector<double> xd(x.size());
    REQUIRE(H::rhs(0.0, x.data(), nullptr, p.data(), xd.data()) == 0);
    return xd[iw];
  };
  // Either side of theta = pi (the same pose up to 2e-9): the same torque -kr (pi - th0).
  const double below = accel(kPi - 1e-9), above = accel(-kPi + 1e-9);
  INFO("theta'' at pi-: " << below << ", at -pi+: " << above);
  CHECK(below == Approx(-kr * (kPi - 3.0) / J).epsilon(1e-6));
  CHECK(above == Approx(below).epsilon(1e-6));
  for (const double th : {2.9, 3.1, -3.1, -2.9, -0.2})
    CHECK(accel(th) == Approx(-kr * wrap(th - 3.0) / J).epsilon(1e-10).margin(1e-12));
  // A swing of amplitude about w sqrt(J / kr) = 0.45 about th0 = 3 crosses pi twice a period.
  auto x = hinge_state(M, 3.0, 2.0, d);
  mbsc::runtime::StepperOptions o;
  o.rtol = o.atol = 1e-12;
  auto rhs = [&](double t, const double* s, double* sd) { return H::rhs(t, s, nullptr, p.data(), sd); };
  mbsc::runtime::Dop853 stepper(rhs, H::kNx, o);
  REQUIRE(stepper.reset(0.0, x) == mbsc::runtime::Stepper::Status::Ok);
  std::array<double, 3> e0{}, e{};
  REQUIRE(H::energy(0.0, x.data(), nullptr, p.data(), e0.data()) == 0);
  const std::size_t iy = static_cast<std::size_t>(index_of(H::kStateNames, H::kNx, "p.y"));
  const std::size_t iz = static_cast<std::size_t>(index_of(H::kStateNames, H::kNx, "p.z"));
  std::vector<double> s(x.size());
  double worst = 0, prev_y = x[iy];
  int crossings = 0;  // of theta = pi: the mass centre (0, d sin, -d cos) passes over the top
  while (stepper.t() < 3.0) {
    REQUIRE(stepper.step(3.0) == mbsc::runtime::Stepper::Status::Ok);
    stepper.interpolate(stepper.t(), s);
    REQUIRE(H::energy(stepper.t(), s.data(), nullptr, p.data(), e.data()) == 0);
    worst = std::max(worst, std::fabs(e[2] - e0[2]));
    if (s[iz] > 0 && (s[iy] > 0) != (prev_y > 0)) ++crossings;
    prev_y = s[iy];
  }
  INFO("energy drift " << worst << " over " << crossings << " crossings of pi");
  CHECK(crossings >= 3);
  CHECK(worst < 1e-9 * (1 + std::fabs(e0[2])));
}

// ---- hinge_pair ----

namespace {

using V3 = std::array<double, 3>;
using Q4 = std::array<double, 4>;  // e0 (scalar), e1, e2, e3

V3 rotate(const Q4& q, const V3& v) {  // R(q) v
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  const double R[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                          {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                          {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
  return {R[0][0] * v[0] + R[0][1] * v[1] + R[0][2] * v[2], R[1][0] * v[0] + R[1][1] * v[1] + R[1][2] * v[2],
          R[2][0] * v[0] + R[2][1] * v[1] + R[2][2] * v[2]};
}
V3 rotate_back(const Q4& q, const V3& v) { return rotate({q[0], -q[1], -q[2], -q[3]}, v); }  // R(q)^T v
Q4 product(const Q4& a, const Q4& b) {
  return {a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3], a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
          a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1], a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]};
}
V3 cross3(const V3& a, const V3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot3(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// A state of the pair that satisfies the revolute joint (positions and speeds): body a
/// anywhere, b turned by theta about a's hinge axis (the x axes of both), turning at
/// rate thd relative to a. Also returns n (the hinge axis in space) and both angular
/// velocities in space.
struct PairState {
  std::vector<double> x;
  V3 n, wa, wb;
};
PairState pair_state(const ModelTable& M, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  const V3 pa{0.1, 0.2, -0.1}, pb{-0.2, 0.05, 0.1};  // the hinge points in the bodies
  Q4 qa{u(rng), u(rng), u(rng), u(rng)};
  const double len = std::sqrt(qa[0] * qa[0] + qa[1] * qa[1] + qa[2] * qa[2] + qa[3] * qa[3]);
  for (double& v : qa) v /= len;
  const double th = 3 * u(rng), thd = 2 * u(rng);
  const Q4 qb = product(qa, {std::cos(th / 2), std::sin(th / 2), 0, 0});
  const V3 xa{u(rng), u(rng), u(rng)}, va{u(rng), u(rng), u(rng)}, wa{u(rng), u(rng), u(rng)};
  const V3 n = rotate(qa, {1, 0, 0});
  const V3 wb{wa[0] + thd * n[0], wa[1] + thd * n[1], wa[2] + thd * n[2]};
  const V3 ra = rotate(qa, pa), rb = rotate(qb, pb);  // hinge point from each mass centre
  const V3 wra = cross3(wa, ra), wrb = cross3(wb, rb);
  PairState out{std::vector<double>(static_cast<std::size_t>(M.nx), 0.0), n, wa, wb};
  const V3 wa_body = rotate_back(qa, wa);
  const char* ax[3] = {"x", "y", "z"};
  const char* vel[3] = {"u", "v", "w"};
  const char* om[3] = {"wx", "wy", "wz"};
  for (int k = 0; k < 3; ++k) {
    const std::size_t i = static_cast<std::size_t>(k);
    put(M, out.x, std::string("a.") + ax[k], xa[i]);
    put(M, out.x, std::string("b.") + ax[k], xa[i] + ra[i] - rb[i]);
    put(M, out.x, std::string("a.") + vel[k], va[i]);
    put(M, out.x, std::string("b.") + vel[k], va[i] + wra[i] - wrb[i]);
    put(M, out.x, std::string("a.") + om[k], wa_body[i]);  // body-frame speeds
    put(M, out.x, std::string("b.") + om[k], wb[i]);       // space-frame speeds
  }
  for (int k = 0; k < 4; ++k) {
    put(M, out.x, "a.e" + std::to_string(k), qa[static_cast<std::size_t>(k)]);
    put(M, out.x, "b.e" + std::to_string(k), qb[static_cast<std::size_t>(k)]);
  }
  return out;
}

/// Virtual power of the element switched on in p_on (the rest off): (h_on - h_off) . z
/// over the independent speeds z; equal to Q . (all speeds) on a consistent state.
double pair_power(const ModelTable& M, const std::vector<double>& x, const std::vector<double>& p_on) {
  std::vector<double> p_off = defaults(M);
  for (const char* n : {"tau", "k", "c"}) param(M, p_off, n) = 0;
  std::vector<double> h_on(static_cast<std::size_t>(M.ndof)), h_off(h_on.size());
  REQUIRE(M.forcing(0.0, x.data(), nullptr, p_on.data(), h_on.data()) == 0);
  REQUIRE(M.forcing(0.0, x.data(), nullptr, p_off.data(), h_off.data()) == 0);
  double P = 0;
  for (int i = 0; i < M.ndof; ++i)
    P += (h_on[static_cast<std::size_t>(i)] - h_off[static_cast<std::size_t>(i)]) *
         x[static_cast<std::size_t>(index_of(M.state_names, M.nx, M.dof_names[i]))];
  return P;
}

/// b_first: the elements' first end is body b (hinge_pair_ba), else a.
void check_pair_power(const ModelTable& M, bool b_first, const char* label) {
  std::mt19937 rng(b_first ? 21 : 20);
  std::vector<double> off = defaults(M);
  for (const char* n : {"tau", "k", "c"}) param(M, off, n) = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const PairState st = pair_state(M, rng);
    INFO(label << " trial " << trial);
    // The state satisfies the joint (positions and speeds).
    std::vector<double> r(static_cast<std::size_t>(M.nc));
    REQUIRE(M.velocity_constraints(0.0, st.x.data(), nullptr, off.data(), r.data()) == 0);
    for (double v : r) REQUIRE(std::fabs(v) < 1e-12);
    r.assign(static_cast<std::size_t>(M.nposc), 0.0);
    REQUIRE(M.position_constraints(0.0, st.x.data(), nullptr, off.data(), r.data()) == 0);
    for (double v : r) REQUIRE(std::fabs(v) < 1e-12);
    // The relative rate about the first end's axis: second body's minus the first's.
    const V3& w1 = b_first ? st.wb : st.wa;
    const V3& w2 = b_first ? st.wa : st.wb;
    const double rate = dot3({w2[0] - w1[0], w2[1] - w1[1], w2[2] - w1[2]}, st.n);
    REQUIRE(std::fabs(rate) > 1e-3);  // (the random relative rate is not tiny: 0 = 0 is no check)
    std::vector<double> p = off;
    param(M, p, "tau") = 0.7;
    CHECK(pair_power(M, st.x, p) == Approx(0.7 * rate).epsilon(1e-9).margin(1e-12));
    p = off;
    param(M, p, "c") = 0.4;
    CHECK(pair_power(M, st.x, p) == Approx(-0.4 * rate * rate).epsilon(1e-9).margin(1e-12));
    p = off;
    param(M, p, "k") = 3.0;
    param(M, p, "th0") = 0.5;
    // -dV/dt along the motion (central difference along xdot = rhs(x)), V from the energy.
    std::vector<double> xd(st.x.size());
    REQUIRE(M.rhs(0.0, st.x.data(), nullptr, p.data(), xd.data()) == 0);
    auto V = [&](const std::vector<double>& s) {
      std::array<double, 3> e{};
      REQUIRE(M.energy(0.0, s.data(), nullptr, p.data(), e.data()) == 0);
      return e[1];
    };
    const double h = 1e-6;
    std::vector<double> xp = st.x, xm = st.x;
    for (std::size_t i = 0; i < xp.size(); ++i) xp[i] += h * xd[i], xm[i] -= h * xd[i];
    const double dV = (V(xp) - V(xm)) / (2 * h);
    CHECK(pair_power(M, st.x, p) == Approx(-dV).epsilon(1e-6).margin(1e-8));
  }
}

}  // namespace

TEST_CASE("spatial actuator, rotational spring and damper between two moving bodies: virtual power, both end orders",
          "[numeric][spatial_forces]") {
  check_pair_power(MBSC_MODEL_TABLE(mbsc_gen::hinge_pair_ab), false, "a first");
  check_pair_power(MBSC_MODEL_TABLE(mbsc_gen::hinge_pair_ba), true, "b first");
}

// ---- slider ----

namespace {

void check_slider(const ModelTable& M, const char* label) {
  std::vector<double> p = defaults(M);
  const double g = param(M, p, "g"), mb = param(M, p, "mb"), ms = param(M, p, "ms");
  const double n[3] = {0, 0.6, 0.8};
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 10; ++trial) {
    const double s1 = u(rng), v1 = u(rng), s2 = u(rng), v2 = u(rng), phi = 3 * u(rng), w = 2 * u(rng);
    std::vector<double> x(static_cast<std::size_t>(M.nx), 0.0);
    const char* ax[3] = {"x", "y", "z"};
    const char* vel[3] = {"u", "v", "w"};
    const char* om[3] = {"wx", "wy", "wz"};
    put(M, x, "block.e0", 1);
    put(M, x, "sleeve.e0", std::cos(phi / 2));
    for (int k = 0; k < 3; ++k) {
      put(M, x, std::string("block.") + ax[k], s1 * n[k]);
      put(M, x, std::string("block.") + vel[k], v1 * n[k]);
      put(M, x, std::string("sleeve.") + ax[k], s2 * n[k]);
      put(M, x, std::string("sleeve.") + vel[k], v2 * n[k]);
      put(M, x, std::string("sleeve.") + om[k], w * n[k]);  // space-frame speeds
      put(M, x, std::string("sleeve.e") + std::to_string(k + 1), std::sin(phi / 2) * n[k]);
    }
    std::vector<double> xd(x.size());
    REQUIRE(M.rhs(0.0, x.data(), nullptr, p.data(), xd.data()) == 0);
    // Compared where the state has the speed (a minimal state keeps the independent ones);
    // each motion (block along, sleeve along, sleeve about) must be compared at least once.
    int compared_block = 0, compared_slide = 0, compared_turn = 0;
    auto check = [&](const std::string& name, double expected, int& compared) {
      const int i = ModelTable::find(M.state_names, M.nx, name.c_str());
      if (i < 0) return;
      INFO(name);
      CHECK(xd[static_cast<std::size_t>(i)] == Approx(expected).margin(1e-10));
      ++compared;
    };
    INFO(label << " trial " << trial);
    const double ab = param(M, p, "F") / mb - g * n[2], as = param(M, p, "Fs") / ms - g * n[2];
    const double alpha = param(M, p, "T") / param(M, p, "Js");
    for (int k = 1; k < 3; ++k) {
      check(std::string("block.") + vel[k], ab * n[k], compared_block);
      check(std::string("sleeve.") + vel[k], as * n[k], compared_slide);
      check(std::string("sleeve.") + om[k], alpha * n[k], compared_turn);
    }
    CHECK(compared_block > 0);
    CHECK(compared_slide > 0);
    CHECK(compared_turn > 0);
  }
}

}  // namespace

TEST_CASE("spatial prismatic and cylindrical actuators: closed-form accelerations", "[numeric][spatial_forces]") {
  check_slider(MBSC_MODEL_TABLE(mbsc_gen::slider), "complement");
  check_slider(MBSC_MODEL_TABLE_MULTIPLIERS(mbsc_gen::slider_mult), "multipliers");
  check_slider(MBSC_MODEL_TABLE(mbsc_gen::slider_min), "minimal");
}
