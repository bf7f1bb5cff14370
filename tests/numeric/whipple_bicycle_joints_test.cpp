// SPDX-License-Identifier: GPL-2.0-or-later
// The Whipple bicycle in joint coordinates (models/whipple_bicycle_joints.mbs: the wheels
// and the front frame placed by `revolute ... coordinate` joints, the rear frame's
// attitude in zxy angles) against
//  * the same bicycle in absolute coordinates (models/whipple_bicycle.mbs, four quaternion
//    bodies): the same motion from the same initial state, the same energy;
//  * the paper's linearized equations and its Table 2 eigenvalues at 5 m/s (Meijaard,
//    Papadopoulos, Ruina and Schwab, Proc. R. Soc. A 463 (2007)): lean and steer
//    accelerations at an upright state, and weave and capsize from a nonlinear run;
//  * itself: the degrees of freedom, upright running as an exact solution, energy
//    conservation, complement = multipliers = --state minimal.
#include <catch2/catch.hpp>
#include <array>
#include <cmath>
#include <iomanip>
#include <string>
#include <vector>

#include "bicycle_modes.hpp"
#include "sampled_run.hpp"
#include "mbsc/runtime/assemble.hpp"
#include "test_support.hpp"
#include "whipple_bicycle/whipple_bicycle.hpp"
#include "whipple_bicycle_joints/whipple_bicycle_joints.hpp"
#include "whipple_bicycle_joints_min/whipple_bicycle_joints_min.hpp"
#include "whipple_bicycle_joints_mult/whipple_bicycle_joints_mult.hpp"

namespace A = mbsc_gen::whipple_bicycle;  // absolute coordinates
namespace J = mbsc_gen::whipple_bicycle_joints;
namespace JM = mbsc_gen::whipple_bicycle_joints_mult;
namespace JN = mbsc_gen::whipple_bicycle_joints_min;
using mbsc_test::index_of;
using mbsc_test::Modes;
using mbsc_test::modes_from_lean;
using mbsc_test::sampled_run;

namespace {

using State = std::vector<double>;

double param(const char* name) { return J::kParamDefaults[index_of(J::kParamNames, J::kNp, name)]; }

std::size_t at_j(const std::string& name) { return static_cast<std::size_t>(index_of(J::kStateNames, J::kNx, name)); }
std::size_t at_a(const std::string& name) { return static_cast<std::size_t>(index_of(A::kStateNames, A::kNx, name)); }

const std::array<const char*, 4> kBodies{"rear_wheel", "rear_frame", "front_frame", "front_wheel"};

/// Upright and straight at the reference pose, riding at v with lean rate `lean_rate`
/// and steer rate 0: the bicycle turns about the ground line through both contact points
/// (the x axis), so a mass centre at height z moves sideways at -lean_rate z. The same
/// physical state in the joint model (`joints`) or the absolute one.
State upright(double v, double lean_rate, bool joints) {
  State x(static_cast<std::size_t>(joints ? J::kNx : A::kNx), 0.0);
  auto at = [&](const std::string& n) { return joints ? at_j(n) : at_a(n); };
  const std::array<double, 4> xc{0.0, param("xB"), param("xH"), param("w")};
  const std::array<double, 4> zc{-param("rR"), param("zB"), param("zH"), -param("rF")};
  for (std::size_t k = 0; k < kBodies.size(); ++k) {
    const std::string b = kBodies[k];
    x[at(b + ".x")] = xc[k];
    x[at(b + ".z")] = zc[k];
    if (!joints) x[at(b + ".e0")] = 1.0;
    x[at(b + ".u")] = v;
    x[at(b + ".v")] = -lean_rate * zc[k];
    x[at(b + ".wx")] = lean_rate;
  }
  x[at("rear_wheel.wy")] = -v / param("rR");
  x[at("front_wheel.wy")] = -v / param("rF");
  if (joints) {
    x[at("theta_R_dot")] = -v / param("rR");
    x[at("theta_F_dot")] = -v / param("rF");
  }
  return x;
}

/// The rear frame's lean: the z component of its y axis is sin(lean). In the joint model
/// that is sin(theta) of its zxy angles; in the absolute one, from the quaternion.
double lean_j(const State& x) { return x[at_j("rear_frame.theta")]; }
double lean_a(const State& x) {
  const double* e = &x[at_a("rear_frame.e0")];
  const double n2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3];
  return std::asin(2 * (e[2] * e[3] + e[0] * e[1]) / n2);
}

double max_abs(const State& a) {
  double m = 0.0;
  for (double v : a) m = std::max(m, std::fabs(v));
  return m;
}

const auto rhs_j = [](double t, const double* s, double* sd) { return J::rhs(t, s, nullptr, J::kParamDefaults, sd); };
const auto rhs_a = [](double t, const double* s, double* sd) { return A::rhs(t, s, nullptr, A::kParamDefaults, sd); };

/// A consistent state near x (joint model): the coordinates by least-squares Newton steps
/// from x, then every speed but the independent ones from the velocity rows.
State assembled(State x) {
  std::vector<bool> given_q(static_cast<std::size_t>(J::kNq), false), given_u(static_cast<std::size_t>(J::kNu), false);
  for (int k = 0; k < J::kNdof; ++k) given_u[at_j(J::kDofNames[k]) - static_cast<std::size_t>(J::kNq)] = true;
  mbsc::runtime::AssemblyOptions opt;
  opt.tolerance = 1e-14;
  const auto r = mbsc::runtime::assemble(MBSC_TEST_ASSEMBLY_MODEL(J), 0.0, x, given_q, given_u, nullptr, J::kParamDefaults, opt);
  INFO(r.message);
  REQUIRE(r.ok());
  return x;
}

/// States along a strongly perturbed run (leaning, steering and turning), re-assembled.
std::vector<State> moving_states() {
  std::vector<State> out;
  sampled_run(rhs_j, assembled(upright(4.0, 0.8, true)), 1.5, 0.25, 1e-10, [&](double t, const State& s) {
    if (t > 0) out.push_back(assembled(s));
  });
  return out;
}

double energy_j(const State& x) {
  std::array<double, 3> e{};
  REQUIRE(J::energy(0.0, x.data(), nullptr, J::kParamDefaults, e.data()) == 0);
  return e[2];
}
double energy_a(const State& x) {
  std::array<double, 3> e{};
  REQUIRE(A::energy(0.0, x.data(), nullptr, A::kParamDefaults, e.data()) == 0);
  return e[2];
}

}  // namespace

TEST_CASE("Whipple bicycle in joint coordinates: the paper's degrees of freedom", "[numeric][bicycle]") {
  CHECK(J::kNdof == 3);             // rear wheel rate, lean rate, steer rate
  CHECK(J::kNu == 4 * 6 + 3);       // body speeds and the three joint rates
  CHECK(J::kNq == 4 * 3 + 3 + 3);   // reference points, the rear frame's angles, joint angles
  CHECK(J::kNposc == 3 * 3 + 2);    // each joint's placement, each wheel's contact height
  CHECK(J::kNc == J::kNu - 3);
  CHECK(J::kNq - J::kNposc == 7);   // configuration degrees of freedom, as in the paper
  // No quaternion: the absolute model's 28 coordinates less 4 x 4 quaternion entries,
  // plus the rear frame's 3 angles and the 3 joint angles.
  CHECK(J::kNq == A::kNq - 16 + 3 + 3);
}

TEST_CASE("Whipple bicycle in joint coordinates: upright straight running is an exact solution", "[numeric][bicycle]") {
  const double v = 4.6;
  const State x0 = upright(v, 0.0, true);
  std::vector<double> c(static_cast<std::size_t>(J::kNc)), g(static_cast<std::size_t>(J::kNposc));
  REQUIRE(J::position_constraints(0.0, x0.data(), nullptr, J::kParamDefaults, g.data()) == 0);
  REQUIRE(J::velocity_constraints(0.0, x0.data(), nullptr, J::kParamDefaults, c.data()) == 0);
  CHECK(max_abs(g) < 1e-15);
  CHECK(max_abs(c) < 1e-14);
  State xd(static_cast<std::size_t>(J::kNx));
  REQUIRE(J::rhs(0.0, x0.data(), nullptr, J::kParamDefaults, xd.data()) == 0);
  for (int k = J::kNq; k < J::kNx; ++k) {
    INFO(J::kStateNames[k]);
    CHECK(std::fabs(xd[static_cast<std::size_t>(k)]) < 1e-12);
  }
}

TEST_CASE("Whipple bicycle in joint coordinates: the same motion as in absolute coordinates", "[numeric][bicycle]") {
  // Started at 4 m/s with a lean rate of 0.8 rad/s: it leans, steers and turns by tens of
  // degrees. Both models start from the same physical state (consistent as given) and
  // are integrated at 1e-12; the lean, the mass centres and the rear frame's speeds must
  // agree along 3 s, and so must the energies (the same expression of different states).
  const State xj0 = upright(4.0, 0.8, true), xa0 = upright(4.0, 0.8, false);
  CHECK(energy_j(xj0) == Approx(energy_a(xa0)).epsilon(1e-14));
  std::vector<State> sj, sa;
  sampled_run(rhs_j, xj0, 3.0, 0.1, 1e-12, [&](double, const State& s) { sj.push_back(s); });
  sampled_run(rhs_a, xa0, 3.0, 0.1, 1e-12, [&](double, const State& s) { sa.push_back(s); });
  REQUIRE(sj.size() == sa.size());
  double worst_lean = 0.0, worst_pos = 0.0, worst_speed = 0.0, max_lean = 0.0, max_yaw = 0.0;
  for (std::size_t k = 0; k < sj.size(); ++k) {
    worst_lean = std::max(worst_lean, std::fabs(lean_j(sj[k]) - lean_a(sa[k])));
    max_lean = std::max(max_lean, std::fabs(lean_j(sj[k])));
    max_yaw = std::max(max_yaw, std::fabs(sj[k][at_j("rear_frame.phi")]));
    for (const char* b : kBodies)
      for (const char* c : {".x", ".y", ".z"})
        worst_pos = std::max(worst_pos, std::fabs(sj[k][at_j(std::string(b) + c)] - sa[k][at_a(std::string(b) + c)]));
    for (const char* c : {"u", "v", "w", "wx", "wy", "wz"}) {
      const std::string n = std::string("rear_frame.") + c;
      worst_speed = std::max(worst_speed, std::fabs(sj[k][at_j(n)] - sa[k][at_a(n)]));
    }
  }
  INFO("largest lean " << max_lean << " rad, yaw " << max_yaw << " rad; differences: lean " << worst_lean
                       << ", positions " << worst_pos << " m, rear frame speeds " << worst_speed);
  CHECK(max_lean > 0.2);  // a genuinely nonlinear run
  CHECK(max_yaw > 0.2);
  CHECK(worst_lean < 1e-8);
  CHECK(worst_pos < 1e-8);
  CHECK(worst_speed < 1e-7);
}

TEST_CASE("Whipple bicycle in joint coordinates: energy is conserved", "[numeric][bicycle]") {
  const State x0 = assembled(upright(4.0, 0.8, true));
  const double e0 = energy_j(x0);
  double worst = 0.0;
  sampled_run(rhs_j, x0, 3.0, 0.05, 1e-12, [&](double, const State& s) { worst = std::max(worst, std::fabs(energy_j(s) - e0)); });
  INFO("energy " << e0 << " J, largest change " << worst << " J");
  CHECK(worst < 1e-9 * std::fabs(e0));
}

TEST_CASE("Whipple bicycle in joint coordinates: complement, multipliers and --state minimal agree", "[numeric][bicycle]") {
  REQUIRE(JM::kNx == J::kNx);
  REQUIRE(JN::kNxFull == J::kNx);
  for (const State& x : moving_states()) {
    State xd(static_cast<std::size_t>(J::kNx)), xdm(static_cast<std::size_t>(J::kNx));
    REQUIRE(J::rhs(0.0, x.data(), nullptr, J::kParamDefaults, xd.data()) == 0);
    REQUIRE(JM::rhs(0.0, x.data(), nullptr, JM::kParamDefaults, xdm.data()) == 0);
    const double scale = std::max(1.0, max_abs(xd));
    for (int k = 0; k < J::kNx; ++k) {
      INFO(J::kStateNames[k]);
      REQUIRE(std::string(J::kStateNames[k]) == JM::kStateNames[k]);
      CHECK(xdm[static_cast<std::size_t>(k)] == Approx(xd[static_cast<std::size_t>(k)]).margin(1e-9 * scale));
    }
    State xn(static_cast<std::size_t>(JN::kNx)), xdn(static_cast<std::size_t>(JN::kNx));
    for (int k = 0; k < JN::kNx; ++k) xn[static_cast<std::size_t>(k)] = x[at_j(JN::kStateNames[k])];
    REQUIRE(JN::rhs(0.0, xn.data(), nullptr, JN::kParamDefaults, xdn.data()) == 0);
    for (int k = 0; k < JN::kNx; ++k) {
      INFO(JN::kStateNames[k]);
      CHECK(xdn[static_cast<std::size_t>(k)] == Approx(xd[at_j(JN::kStateNames[k])]).margin(1e-9 * scale));
    }
  }
}

TEST_CASE("Whipple bicycle in joint coordinates: lean and steer accelerations match the paper's linear equations",
          "[numeric][bicycle]") {
  // M q'' + v C1 q' + (g K0 + v^2 K2) q = 0 for q = (lean, steer) with the paper's matrices
  // (its section 3). Upright with a small lean rate and no steer rate:
  // q'' = -v M^-1 C1 (lean rate, 0) up to terms cubic in the rates. Here the lean
  // acceleration is rear_frame.wx' and the steer acceleration delta_dot' itself.
  const double M[2][2] = {{80.81722, 2.31941332208709}, {2.31941332208709, 0.29784188199686}};
  const double C1_10 = -0.85035641456978;
  const double det = M[0][0] * M[1][1] - M[0][1] * M[1][0];
  for (const double v : {3.0, 5.0, 8.0}) {
    const double lean_rate = 1e-3;
    const double b = -v * C1_10 * lean_rate;
    const double lean_acc = -M[0][1] * b / det, steer_acc = M[0][0] * b / det;
    const State x = upright(v, lean_rate, true);
    State xd(static_cast<std::size_t>(J::kNx));
    REQUIRE(J::rhs(0.0, x.data(), nullptr, J::kParamDefaults, xd.data()) == 0);
    INFO("v = " << v);
    CHECK(xd[at_j("rear_frame.wx")] == Approx(lean_acc).epsilon(1e-6));
    CHECK(xd[at_j("delta_dot")] == Approx(steer_acc).epsilon(1e-6));
  }
}

TEST_CASE("Whipple bicycle in joint coordinates: weave and capsize eigenvalues at 5 m/s", "[numeric][bicycle]") {
  // A nonlinear run with a tiny lean rate, the lean sampled every 0.1 s from t = 1 s
  // (bicycle_modes.hpp), against the paper's Table 2 at 5 m/s (measured here:
  // -0.7753418895 +- 4.464867718 i and -0.3228664262, within 1e-8 relative).
  const double dt = 0.1;
  std::vector<double> lean;
  sampled_run(rhs_j, upright(5.0, 1e-4, true), 6.0, dt, 1e-13, [&](double t, const State& s) {
    if (t > 1.0 - 1e-9) lean.push_back(lean_j(s));
  });
  const Modes m = modes_from_lean(lean, dt);
  INFO(std::setprecision(10) << "weave " << m.weave << ", capsize " << m.capsize);
  REQUIRE(m.oscillating == 2);
  CHECK(m.weave.real() == Approx(-0.775341882195845).epsilon(1e-6));
  CHECK(m.weave.imag() == Approx(4.464867713788234).epsilon(1e-6));
  CHECK(m.capsize == Approx(-0.322866429004087).epsilon(1e-6));
}
