// SPDX-License-Identifier: GPL-2.0-or-later
// Spatial revolute joints with coordinates (docs/language.md, "Joint coordinates in
// space") against plain revolute joints between bodies with attitudes of their own: the
// two-link arm of tests/data/spatial_joints/arm_joint.mbs (a vertical shoulder axis on the
// ground, an elbow axis along (1, 1, 0) in link 1, full inertia tensors, a torque, a
// rotational spring and damper) and arm_absolute.mbs (the same arm, zyx angles for both
// links). A joint state (q1, q2, their rates) is mapped to the absolute state by the
// rotations it stands for, R1 = Rz(q1), R2 = R1 Rot(n, q2), and the mass centres and the
// body-frame speeds of the assembled joint state:
//  * the accelerations of every body speed agree at random states, as do the energies;
//  * 2 s runs from the same state with the same torque agree along the way;
//  * the joint model's velocity rows: link 2's body-frame angular speed is R2ᵀ R2' with
//    R2' the rate of the rotation computed from q and q'.
#include <catch2/catch.hpp>
#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "arm_absolute/arm_absolute.hpp"
#include "arm_joint/arm_joint.hpp"
#include "mbsc/runtime/assemble.hpp"
#include "mbsc/runtime/dop853.hpp"
#include "spatial_support.hpp"
#include "test_support.hpp"

namespace A = mbsc_gen::arm_absolute;
namespace J = mbsc_gen::arm_joint;
using mbsc_test::index_of;

namespace {

using State = std::vector<double>;
using Mat = mbsc_test::Mat3;
using mbsc_test::product;
using mbsc_test::total_energy;

std::size_t at_j(const std::string& n) { return static_cast<std::size_t>(index_of(J::kStateNames, J::kNx, n)); }
std::size_t at_a(const std::string& n) { return static_cast<std::size_t>(index_of(A::kStateNames, A::kNx, n)); }

/// Rotation by angle q about the unit axis n (Rodrigues).
Mat rotation(const std::array<double, 3>& n, double q) {
  const double c = std::cos(q), s = std::sin(q), v = 1 - c;
  return {{{c + n[0] * n[0] * v, n[0] * n[1] * v - n[2] * s, n[0] * n[2] * v + n[1] * s},
           {n[1] * n[0] * v + n[2] * s, c + n[1] * n[1] * v, n[1] * n[2] * v - n[0] * s},
           {n[2] * n[0] * v - n[1] * s, n[2] * n[1] * v + n[0] * s, c + n[2] * n[2] * v}}};
}

/// The joint state at (q1, q2, q1', q2'): the rest assembled from the rows.
State joint_state(double q1, double q2, double w1, double w2) {
  State x(static_cast<std::size_t>(J::kNx), 0.0);
  x[at_j("q1")] = q1;
  x[at_j("q2")] = q2;
  x[at_j("q1_dot")] = w1;
  x[at_j("q2_dot")] = w2;
  std::vector<bool> given_q(static_cast<std::size_t>(J::kNq), false), given_u(static_cast<std::size_t>(J::kNu), false);
  given_q[at_j("q1")] = given_q[at_j("q2")] = true;
  given_u[at_j("q1_dot") - J::kNq] = given_u[at_j("q2_dot") - J::kNq] = true;
  mbsc::runtime::AssemblyOptions opt;
  opt.tolerance = 1e-14;
  const auto r = mbsc::runtime::assemble(MBSC_TEST_ASSEMBLY_MODEL(J), 0.0, x, given_q, given_u, nullptr, J::kParamDefaults, opt);
  INFO(r.message);
  REQUIRE(r.ok());
  return x;
}

const std::array<double, 3> kElbow{1 / std::sqrt(2.0), 1 / std::sqrt(2.0), 0.0};

/// The same configuration and motion in the absolute model: zyx angles of R1 and R2,
/// mass centres and body-frame speeds as they are.
State absolute_state(const State& xj) {
  State x(static_cast<std::size_t>(A::kNx), 0.0);
  const Mat R1 = rotation({0, 0, 1}, xj[at_j("q1")]);
  const Mat R2 = product(R1, rotation(kElbow, xj[at_j("q2")]));
  const std::array<std::pair<const char*, Mat>, 2> links{{{"link1", R1}, {"link2", R2}}};
  for (const auto& [b, R] : links) {
    const std::string s = b;
    x[at_a(s + ".phi")] = std::atan2(R[1][0], R[0][0]);  // R = Rz(phi) Ry(theta) Rx(psi)
    x[at_a(s + ".theta")] = -std::asin(R[2][0]);
    x[at_a(s + ".psi")] = std::atan2(R[2][1], R[2][2]);
    for (const char* c : {".x", ".y", ".z", ".u", ".v", ".w", ".wx", ".wy", ".wz"}) x[at_a(s + c)] = xj[at_j(s + c)];
  }
  return x;
}

const char* const kSpeeds[] = {"link1.u", "link1.v", "link1.w", "link1.wx", "link1.wy", "link1.wz",
                               "link2.u", "link2.v", "link2.w", "link2.wx", "link2.wy", "link2.wz"};

}  // namespace

TEST_CASE("spatial joint coordinates: the arm's accelerations equal those in absolute coordinates", "[numeric][spatial]") {
  CHECK(J::kNdof == 2);
  CHECK(A::kNdof == 2);
  CHECK(J::kNq == 8);  // two mass centres and two joint angles, no attitude coordinates
  std::mt19937 rng(4242);
  std::uniform_real_distribution<double> angle(-3.0, 3.0), rate(-2.0, 2.0);
  const double T[1] = {0.7};
  for (int trial = 0; trial < 20; ++trial) {
    const State xj = joint_state(angle(rng), angle(rng), rate(rng), rate(rng));
    const State xa = absolute_state(xj);
    // The mapped state satisfies the absolute model's rows.
    std::vector<double> g(static_cast<std::size_t>(A::kNposc)), c(static_cast<std::size_t>(A::kNc));
    REQUIRE(A::position_constraints(0.0, xa.data(), T, A::kParamDefaults, g.data()) == 0);
    REQUIRE(A::velocity_constraints(0.0, xa.data(), T, A::kParamDefaults, c.data()) == 0);
    for (double r : g) CHECK(std::fabs(r) < 1e-12);
    for (double r : c) CHECK(std::fabs(r) < 1e-12);
    CHECK(total_energy(J::energy, xj, J::kParamDefaults) ==
          Approx(total_energy(A::energy, xa, A::kParamDefaults)).epsilon(1e-12));
    State dj(xj.size()), da(xa.size());
    REQUIRE(J::rhs(0.0, xj.data(), T, J::kParamDefaults, dj.data()) == 0);
    REQUIRE(A::rhs(0.0, xa.data(), T, A::kParamDefaults, da.data()) == 0);
    for (const char* s : kSpeeds) {
      INFO(s << " at trial " << trial);
      CHECK(dj[at_j(s)] == Approx(da[at_a(s)]).margin(1e-9));
    }
  }
}

TEST_CASE("spatial joint coordinates: the arm's motion equals that in absolute coordinates", "[numeric][spatial]") {
  const State xj0 = joint_state(0.4, -1.1, 1.5, -0.8);
  const State xa0 = absolute_state(xj0);
  const double T[1] = {0.4};
  mbsc::runtime::StepperOptions o;
  o.rtol = o.atol = 1e-12;
  mbsc::runtime::Dop853 sj([&](double t, const double* s, double* sd) { return J::rhs(t, s, T, J::kParamDefaults, sd); },
                           J::kNx, o);
  mbsc::runtime::Dop853 sa([&](double t, const double* s, double* sd) { return A::rhs(t, s, T, A::kParamDefaults, sd); },
                           A::kNx, o);
  REQUIRE(sj.reset(0.0, xj0) == mbsc::runtime::Stepper::Status::Ok);
  REQUIRE(sa.reset(0.0, xa0) == mbsc::runtime::Stepper::Status::Ok);
  State xj(xj0.size()), xa(xa0.size());
  double worst = 0.0, travel = 0.0;
  for (int k = 1; k <= 20; ++k) {
    const double t = 0.1 * k;
    while (sj.t() < t) REQUIRE(sj.step(t) == mbsc::runtime::Stepper::Status::Ok);
    while (sa.t() < t) REQUIRE(sa.step(t) == mbsc::runtime::Stepper::Status::Ok);
    sj.interpolate(t, xj);
    sa.interpolate(t, xa);
    for (const char* c : {"link2.x", "link2.y", "link2.z", "link1.x", "link1.y"}) {
      worst = std::max(worst, std::fabs(xj[at_j(c)] - xa[at_a(c)]));
      travel = std::max(travel, std::fabs(xj[at_j(c)] - xj0[at_j(c)]));
    }
    for (const char* s : kSpeeds) worst = std::max(worst, std::fabs(xj[at_j(s)] - xa[at_a(s)]));
  }
  INFO("largest difference " << worst << ", largest displacement " << travel << " m");
  CHECK(travel > 0.3);
  CHECK(worst < 1e-8);
}

TEST_CASE("spatial joint coordinates: the angular speeds are those of the rotations", "[numeric][spatial]") {
  // Along the joint model's own run, the body-frame angular speed of link 2 from the
  // rotation matrices: [w]x = R2ᵀ R2', R2' by central differences of R2(q(t)).
  const State x0 = joint_state(0.2, 0.9, -1.2, 2.0);
  const double h = 1e-6;
  auto R2_of = [](const State& x) {
    return product(rotation({0, 0, 1}, x[at_j("q1")]), rotation(kElbow, x[at_j("q2")]));
  };
  State xd(x0.size());
  const double T[1] = {0.0};
  REQUIRE(J::rhs(0.0, x0.data(), T, J::kParamDefaults, xd.data()) == 0);
  State xp = x0, xm = x0;
  for (const char* q : {"q1", "q2"}) {
    xp[at_j(q)] += h * xd[at_j(q)];
    xm[at_j(q)] -= h * xd[at_j(q)];
  }
  const Mat R = R2_of(x0), Rp = R2_of(xp), Rm = R2_of(xm);
  Mat W{};  // R^T R'
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) W[i][j] += R[k][i] * (Rp[k][j] - Rm[k][j]) / (2 * h);
  CHECK(W[2][1] == Approx(x0[at_j("link2.wx")]).margin(1e-7));
  CHECK(W[0][2] == Approx(x0[at_j("link2.wy")]).margin(1e-7));
  CHECK(W[1][0] == Approx(x0[at_j("link2.wz")]).margin(1e-7));
}
