// SPDX-License-Identifier: GPL-2.0-or-later
// rigid3d leaves (thesis Ex 2.1, 2.5): one free body with a full inertia tensor in four
// parametrizations (quaternion or Euler angles, body- or space-frame angular speeds).
// They are different ODEs for one motion: attitude, mass centre and angular velocity
// in space must agree; angular momentum about the mass centre (in space) and energy
// are conserved; a spin about a principal axis is the closed-form uniform rotation.
#include <catch2/catch.hpp>
#include <array>
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "free_body_euler/free_body_euler.hpp"
#include "free_body_euler_min/free_body_euler_min.hpp"
#include "free_body_euler_space/free_body_euler_space.hpp"
#include "free_body_principal/free_body_principal.hpp"
#include "free_body_quaternion/free_body_quaternion.hpp"
#include "free_body_quaternion_min/free_body_quaternion_min.hpp"
#include "free_body_quaternion_space/free_body_quaternion_space.hpp"
#include "mbsc/runtime/dop853.hpp"
#include "mbsc/runtime/simulate.hpp"
#include "torque_body/torque_body.hpp"
#include "torque_euler_space/torque_euler_space.hpp"
#include "torque_space/torque_space.hpp"
#include "test_support.hpp"

using mbsc_test::index_of;
using Mat = std::array<double, 9>;
using Vec3 = std::array<double, 3>;

namespace {

using Fn = int (*)(double, const double*, const double*, const double*, double*);

Mat mul(const Mat& a, const Mat& b) {
  Mat c{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) c[3 * i + j] += a[3 * i + k] * b[3 * k + j];
  return c;
}
Vec3 mul(const Mat& a, const Vec3& v) {
  Vec3 r{};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) r[i] += a[3 * i + k] * v[k];
  return r;
}
Vec3 mul_t(const Mat& a, const Vec3& v) {
  Vec3 r{};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) r[i] += a[3 * k + i] * v[k];
  return r;
}
/// Rotation by angle a about axis 'x', 'y' or 'z' (written independently of the compiler).
Mat axis(char ax, double a) {
  const double c = std::cos(a), s = std::sin(a);
  if (ax == 'x') return {1, 0, 0, 0, c, -s, 0, s, c};
  if (ax == 'y') return {c, 0, s, 0, 1, 0, -s, 0, c};
  return {c, -s, 0, s, c, 0, 0, 0, 1};
}
Mat euler(const char* seq, double a, double b, double c) { return mul(mul(axis(seq[0], a), axis(seq[1], b)), axis(seq[2], c)); }
/// Rotation of a unit quaternion (e0 scalar), normalized first.
Mat quaternion(const double* e) {
  const double n = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3]);
  const double w = e[0] / n, x = e[1] / n, y = e[2] / n, z = e[3] / n;
  return {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
          2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
          2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
}
/// Quaternion of a rotation matrix (Shepperd's largest-diagonal choice).
std::array<double, 4> quaternion_of(const Mat& R) {
  const double tr = R[0] + R[4] + R[8];
  std::array<double, 4> e{};
  if (tr > 0) {
    const double s = 2 * std::sqrt(1 + tr);
    e = {s / 4, (R[7] - R[5]) / s, (R[2] - R[6]) / s, (R[3] - R[1]) / s};
  } else if (R[0] > R[4] && R[0] > R[8]) {
    const double s = 2 * std::sqrt(1 + R[0] - R[4] - R[8]);
    e = {(R[7] - R[5]) / s, s / 4, (R[1] + R[3]) / s, (R[2] + R[6]) / s};
  } else if (R[4] > R[8]) {
    const double s = 2 * std::sqrt(1 + R[4] - R[0] - R[8]);
    e = {(R[2] - R[6]) / s, (R[1] + R[3]) / s, s / 4, (R[5] + R[7]) / s};
  } else {
    const double s = 2 * std::sqrt(1 + R[8] - R[0] - R[4]);
    e = {(R[3] - R[1]) / s, (R[2] + R[6]) / s, (R[5] + R[7]) / s, s / 4};
  }
  return e;
}

/// One generated form of the body.
struct Form {
  std::string name;
  Fn rhs, energy;
  const char* const* names;
  int nx;
  const double* params;
  std::string attitude;  // "quaternion" or the Euler sequence
  bool space;
  std::vector<double> x;
  double& at(const std::string& n) { return x[static_cast<std::size_t>(index_of(names, nx, n))]; }
  Mat rotation(const std::vector<double>& s) const {
    const int a = index_of(names, nx, attitude == "quaternion" ? "b.e0" : "b.phi");
    if (attitude == "quaternion") return quaternion(&s[static_cast<std::size_t>(a)]);
    return euler(attitude.c_str(), s[static_cast<std::size_t>(a)], s[static_cast<std::size_t>(a) + 1],
                 s[static_cast<std::size_t>(a) + 2]);
  }
  Vec3 omega_space(const std::vector<double>& s) const {
    const int w = index_of(names, nx, "b.wx");
    const Vec3 v{s[static_cast<std::size_t>(w)], s[static_cast<std::size_t>(w) + 1], s[static_cast<std::size_t>(w) + 2]};
    return space ? v : mul(rotation(s), v);
  }
  /// Starts at attitude R, body angular velocity wb, mass centre at rest at the origin
  /// moving with velocity v.
  void start(const Mat& R, const Vec3& wb, const Vec3& v) {
    x.assign(static_cast<std::size_t>(nx), 0.0);
    if (attitude == "quaternion") {
      const auto e = quaternion_of(R);
      at("b.e0") = e[0], at("b.e1") = e[1], at("b.e2") = e[2], at("b.e3") = e[3];
    } else if (attitude == "zyx") {  // R = Rz(a) Ry(b) Rx(c)
      at("b.phi") = std::atan2(R[3], R[0]);
      at("b.theta") = -std::asin(R[6]);
      at("b.psi") = std::atan2(R[7], R[8]);
    } else {  // zxz: R = Rz(a) Rx(b) Rz(c)
      at("b.phi") = std::atan2(R[2], -R[5]);
      at("b.theta") = std::acos(R[8]);
      at("b.psi") = std::atan2(R[6], R[7]);
    }
    const Vec3 w = space ? mul(R, wb) : wb;
    at("b.wx") = w[0], at("b.wy") = w[1], at("b.wz") = w[2];
    at("b.u") = v[0], at("b.v") = v[1], at("b.w") = v[2];
  }
  /// Angular momentum about the mass centre, space components: R I R^T w_space.
  Vec3 momentum(const std::vector<double>& s) const {
    const double* p = params;
    const Mat I{p[2], p[5], p[6], p[5], p[3], p[7], p[6], p[7], p[4]};  // Ixx Iyy Izz Ixy Ixz Iyz
    const Mat R = rotation(s);
    return mul(R, mul(I, mul_t(R, omega_space(s))));
  }
};

/// A Form of the generated model in namespace NS.
#define MAKE_FORM(NS, name, attitude, space) \
  Form { name, NS::rhs, NS::energy, NS::kStateNames, NS::kNx, NS::kParamDefaults, attitude, space, {} }

std::unique_ptr<mbsc::runtime::Dop853> integrator(Form& f, double tol) {
  mbsc::runtime::StepperOptions o;
  o.rtol = o.atol = tol;
  auto rhs = [&f](double t, const double* x, double* xd) { return f.rhs(t, x, nullptr, f.params, xd); };
  auto s = std::make_unique<mbsc::runtime::Dop853>(rhs, f.nx, o);
  REQUIRE(s->reset(0.0, f.x) == mbsc::runtime::Stepper::Status::Ok);
  return s;
}

void run_to(mbsc::runtime::Dop853& s, double t) {
  while (s.t() < t) REQUIRE(s.step(t) == mbsc::runtime::Stepper::Status::Ok);
}

const Mat kR0 = euler("zyx", 0.3, 0.4, -0.2);
const Vec3 kWb{1.0, -0.5, 2.0}, kV{0.5, -0.2, 3.0};

}  // namespace

namespace Q = mbsc_gen::free_body_quaternion;
namespace E = mbsc_gen::free_body_euler;
namespace QS = mbsc_gen::free_body_quaternion_space;
namespace ES = mbsc_gen::free_body_euler_space;
namespace P = mbsc_gen::free_body_principal;
namespace TQ = mbsc_gen::torque_space;
namespace TE = mbsc_gen::torque_euler_space;
namespace TB = mbsc_gen::torque_body;
namespace QM = mbsc_gen::free_body_quaternion_min;
namespace EM = mbsc_gen::free_body_euler_min;

TEST_CASE("rigid3d: the parameters the tests read", "[numeric][rigid3d]") {
  const char* const want[] = {"m", "g", "Ixx", "Iyy", "Izz", "Ixy", "Ixz", "Iyz"};
  for (int k = 0; k < 8; ++k) {
    REQUIRE(std::string(Q::kParamNames[k]) == want[k]);
    REQUIRE(std::string(E::kParamNames[k]) == want[k]);
    REQUIRE(std::string(QS::kParamNames[k]) == want[k]);
    REQUIRE(std::string(ES::kParamNames[k]) == want[k]);
  }
  REQUIRE(Q::kNdof == 6);
  REQUIRE(E::kNdof == 6);
  REQUIRE(QS::kNdof == 6);
  REQUIRE(ES::kNdof == 6);
}

TEST_CASE("rigid3d: quaternion and Euler forms, body and space frames, give one motion", "[numeric][rigid3d]") {
  std::vector<Form> forms{MAKE_FORM(Q, "quaternion/body", "quaternion", false), MAKE_FORM(E, "zyx/body", "zyx", false),
                          MAKE_FORM(QS, "quaternion/space", "quaternion", true), MAKE_FORM(ES, "zxz/space", "zxz", true)};
  std::vector<std::unique_ptr<mbsc::runtime::Dop853>> steppers;
  for (auto& f : forms) {
    f.start(kR0, kWb, kV);
    // The starting attitudes are one attitude.
    const Mat R = f.rotation(f.x);
    for (int k = 0; k < 9; ++k) REQUIRE(R[k] == Approx(kR0[k]).margin(1e-14));
    steppers.push_back(integrator(f, 1e-13));
  }
  double worst = 0.0;
  for (int check = 1; check <= 8; ++check) {  // every 0.25 s, 2 s in all
    const double t = 0.25 * check;
    for (auto& s : steppers) run_to(*s, t);
    const std::vector<double>& ref = steppers[0]->x();
    const Mat R0 = forms[0].rotation(ref);
    const Vec3 w0 = forms[0].omega_space(ref);
    for (std::size_t k = 1; k < forms.size(); ++k) {
      const std::vector<double>& s = steppers[k]->x();
      INFO(forms[k].name << " at t = " << t);
      // Away from gimbal lock: zyx's theta from +-pi/2, zxz's theta from 0 and pi.
      if (forms[k].attitude == "zyx") REQUIRE(std::abs(std::cos(s[4])) > 0.2);
      if (forms[k].attitude == "zxz") REQUIRE(std::abs(std::sin(s[4])) > 0.2);
      const Mat R = forms[k].rotation(s);
      const Vec3 w = forms[k].omega_space(s);
      for (int i = 0; i < 9; ++i) worst = std::max(worst, std::abs(R[i] - R0[i]));
      for (int i = 0; i < 3; ++i) worst = std::max(worst, std::abs(w[i] - w0[i]));
      for (const char* n : {"b.x", "b.y", "b.z", "b.u", "b.v", "b.w"})
        worst = std::max(worst, std::abs(s[static_cast<std::size_t>(index_of(forms[k].names, forms[k].nx, n))] -
                                         ref[static_cast<std::size_t>(index_of(forms[0].names, forms[0].nx, n))]));
    }
  }
  CHECK(worst < 1e-9);
  // The mass centre falls freely: z = w0 t - g t^2 / 2.
  const std::vector<double>& ref = steppers[0]->x();
  CHECK(ref[2] == Approx(kV[2] * 2.0 - 0.5 * Q::kParamDefaults[1] * 4.0).margin(1e-10));
}

TEST_CASE("rigid3d: angular momentum in space and energy are conserved; the quaternion stays unit", "[numeric][rigid3d]") {
  std::vector<Form> forms{MAKE_FORM(Q, "quaternion/body", "quaternion", false), MAKE_FORM(E, "zyx/body", "zyx", false),
                          MAKE_FORM(QS, "quaternion/space", "quaternion", true), MAKE_FORM(ES, "zxz/space", "zxz", true)};
  for (auto& f : forms) {
    INFO(f.name);
    f.start(kR0, kWb, kV);
    double e0[3];
    REQUIRE(f.energy(0.0, f.x.data(), nullptr, f.params, e0) == 0);
    const Vec3 h0 = f.momentum(f.x);
    auto s = integrator(f, 1e-13);
    double drift_e = 0.0, drift_h = 0.0, drift_norm = 0.0;
    for (int check = 1; check <= 8; ++check) {
      run_to(*s, 0.25 * check);
      double e[3];
      REQUIRE(f.energy(0.0, s->x().data(), nullptr, f.params, e) == 0);
      drift_e = std::max(drift_e, std::abs(e[2] - e0[2]) / std::abs(e0[2]));
      const Vec3 h = f.momentum(s->x());
      for (int i = 0; i < 3; ++i) drift_h = std::max(drift_h, std::abs(h[i] - h0[i]));
      if (f.attitude == "quaternion") {
        const double* q = &s->x()[static_cast<std::size_t>(index_of(f.names, f.nx, "b.e0"))];
        drift_norm = std::max(drift_norm, std::abs(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3] - 1.0));
      }
    }
    CHECK(drift_e < 1e-10);
    CHECK(drift_h < 1e-10);
    CHECK(drift_norm < 1e-9);
    // (Kinetic energy changes as the body rises and falls: the test is not vacuous.)
    double e_end[3];
    REQUIRE(f.energy(0.0, s->x().data(), nullptr, f.params, e_end) == 0);
    CHECK(std::abs(e_end[0] - e0[0]) > 1.0);
  }
}

TEST_CASE("rigid3d: spin about a principal axis is uniform rotation (thesis Ex 2.1)", "[numeric][rigid3d]") {
  // free_body_principal: the quaternion model with Ixy = Ixz = Iyz = 0 frozen and no
  // gravity. w = (0, W, 0), e(0) = (1, 0, 0, 0): e = (cos(W t / 2), 0, sin(W t / 2), 0).
  Form f = MAKE_FORM(P, "principal", "quaternion", false);
  const double W = 3.7;
  f.x.assign(P::kNx, 0.0);
  f.at("b.e0") = 1.0;
  f.at("b.wy") = W;
  auto s = integrator(f, 1e-13);
  for (int check = 1; check <= 8; ++check) {
    const double t = 0.25 * check;
    run_to(*s, t);
    const std::vector<double>& x = s->x();
    INFO("t = " << t);
    CHECK(x[static_cast<std::size_t>(index_of(f.names, f.nx, "b.e0"))] == Approx(std::cos(W * t / 2)).margin(1e-11));
    CHECK(x[static_cast<std::size_t>(index_of(f.names, f.nx, "b.e1"))] == Approx(0.0).margin(1e-11));
    CHECK(x[static_cast<std::size_t>(index_of(f.names, f.nx, "b.e2"))] == Approx(std::sin(W * t / 2)).margin(1e-11));
    CHECK(x[static_cast<std::size_t>(index_of(f.names, f.nx, "b.e3"))] == Approx(0.0).margin(1e-11));
    CHECK(x[static_cast<std::size_t>(index_of(f.names, f.nx, "b.wy"))] == Approx(W).margin(1e-11));
    CHECK(x[static_cast<std::size_t>(index_of(f.names, f.nx, "b.wx"))] == Approx(0.0).margin(1e-11));
    CHECK(x[static_cast<std::size_t>(index_of(f.names, f.nx, "b.z"))] == Approx(0.0).margin(1e-11));
  }
}

TEST_CASE("rigid3d: an off-principal spin is not uniform (the tensor's products act)", "[numeric][rigid3d]") {
  // The full tensor of free_body_quaternion: w = (0, W, 0) is not an eigenvector, so
  // the body-frame angular velocity changes at once (w' = -I^-1 (w x I w) != 0).
  Form f = MAKE_FORM(Q, "quaternion/body", "quaternion", false);
  f.x.assign(Q::kNx, 0.0);
  f.at("b.e0") = 1.0;
  f.at("b.wy") = 3.7;
  std::vector<double> xd(Q::kNx);
  REQUIRE(f.rhs(0.0, f.x.data(), nullptr, f.params, xd.data()) == 0);
  const double* p = f.params;
  // Closed form of w' at this state: I w' = -(w x I w), with I w = W (Ixy, Iyy, Iyz).
  const double W = 3.7;
  const Vec3 Iw{W * p[5], W * p[3], W * p[7]};
  const Vec3 rhs{-(W * Iw[2]), 0.0, -(-W * Iw[0])};  // -(w x Iw) with w = (0, W, 0)
  // Check I w' = rhs.
  const int wx = index_of(f.names, f.nx, "b.wx");
  const Vec3 wd{xd[static_cast<std::size_t>(wx)], xd[static_cast<std::size_t>(wx) + 1], xd[static_cast<std::size_t>(wx) + 2]};
  const Mat I{p[2], p[5], p[6], p[5], p[3], p[7], p[6], p[7], p[4]};
  const Vec3 Iwd = mul(I, wd);
  for (int i = 0; i < 3; ++i) CHECK(Iwd[i] == Approx(rhs[i]).margin(1e-12));
  CHECK(std::abs(wd[0]) + std::abs(wd[2]) > 1e-3);
}

TEST_CASE("rigid3d: a constant torque in space adds tau t to the angular momentum", "[numeric][rigid3d]") {
  // torque_space: quaternion, body-frame speeds (torque enters as R^T tau);
  // torque_euler_space: zxz angles, space-frame speeds (torque enters as it is).
  std::vector<Form> forms{MAKE_FORM(TQ, "torque/quaternion/body", "quaternion", false),
                          MAKE_FORM(TE, "torque/zxz/space", "zxz", true)};
  for (auto& f : forms) {
    INFO(f.name);
    // Parameters: m, Ixx, Iyy, Izz, Ixy, Ixz, Iyz, Tx, Ty, Tz.
    REQUIRE(std::string(TQ::kParamNames[7]) == "Tx");
    REQUIRE(std::string(TE::kParamNames[1]) == "Ixx");
    const double* p = f.params;
    const Mat I{p[1], p[4], p[5], p[4], p[2], p[6], p[5], p[6], p[3]};
    const Vec3 tau{p[7], p[8], p[9]};
    const Mat R0 = euler("zyx", 0.3, 1.0, -0.2);
    f.start(R0, kWb, kV);
    auto h_of = [&](const std::vector<double>& s) {
      const Mat R = f.rotation(s);
      return mul(R, mul(I, mul_t(R, f.omega_space(s))));
    };
    const Vec3 h0 = h_of(f.x);
    auto s = integrator(f, 1e-13);
    double worst = 0.0;
    for (int check = 1; check <= 8; ++check) {
      const double t = 0.25 * check;
      run_to(*s, t);
      const Vec3 h = h_of(s->x());
      for (int i = 0; i < 3; ++i) worst = std::max(worst, std::abs(h[i] - (h0[i] + tau[i] * t)));
    }
    CHECK(worst < 1e-10);
  }
}

TEST_CASE("rigid3d: a constant body torque on a spherical body turns it about a fixed axis", "[numeric][rigid3d]") {
  // torque_body: J about every axis, quaternion with space-frame speeds, torque fixed in
  // the body (enters as R tau). From rest at attitude R0: R(t) = R0 Rot(n, |tau| t^2 / (2 J)).
  Form f = MAKE_FORM(TB, "torque/body", "quaternion", true);
  const double* p = f.params;  // m, J, Tx, Ty, Tz
  REQUIRE(std::string(TB::kParamNames[1]) == "J");
  const double J = p[1];
  const Vec3 tau{p[2], p[3], p[4]};
  const double T = std::sqrt(tau[0] * tau[0] + tau[1] * tau[1] + tau[2] * tau[2]);
  const Vec3 n{tau[0] / T, tau[1] / T, tau[2] / T};
  const Mat R0 = euler("zyx", 0.3, 0.4, -0.2);
  f.start(R0, {0, 0, 0}, {0, 0, 0});
  auto s = integrator(f, 1e-13);
  double worst = 0.0;
  for (int check = 1; check <= 8; ++check) {
    const double t = 0.25 * check;
    run_to(*s, t);
    // Rodrigues: Rot(n, a) = I + sin a K + (1 - cos a) K^2, K the skew matrix of n.
    const double a = T * t * t / (2 * J);
    const Mat K{0, -n[2], n[1], n[2], 0, -n[0], -n[1], n[0], 0};
    const Mat K2 = mul(K, K);
    Mat rot{};
    for (int k = 0; k < 9; ++k) rot[k] = (k % 4 == 0 ? 1.0 : 0.0) + std::sin(a) * K[k] + (1 - std::cos(a)) * K2[k];
    const Mat want = mul(R0, rot), got = f.rotation(s->x());
    for (int k = 0; k < 9; ++k) worst = std::max(worst, std::abs(got[k] - want[k]));
  }
  CHECK(worst < 1e-9);
  // It did turn: |tau| t^2 / (2 J) at t = 2 is about 1.5 rad.
  CHECK(T * 4 / (2 * J) > 1.0);
}

TEST_CASE("rigid3d: --state minimal keeps a free body's state and rhs", "[numeric][rigid3d][minimal]") {
  // No constraints: the minimal state is the full one (7 + 6 with a quaternion, 6 + 6
  // with angles), and the rhs agrees entry by entry.
  REQUIRE(QM::kNx == Q::kNx);
  REQUIRE(EM::kNx == E::kNx);
  Form q = MAKE_FORM(Q, "quaternion/body", "quaternion", false), e = MAKE_FORM(E, "zyx/body", "zyx", false);
  q.start(kR0, kWb, kV);
  e.start(kR0, kWb, kV);
  std::vector<double> a(Q::kNx), b(Q::kNx), c(E::kNx), d(E::kNx);
  REQUIRE(Q::rhs(0.0, q.x.data(), nullptr, Q::kParamDefaults, a.data()) == 0);
  REQUIRE(QM::rhs(0.0, q.x.data(), nullptr, QM::kParamDefaults, b.data()) == 0);
  REQUIRE(E::rhs(0.0, e.x.data(), nullptr, E::kParamDefaults, c.data()) == 0);
  REQUIRE(EM::rhs(0.0, e.x.data(), nullptr, EM::kParamDefaults, d.data()) == 0);
  for (int k = 0; k < Q::kNx; ++k) CHECK(b[static_cast<std::size_t>(k)] == Approx(a[static_cast<std::size_t>(k)]).margin(1e-14));
  for (int k = 0; k < E::kNx; ++k) CHECK(d[static_cast<std::size_t>(k)] == Approx(c[static_cast<std::size_t>(k)]).margin(1e-14));
}

TEST_CASE("rigid3d: the generated header lists the unit quaternions an app keeps at |e| = 1", "[numeric][rigid3d]") {
  // kQuaternionIndices: four state indices per quaternion body, e0 first; none for angles.
  REQUIRE(Q::kNquaternions == 1);
  REQUIRE(QM::kNquaternions == 1);
  CHECK(E::kNquaternions == 0);
  for (int k = 0; k < 4; ++k) {
    CHECK(std::string(Q::kStateNames[Q::kQuaternionIndices[k]]) == "b.e" + std::to_string(k));
    CHECK(std::string(QM::kStateNames[QM::kQuaternionIndices[k]]) == "b.e" + std::to_string(k));
  }
  // Handed to the runtime's simulate, they keep the norm at one step's error; without
  // them it drifts with the integrator's error over a long, loose run.
  Form q = MAKE_FORM(Q, "quaternion/body", "quaternion", false);
  q.start(kR0, kWb, kV);
  const auto model = MBSC_MODEL_TABLE(Q);
  mbsc::runtime::StepperOptions so;
  so.rtol = 1e-6;
  so.atol = 1e-8;
  auto norm_error = [&](bool keep, long& normalizations) {
    mbsc::runtime::SimulationOptions opt;
    opt.t_end = 200.0;
    opt.dt_out = 0.0;
    if (keep) opt.unit_quaternions = mbsc::runtime::unit_quaternions_of(Q::kQuaternionIndices, Q::kNquaternions);
    const auto r = mbsc::runtime::simulate(model, "dopri5", so, opt, q.x, {}, Q::kParamDefaults);
    INFO(r.message);
    REQUIRE(r.ok());
    normalizations = r.normalizations;
    const double* e = &r.x[static_cast<std::size_t>(Q::kQuaternionIndices[0])];
    return std::abs(std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3]) - 1.0);
  };
  long kept = 0, drifted = 0;
  const double with = norm_error(true, kept), without = norm_error(false, drifted);
  INFO("|e| - 1 with " << with << " (" << kept << " normalizations), without " << without);
  CHECK(kept > 0);
  CHECK(drifted == 0);
  CHECK(with < 1e-5);
  CHECK(with < 0.2 * without);
}
