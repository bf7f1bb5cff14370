// SPDX-License-Identifier: GPL-2.0-or-later
// Universal, cylindrical, spherical and prismatic joints with coordinates (docs/language.md,
// "Joint coordinates in space") against the same joints without coordinates between bodies
// with quaternion attitudes of their own: the chain of
// tests/data/spatial_joints/mixed_joint.mbs and mixed_absolute.mbs (a universal joint to the
// ground, a cylindrical joint with a torque and a spring, a spherical joint in zyx angles,
// a prismatic joint with a force and a spring; full inertia tensors). A joint state is
// mapped to the absolute state by the rotations it stands for,
//   R1 = Rx(q1) Ry(q2),  R2 = R1 Rz(r),  R3 = R2 Rz(a) Ry(b) Rx(c),  R4 = R3,
// written here independently of the compiler, and the assembled mass centres and
// body-frame speeds of the joint state:
//  * the mapped state satisfies every row of the absolute model (the points coincide, the
//    slides run along the axes, the universal's axes stay perpendicular), and the
//    energies agree;
//  * the accelerations of every body speed agree at random states (the absolute model in
//    the multipliers form, an independent formulation of the same mechanics);
//  * each link's body-frame angular speed is Rᵀ R' with R' by central differences of R(q).
#include <catch2/catch.hpp>
#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "mbsc/runtime/assemble.hpp"
#include "mixed_absolute/mixed_absolute.hpp"
#include "mixed_absolute_support.hpp"
#include "mixed_joint/mixed_joint.hpp"
#include "spatial_support.hpp"
#include "test_support.hpp"

namespace A = mbsc_gen::mixed_absolute;
namespace J = mbsc_gen::mixed_joint;
using mbsc_test::index_of;

namespace {

using State = std::vector<double>;
using Mat = mbsc_test::Mat3;
using mbsc_test::product;
using mbsc_test::quaternion;
using mbsc_test::turn;
using mbsc_test::total_energy;

std::size_t at_j(const std::string& n) { return static_cast<std::size_t>(index_of(J::kStateNames, J::kNx, n)); }
std::size_t at_a(const std::string& n) { return static_cast<std::size_t>(index_of(A::kStateNames, A::kNx, n)); }

/// The four links' rotations at the joint coordinates of state x.
std::array<Mat, 4> rotations(const State& x) {
  const Mat R1 = product(turn(0, x[at_j("q1")]), turn(1, x[at_j("q2")]));
  const Mat R2 = product(R1, turn(2, x[at_j("r")]));
  const Mat R3 = product(R2, product(turn(2, x[at_j("a")]), product(turn(1, x[at_j("b")]), turn(0, x[at_j("c")]))));
  return {R1, R2, R3, R3};
}

const char* const kJointCoordinates[] = {"q1", "q2", "s", "r", "a", "b", "c", "p"};
const char* const kLinks[] = {"link1", "link2", "link3", "link4"};

/// The joint state at the given joint coordinates and rates: the rest assembled from the rows.
State joint_state(const std::array<double, 8>& q, const std::array<double, 8>& v) {
  State x(static_cast<std::size_t>(J::kNx), 0.0);
  std::vector<bool> given_q(static_cast<std::size_t>(J::kNq), false), given_u(static_cast<std::size_t>(J::kNu), false);
  for (std::size_t k = 0; k < 8; ++k) {
    const std::string name = kJointCoordinates[k];
    x[at_j(name)] = q[k];
    x[at_j(name + "_dot")] = v[k];
    given_q[at_j(name)] = true;
    given_u[at_j(name + "_dot") - static_cast<std::size_t>(J::kNq)] = true;
  }
  mbsc::runtime::AssemblyOptions opt;
  opt.tolerance = 1e-14;
  const auto r = mbsc::runtime::assemble(MBSC_TEST_ASSEMBLY_MODEL(J), 0.0, x, given_q, given_u, nullptr, J::kParamDefaults, opt);
  INFO(r.message);
  REQUIRE(r.ok());
  return x;
}

/// The same configuration and motion in the absolute model.
State absolute_state(const State& xj) {
  State x(static_cast<std::size_t>(A::kNx), 0.0);
  const auto R = rotations(xj);
  for (std::size_t b = 0; b < 4; ++b) {
    const std::string s = kLinks[b];
    const auto e = quaternion(R[b]);
    for (std::size_t k = 0; k < 4; ++k) x[at_a(s + ".e" + std::to_string(k))] = e[k];
    for (const char* c : {".x", ".y", ".z", ".u", ".v", ".w", ".wx", ".wy", ".wz"}) x[at_a(s + c)] = xj[at_j(s + c)];
  }
  return x;
}

}  // namespace

TEST_CASE("spatial joint kinds: the mixed chain's accelerations equal those in absolute coordinates", "[numeric][spatial]") {
  CHECK(J::kNdof == 8);
  CHECK(A::kNdof == 8);
  CHECK(J::kNq == 20);  // four mass centres and eight joint coordinates, no attitude coordinates
  std::mt19937 rng(20261205);
  std::uniform_real_distribution<double> angle(-3.0, 3.0), middle(-1.2, 1.2), slide(-0.3, 0.3), rate(-2.0, 2.0);
  const double inputs[2] = {0.7, -0.4};
  double worst = 0.0;
  for (int trial = 0; trial < 20; ++trial) {
    // The zyx middle angle b stays away from ±pi/2, where the angles lose a rate.
    const std::array<double, 8> q{angle(rng), angle(rng), slide(rng), angle(rng), angle(rng), middle(rng), angle(rng), slide(rng)};
    std::array<double, 8> v{};
    for (double& r : v) r = rate(rng);
    const State xj = joint_state(q, v);
    const State xa = absolute_state(xj);
    mbsc_test::check_on_mixed_absolute_rows(xa, inputs, trial);
    CHECK(total_energy(J::energy, xj, J::kParamDefaults) ==
          Approx(total_energy(A::energy, xa, A::kParamDefaults)).epsilon(1e-12));
    State dj(xj.size()), da(xa.size());
    REQUIRE(J::rhs(0.0, xj.data(), inputs, J::kParamDefaults, dj.data()) == 0);
    REQUIRE(A::rhs(0.0, xa.data(), inputs, A::kParamDefaults, da.data()) == 0);
    for (const char* b : kLinks)
      for (const char* s : {".u", ".v", ".w", ".wx", ".wy", ".wz"}) {
        const std::string name = std::string(b) + s;
        INFO(name << " at trial " << trial);
        CHECK(dj[at_j(name)] == Approx(da[at_a(name)]).margin(1e-9));
        worst = std::max(worst, std::fabs(dj[at_j(name)] - da[at_a(name)]));
      }
  }
  INFO("largest difference of an acceleration " << worst);
  CHECK(worst < 1e-9);
}

TEST_CASE("spatial joint kinds: each link's angular speeds are those of its rotation", "[numeric][spatial]") {
  // [w]x = Rᵀ R' with R' by central differences of R(q(t)) along the joint rates.
  const State x0 = joint_state({0.3, -0.7, 0.1, 1.1, -0.4, 0.6, 2.0, -0.2}, {1.2, -0.8, 0.5, 2.0, -1.5, 0.9, 1.7, 0.3});
  const double h = 1e-6;
  State xp = x0, xm = x0;
  for (const char* q : kJointCoordinates) {
    xp[at_j(q)] += h * x0[at_j(std::string(q) + "_dot")];
    xm[at_j(q)] -= h * x0[at_j(std::string(q) + "_dot")];
  }
  const auto R = rotations(x0), Rp = rotations(xp), Rm = rotations(xm);
  for (std::size_t b = 0; b < 4; ++b) {
    Mat W{};  // R^T R'
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) W[i][j] += R[b][k][i] * (Rp[b][k][j] - Rm[b][k][j]) / (2 * h);
    const std::string s = kLinks[b];
    INFO(s);
    CHECK(W[2][1] == Approx(x0[at_j(s + ".wx")]).margin(1e-7));
    CHECK(W[0][2] == Approx(x0[at_j(s + ".wy")]).margin(1e-7));
    CHECK(W[1][0] == Approx(x0[at_j(s + ".wz")]).margin(1e-7));
  }
}
