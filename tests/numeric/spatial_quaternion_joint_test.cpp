// SPDX-License-Identifier: GPL-2.0-or-later
// A spherical joint written with a quaternion (docs/language.md, "Joint coordinates in
// space"): the chain of tests/data/spatial_joints/mixed_quaternion.mbs, whose link 3
// hangs from link 2 by the joint quaternion e and the relative angular speeds ball_wx,
// ball_wy, ball_wz, against the same chain in absolute coordinates (mixed_absolute.mbs:
// quaternion attitudes of every link and joints without coordinates). A joint state is
// mapped to the absolute state by the rotations it stands for,
//   R1 = Rx(q1) Ry(q2),  R2 = R1 Rz(r),  R3 = R2 R(e),  R4 = R3,
// written here independently of the compiler:
//  * the mapped state satisfies every row of the absolute model and the energies agree;
//  * the accelerations of every body speed agree at random states (the absolute model in
//    the multipliers form, an independent formulation), and the minimal state's
//    accelerations are the full state's;
//  * link 3's body-frame angular speed is R3ᵀ R3' with R3' by central differences along
//    the rates the generated kinematic equations give e, which keep |e| = 1;
//  * the generated header lists the joint's quaternion for the runtime's normalization;
//  * a chain of 16 links on quaternion joints (quat_chain16.mbs, 48 degrees of freedom,
//    the tree recursion) keeps its energy along an RK4 run, to the integrator's error.
#include <catch2/catch.hpp>
#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "mbsc/runtime/assemble.hpp"
#include "mixed_absolute/mixed_absolute.hpp"
#include "mixed_absolute_support.hpp"
#include "mixed_quaternion/mixed_quaternion.hpp"
#include "mixed_quaternion_min/mixed_quaternion_min.hpp"
#include "quat_chain16/quat_chain16.hpp"
#include "spatial_support.hpp"
#include "test_support.hpp"

namespace A = mbsc_gen::mixed_absolute;
namespace Q = mbsc_gen::mixed_quaternion;
namespace M = mbsc_gen::mixed_quaternion_min;
namespace C = mbsc_gen::quat_chain16;
using mbsc_test::index_of;

namespace {

using State = std::vector<double>;
using Mat = mbsc_test::Mat3;
using Quaternion = std::array<double, 4>;
using mbsc_test::product;
using mbsc_test::quaternion;
using mbsc_test::rotation_of;
using mbsc_test::total_energy;
using mbsc_test::turn;

std::size_t at_q(const std::string& n) { return static_cast<std::size_t>(index_of(Q::kStateNames, Q::kNx, n)); }
std::size_t at_m(const std::string& n) { return static_cast<std::size_t>(index_of(M::kStateNames, M::kNx, n)); }
std::size_t at_a(const std::string& n) { return static_cast<std::size_t>(index_of(A::kStateNames, A::kNx, n)); }

const char* const kAngles[] = {"q1", "q2", "s", "r", "p"};  // the other joints' coordinates
const char* const kBallSpeeds[] = {"ball_wx", "ball_wy", "ball_wz"};
const char* const kLinks[] = {"link1", "link2", "link3", "link4"};

Quaternion ball_quaternion(const State& x) {
  return {x[at_q("e0")], x[at_q("e1")], x[at_q("e2")], x[at_q("e3")]};
}

/// The four links' rotations at the joint coordinates of state x.
std::array<Mat, 4> rotations(const State& x) {
  const Mat R1 = product(turn(0, x[at_q("q1")]), turn(1, x[at_q("q2")]));
  const Mat R2 = product(R1, turn(2, x[at_q("r")]));
  const Mat R3 = product(R2, rotation_of(ball_quaternion(x)));
  return {R1, R2, R3, R3};
}

/// The joint state at the given joint coordinates, unit quaternion and speeds: the rest
/// assembled from the rows.
State joint_state(const std::array<double, 5>& q, const Quaternion& e, const std::array<double, 5>& v,
                  const std::array<double, 3>& w) {
  State x(static_cast<std::size_t>(Q::kNx), 0.0);
  std::vector<bool> given_q(static_cast<std::size_t>(Q::kNq), false), given_u(static_cast<std::size_t>(Q::kNu), false);
  auto give = [&](const std::string& name, double value) {
    const std::size_t i = at_q(name);
    x[i] = value;
    if (i < static_cast<std::size_t>(Q::kNq)) given_q[i] = true;
    else given_u[i - static_cast<std::size_t>(Q::kNq)] = true;
  };
  for (std::size_t k = 0; k < 5; ++k) {
    give(kAngles[k], q[k]);
    give(std::string(kAngles[k]) + "_dot", v[k]);
  }
  for (std::size_t k = 0; k < 4; ++k) give("e" + std::to_string(k), e[k]);
  for (std::size_t k = 0; k < 3; ++k) give(kBallSpeeds[k], w[k]);
  mbsc::runtime::AssemblyOptions opt;
  opt.tolerance = 1e-14;
  const auto r = mbsc::runtime::assemble(MBSC_TEST_ASSEMBLY_MODEL(Q), 0.0, x, given_q, given_u, nullptr, Q::kParamDefaults, opt);
  INFO(r.message);
  REQUIRE(r.ok());
  return x;
}

/// The same configuration and motion in the absolute model.
State absolute_state(const State& xq) {
  State x(static_cast<std::size_t>(A::kNx), 0.0);
  const auto R = rotations(xq);
  for (std::size_t b = 0; b < 4; ++b) {
    const std::string s = kLinks[b];
    const auto e = quaternion(R[b]);
    for (std::size_t k = 0; k < 4; ++k) x[at_a(s + ".e" + std::to_string(k))] = e[k];
    for (const char* c : {".x", ".y", ".z", ".u", ".v", ".w", ".wx", ".wy", ".wz"}) x[at_a(s + c)] = xq[at_q(s + c)];
  }
  return x;
}

/// A random unit quaternion (a normalized draw of four entries).
Quaternion random_unit(std::mt19937& rng) {
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  Quaternion e{};
  double n = 0;
  while (n < 0.1) {
    for (double& c : e) c = entry(rng);
    n = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3]);
  }
  for (double& c : e) c /= n;
  return e;
}

}  // namespace

TEST_CASE("a spherical joint's quaternion: the mixed chain's accelerations equal those in absolute coordinates",
          "[numeric][spatial]") {
  CHECK(Q::kNdof == 8);
  CHECK(Q::kNq == 21);  // four mass centres, five joint coordinates and the joint's quaternion
  CHECK(M::kNx == 9 + 8);  // the minimal state: the joints' coordinates and speeds
  std::mt19937 rng(20261205);
  std::uniform_real_distribution<double> angle(-3.0, 3.0), slide(-0.3, 0.3), rate(-2.0, 2.0);
  const double inputs[2] = {0.7, -0.4};
  double worst = 0.0, worst_minimal = 0.0;
  // Any attitude of link 3, the upside-down ones (e0 near 0) included: no angle is singular.
  for (int trial = 0; trial < 20; ++trial) {
    const std::array<double, 5> q{angle(rng), angle(rng), slide(rng), angle(rng), slide(rng)};
    const Quaternion e = trial == 0 ? Quaternion{0.0, 0.6, 0.0, 0.8} : random_unit(rng);
    std::array<double, 5> v{};
    for (double& r : v) r = rate(rng);
    const std::array<double, 3> w{rate(rng), rate(rng), rate(rng)};
    const State xq = joint_state(q, e, v, w);
    const State xa = absolute_state(xq);
    mbsc_test::check_on_mixed_absolute_rows(xa, inputs, trial);
    CHECK(total_energy(Q::energy, xq, Q::kParamDefaults) ==
          Approx(total_energy(A::energy, xa, A::kParamDefaults)).epsilon(1e-12));
    State dq(xq.size()), da(xa.size());
    REQUIRE(Q::rhs(0.0, xq.data(), inputs, Q::kParamDefaults, dq.data()) == 0);
    REQUIRE(A::rhs(0.0, xa.data(), inputs, A::kParamDefaults, da.data()) == 0);
    for (const char* b : kLinks)
      for (const char* s : {".u", ".v", ".w", ".wx", ".wy", ".wz"}) {
        const std::string name = std::string(b) + s;
        INFO(name << " at trial " << trial);
        CHECK(dq[at_q(name)] == Approx(da[at_a(name)]).margin(1e-9));
        worst = std::max(worst, std::fabs(dq[at_q(name)] - da[at_a(name)]));
      }
    // The minimal state: the joint coordinates and speeds alone.
    State xm(static_cast<std::size_t>(M::kNx)), dm(xm.size());
    for (int i = 0; i < M::kNx; ++i) xm[static_cast<std::size_t>(i)] = xq[at_q(M::kStateNames[i])];
    REQUIRE(M::rhs(0.0, xm.data(), inputs, M::kParamDefaults, dm.data()) == 0);
    for (int i = 0; i < M::kNx; ++i) {
      INFO(M::kStateNames[i] << " at trial " << trial);
      CHECK(dm[static_cast<std::size_t>(i)] == Approx(dq[at_q(M::kStateNames[i])]).margin(1e-9));
      worst_minimal = std::max(worst_minimal, std::fabs(dm[static_cast<std::size_t>(i)] - dq[at_q(M::kStateNames[i])]));
    }
  }
  INFO("largest difference of an acceleration: absolute " << worst << ", minimal state " << worst_minimal);
  CHECK(worst < 1e-9);
  CHECK(worst_minimal < 1e-9);
}

TEST_CASE("a spherical joint's quaternion: its rates turn link 3 at link 3's angular speeds", "[numeric][spatial]") {
  // [w]x = R3ᵀ R3', R3' by central differences along the rates the rhs gives every joint
  // coordinate (e' from the joint's kinematic equations), and e.e' = 0.
  std::mt19937 rng(7);
  const State x0 = joint_state({0.3, -0.7, 0.1, 1.1, -0.2}, random_unit(rng), {1.2, -0.8, 0.5, 2.0, 0.3}, {-1.5, 0.9, 1.7});
  const double inputs[2] = {0.0, 0.0};
  State d0(x0.size());
  REQUIRE(Q::rhs(0.0, x0.data(), inputs, Q::kParamDefaults, d0.data()) == 0);
  double norm_rate = 0;
  for (int k = 0; k < 4; ++k) norm_rate += x0[at_q("e" + std::to_string(k))] * d0[at_q("e" + std::to_string(k))];
  CHECK(std::fabs(norm_rate) < 1e-15);
  const double h = 1e-6;
  State xp = x0, xm = x0;
  for (const char* q : {"q1", "q2", "r", "e0", "e1", "e2", "e3"}) {
    xp[at_q(q)] += h * d0[at_q(q)];
    xm[at_q(q)] -= h * d0[at_q(q)];
  }
  const auto R = rotations(x0), Rp = rotations(xp), Rm = rotations(xm);
  Mat W{};  // R3ᵀ R3'
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) W[i][j] += R[2][k][i] * (Rp[2][k][j] - Rm[2][k][j]) / (2 * h);
  CHECK(W[2][1] == Approx(x0[at_q("link3.wx")]).margin(1e-7));
  CHECK(W[0][2] == Approx(x0[at_q("link3.wy")]).margin(1e-7));
  CHECK(W[1][0] == Approx(x0[at_q("link3.wz")]).margin(1e-7));
}

TEST_CASE("a spherical joint's quaternion is listed for the runtime's normalization", "[numeric][spatial]") {
  REQUIRE(Q::kNquaternions == 1);
  REQUIRE(M::kNquaternions == 1);
  for (int k = 0; k < 4; ++k) {
    const std::string e = "e" + std::to_string(k);
    CHECK(Q::kQuaternionIndices[k] == static_cast<int>(at_q(e)));
    CHECK(M::kQuaternionIndices[k] == static_cast<int>(at_m(e)));
  }
}

TEST_CASE("a chain of 16 quaternion joints keeps its energy", "[numeric][spatial]") {
  // Every link's attitude is a product of up to 16 joint quaternions: the derivation must
  // see the chain's 48 degrees of freedom (a probe off |e| = 1 once saw a false
  // redundancy here), and the rhs must be the mechanics: with gravity alone the energy is
  // constant, so an RK4 run's drift is the integrator's, and it falls 16-fold when the
  // step halves (a wrong acceleration would leave a drift that does not shrink).
  REQUIRE(C::kNdof == 48);
  REQUIRE(C::kNquaternions == 16);
  std::mt19937 rng(16);
  std::uniform_real_distribution<double> rate(-1.0, 1.0);
  State x0(static_cast<std::size_t>(C::kNx), 0.0);
  for (int q = 0; q < C::kNquaternions; ++q) {
    const Quaternion e = random_unit(rng);
    for (int k = 0; k < 4; ++k) x0[static_cast<std::size_t>(C::kQuaternionIndices[4 * q + k])] = e[k];
  }
  for (int i = C::kNq; i < C::kNx; ++i) x0[static_cast<std::size_t>(i)] = rate(rng);
  auto energy = [](const State& x) { return total_energy(C::energy, x, C::kParamDefaults); };
  auto drift = [&](int steps) {
    const double h = 0.5 / steps;
    State x = x0, k1(x.size()), k2(x.size()), k3(x.size()), k4(x.size()), y(x.size());
    auto f = [](const State& at, State& out) { REQUIRE(C::rhs(0.0, at.data(), nullptr, C::kParamDefaults, out.data()) == 0); };
    double worst = 0.0;
    const double e0 = energy(x0);
    for (int s = 0; s < steps; ++s) {
      f(x, k1);
      for (std::size_t i = 0; i < x.size(); ++i) y[i] = x[i] + 0.5 * h * k1[i];
      f(y, k2);
      for (std::size_t i = 0; i < x.size(); ++i) y[i] = x[i] + 0.5 * h * k2[i];
      f(y, k3);
      for (std::size_t i = 0; i < x.size(); ++i) y[i] = x[i] + h * k3[i];
      f(y, k4);
      for (std::size_t i = 0; i < x.size(); ++i) x[i] += h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
      worst = std::max(worst, std::fabs(energy(x) - e0));
    }
    return worst / std::max(1.0, std::fabs(e0));
  };
  const double coarse = drift(500), fine = drift(1000);
  INFO("relative energy drift over 0.5 s: h = 1 ms " << coarse << ", h = 0.5 ms " << fine);
  CHECK(fine < 1e-8);
  CHECK(fine < coarse / 8);
}
