// SPDX-License-Identifier: GPL-2.0-or-later
// The heavy symmetric top of models/heavy_top.mbs (a rigid3d body held at its tip by a
// spherical joint to the ground) against the closed form of steady precession: at tilt
// theta and spin n about the symmetry axis, the axis turns about the vertical at a rate
// Omega with I1 Omega^2 cos(theta) - C n Omega + m g l = 0 (I1 = A + m l^2 about the tip).
// Started in such a motion, the compiled model must keep theta and advance the axis's
// azimuth at Omega, for both roots (slow and fast precession); energy is conserved,
// the tip stays at the origin, and the multipliers form gives the same accelerations.
#include <catch2/catch.hpp>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "heavy_top/heavy_top.hpp"
#include "heavy_top_mult/heavy_top_mult.hpp"
#include "mbsc/runtime/dop853.hpp"
#include "test_support.hpp"

namespace T = mbsc_gen::heavy_top;
namespace TM = mbsc_gen::heavy_top_mult;
using mbsc_test::index_of;

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Params {
  double m, g, l, A, C;
};
Params params() {
  const double* p = T::kParamDefaults;
  REQUIRE(std::string(T::kParamNames[0]) == "m");
  REQUIRE(std::string(T::kParamNames[4]) == "C");
  return {p[0], p[1], p[2], p[3], p[4]};
}

double& at(std::vector<double>& x, const char* name) { return x[static_cast<std::size_t>(index_of(T::kStateNames, T::kNx, name))]; }

/// The symmetry axis (body z) in space, from the (normalized) quaternion.
std::array<double, 3> axis_of(const std::vector<double>& x) {
  const double* e = &x[static_cast<std::size_t>(index_of(T::kStateNames, T::kNx, "top.e0"))];
  const double n = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3]);
  const double w = e[0] / n, a = e[1] / n, b = e[2] / n, c = e[3] / n;
  return {2 * (a * c + w * b), 2 * (b * c - w * a), 1 - 2 * (a * a + b * b)};
}

/// A state in steady precession at rate Omega, tilt theta, spin n: attitude Rx(theta),
/// angular velocity Omega z + (n - Omega cos theta) e3 in space, tip at the origin.
std::vector<double> steady_state(double theta, double n, double Omega, const Params& P) {
  std::vector<double> x(static_cast<std::size_t>(T::kNx), 0.0);
  at(x, "top.e0") = std::cos(theta / 2);
  at(x, "top.e1") = std::sin(theta / 2);
  const double s = std::sin(theta), c = std::cos(theta);
  const std::array<double, 3> e3{0, -s, c};
  const double spin = n - Omega * c;
  const std::array<double, 3> w{spin * e3[0], spin * e3[1], Omega + spin * e3[2]};
  // Body components: R^T w with R = Rx(theta).
  at(x, "top.wx") = w[0];
  at(x, "top.wy") = c * w[1] + s * w[2];
  at(x, "top.wz") = -s * w[1] + c * w[2];
  const std::array<double, 3> r{P.l * e3[0], P.l * e3[1], P.l * e3[2]};
  at(x, "top.x") = r[0], at(x, "top.y") = r[1], at(x, "top.z") = r[2];
  at(x, "top.u") = w[1] * r[2] - w[2] * r[1];
  at(x, "top.v") = w[2] * r[0] - w[0] * r[2];
  at(x, "top.w") = w[0] * r[1] - w[1] * r[0];
  return x;
}

}  // namespace

TEST_CASE("heavy top: steady precession at the closed-form rates", "[numeric][spatial_joints]") {
  const Params P = params();
  const double I1 = P.A + P.m * P.l * P.l;
  const double theta = 0.5, n = 60.0;
  const double a = I1 * std::cos(theta), b = -P.C * n, c = P.m * P.g * P.l;
  const double disc = std::sqrt(b * b - 4 * a * c);
  const std::array<double, 2> rates{(-b - disc) / (2 * a), (-b + disc) / (2 * a)};
  for (const double Omega : rates) {
    INFO("Omega = " << Omega << " (roots " << rates[0] << ", " << rates[1] << ")");
    std::vector<double> x = steady_state(theta, n, Omega, P);
    mbsc::runtime::StepperOptions o;
    o.rtol = o.atol = 1e-13;
    auto rhs = [](double t, const double* s, double* sd) { return T::rhs(t, s, nullptr, T::kParamDefaults, sd); };
    mbsc::runtime::Dop853 stepper(rhs, T::kNx, o);
    REQUIRE(stepper.reset(0.0, x) == mbsc::runtime::Stepper::Status::Ok);
    std::array<double, 3> e0{};  // kinetic, potential, total
    REQUIRE(T::energy(0.0, x.data(), nullptr, T::kParamDefaults, e0.data()) == 0);
    double worst_tilt = 0.0, worst_azimuth = 0.0, worst_energy = 0.0, worst_tip = 0.0;
    for (int k = 1; k <= 20; ++k) {
      const double t = 0.05 * k;
      while (stepper.t() < t) REQUIRE(stepper.step(t) == mbsc::runtime::Stepper::Status::Ok);
      std::vector<double> s(static_cast<std::size_t>(T::kNx));
      stepper.interpolate(t, s);
      const auto e3 = axis_of(s);
      worst_tilt = std::max(worst_tilt, std::fabs(std::acos(e3[2]) - theta));
      // Azimuth starts at -pi/2 and grows at Omega (difference wrapped to (-pi, pi]).
      double d = std::atan2(e3[1], e3[0]) - (-kPi / 2 + Omega * t);
      d = std::remainder(d, 2 * kPi);
      worst_azimuth = std::max(worst_azimuth, std::fabs(d));
      std::array<double, 3> e{};
      REQUIRE(T::energy(t, s.data(), nullptr, T::kParamDefaults, e.data()) == 0);
      worst_energy = std::max(worst_energy, std::fabs(e[2] - e0[2]));
      // The tip, l below the mass centre along the axis, stays at the origin.
      const double* r = &s[static_cast<std::size_t>(index_of(T::kStateNames, T::kNx, "top.x"))];
      worst_tip = std::max(worst_tip, std::hypot(r[0] - P.l * e3[0], r[1] - P.l * e3[1], r[2] - P.l * e3[2]));
    }
    CHECK(worst_tilt < 1e-8);
    CHECK(worst_azimuth < 1e-8);
    CHECK(worst_energy < 1e-9);
    CHECK(worst_tip < 1e-9);
  }
}

TEST_CASE("heavy top: both formulations give the same accelerations", "[numeric][spatial_joints]") {
  const Params P = params();
  REQUIRE(TM::kNx == T::kNx);
  std::vector<double> pm(TM::kParamDefaults, TM::kParamDefaults + TM::kNp);
  for (double theta : {0.2, 0.7, 1.3}) {
    for (double Omega : {-2.0, 0.5, 4.0}) {
      const std::vector<double> x = steady_state(theta, 25.0 + theta, Omega, P);
      std::vector<double> xd(static_cast<std::size_t>(T::kNx)), xdm(static_cast<std::size_t>(T::kNx));
      REQUIRE(T::rhs(0.0, x.data(), nullptr, T::kParamDefaults, xd.data()) == 0);
      REQUIRE(TM::rhs(0.0, x.data(), nullptr, pm.data(), xdm.data()) == 0);
      for (int k = 0; k < T::kNx; ++k) {
        REQUIRE(std::string(T::kStateNames[k]) == TM::kStateNames[k]);
        CHECK(xdm[static_cast<std::size_t>(k)] == Approx(xd[static_cast<std::size_t>(k)]).margin(1e-9));
      }
    }
  }
}
