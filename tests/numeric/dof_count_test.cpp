// SPDX-License-Identifier: GPL-2.0-or-later
// Degrees of freedom of every shipped closed planar mechanism (and the library four-bar
// of tests/data/planar): the Gruebler count, worked by hand below from the mechanism's
// links and pairs, equals
//  - the generated kNdof, and
//  - at random consistent states (runtime assembly), the number of coordinates minus
//    the numeric rank of position_jacobian (the mechanism's mobility), and the number of
//    speeds minus the numeric rank of constraint_jacobian (kNdof again),
// with the ranks from an SVD with a clear gap between kept and dropped singular values.
#include <catch2/catch.hpp>
#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "five_bar/five_bar.hpp"
#include "four_bar_toggle/four_bar_toggle.hpp"
#include "four_bar/four_bar.hpp"
#include "four_bar_joints/four_bar_joints.hpp"
#include "mbsc/runtime/assemble.hpp"
#include "ring_disc/ring_disc.hpp"
#include "ring_disc_joints/ring_disc_joints.hpp"
#include "slider_crank/slider_crank.hpp"
#include "test_support.hpp"
#include "three_rrr/three_rrr.hpp"
#include "whitworth/whitworth.hpp"

using mbsc::runtime::AssemblyModel;
using mbsc_test::index_of;

namespace {

/// Numeric rank of a row-major rows x cols matrix; the singular values must show a gap.
int numeric_rank(const std::vector<double>& a, int rows, int cols) {
  if (rows == 0) return 0;
  const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> A(a.data(), rows, cols);
  const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(A).singularValues();
  int rank = 0;
  while (rank < s.size() && s(rank) > 1e-9 * s(0)) ++rank;
  INFO("singular values " << s.transpose());
  if (rank > 0) CHECK(s(rank - 1) > 1e-6 * s(0));  // not near a singular configuration
  if (rank < s.size()) CHECK(s(rank) < 1e-12 * s(0));
  return rank;
}

/// Assembles x (given entries marked) and checks the two numeric counts.
void check_counts(const AssemblyModel& m, std::vector<double>& x, const std::vector<bool>& gq, const std::vector<bool>& gu,
                  const double* u, const double* p, int mobility, int ndof) {
  const auto r = mbsc::runtime::assemble(m, 0.0, x, gq, gu, u, p);
  INFO(r.message);
  REQUIRE(r.ok());
  if (m.nposc > 0) {
    std::vector<double> J(static_cast<std::size_t>(m.nposc * m.nq));
    REQUIRE(m.position_jacobian(0.0, x.data(), u, p, J.data()) == 0);
    CHECK(m.nq - numeric_rank(J, m.nposc, m.nq) == mobility);
  }
  std::vector<double> A(static_cast<std::size_t>(m.nc * m.nu));
  REQUIRE(m.constraint_jacobian(0.0, x.data(), u, p, A.data()) == 0);
  CHECK(m.nu - numeric_rank(A, m.nc, m.nu) == ndof);
}

std::mt19937& rng() {
  static std::mt19937 r(61);
  return r;
}
double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng()); }

}  // namespace

TEST_CASE("DOF: four-bar (hand constraints and library joints)", "[numeric][dof]") {
  // Gruebler: 4 links (ground included), 4 revolute pairs: 3 (4 - 1) - 2 * 4 = 1.
  const int gruebler = 3 * (4 - 1) - 2 * 4;
  REQUIRE(gruebler == 1);
  namespace F = mbsc_gen::four_bar;
  namespace L = mbsc_gen::four_bar_joints;
  CHECK(F::kNdof == gruebler);
  CHECK(L::kNdof == gruebler);
  for (int k = 0; k < 5; ++k) {
    const double crank = uniform(0.0, 2 * M_PI);
    {
      auto ix = [](const char* n) { return static_cast<std::size_t>(index_of(F::kStateNames, F::kNx, n)); };
      std::vector<double> x(F::kNx, 0.0);
      x[ix("crank.theta")] = crank, x[ix("coupler.theta")] = 0.4, x[ix("rocker.theta")] = 1.9;
      x[ix("crank.w")] = uniform(-5, 5);
      std::vector<bool> gq(F::kNq, false), gu(F::kNu, false);
      gq[ix("crank.theta")] = true, gu[ix("crank.w") - F::kNq] = true;
      check_counts(MBSC_TEST_ASSEMBLY_MODEL(F), x, gq, gu, nullptr, F::kParamDefaults, gruebler, gruebler);
    }
    {
      auto ix = [](const char* n) { return static_cast<std::size_t>(index_of(L::kStateNames, L::kNx, n)); };
      std::vector<double> x(L::kNx, 0.0);
      x[ix("crank.theta")] = crank, x[ix("coupler.theta")] = 0.4, x[ix("rocker.theta")] = 1.9;
      x[ix("crank.w")] = uniform(-5, 5);
      std::vector<bool> gq(L::kNq, false), gu(L::kNu, false);
      gq[ix("crank.theta")] = true, gu[ix("crank.w") - L::kNq] = true;
      check_counts(MBSC_TEST_ASSEMBLY_MODEL(L), x, gq, gu, nullptr, L::kParamDefaults, gruebler, gruebler);
    }
  }
}

TEST_CASE("DOF: slider-crank", "[numeric][dof]") {
  // Gruebler: ground, crank, rod, slider; pivot, crankpin, wristpin and the guide:
  // 3 (4 - 1) - 2 * 4 = 1 (the model's slider is a particle on the line: 2 coordinates,
  // one guide row, the same count).
  const int gruebler = 3 * (4 - 1) - 2 * 4;
  namespace S = mbsc_gen::slider_crank;
  CHECK(S::kNdof == gruebler);
  auto ix = [](const char* n) { return static_cast<std::size_t>(index_of(S::kStateNames, S::kNx, n)); };
  for (int k = 0; k < 5; ++k) {
    std::vector<double> x(S::kNx, 0.0);
    const double th = uniform(0.0, 2 * M_PI);
    x[ix("crank.theta")] = th, x[ix("rod.theta")] = -0.2 * std::sin(th), x[ix("slider.x")] = 0.4;
    x[ix("crank.w")] = uniform(-5, 5);
    std::vector<bool> gq(S::kNq, false), gu(S::kNu, false);
    gq[ix("crank.theta")] = true, gu[ix("crank.w") - S::kNq] = true;
    const double u[2] = {0.0, 0.0};
    check_counts(MBSC_TEST_ASSEMBLY_MODEL(S), x, gq, gu, u, S::kParamDefaults, gruebler, gruebler);
  }
}

TEST_CASE("DOF: Whitworth quick-return", "[numeric][dof]") {
  // Gruebler: ground, slider, rod, rocker, crank (5 links); lower pairs: the guide and the
  // revolutes slider-rod, rod-rocker, rocker pivot, crank pivot (5); the crank's pin in
  // the rocker's slot is a higher pair (1 condition): 3 (5 - 1) - 2 * 5 - 1 = 1.
  const int gruebler = 3 * (5 - 1) - 2 * 5 - 1;
  namespace W = mbsc_gen::whitworth;
  CHECK(W::kNdof == gruebler);
  auto ix = [](const char* n) { return static_cast<std::size_t>(index_of(W::kStateNames, W::kNx, n)); };
  for (int k = 0; k < 5; ++k) {
    // Around the thesis's configuration (shipped_planar_test.cpp), the crank turned.
    std::vector<double> x(W::kNx, 0.0);
    x[ix("crank.theta")] = M_PI / 4 + uniform(-0.4, 0.4);
    x[ix("crank.w")] = uniform(-3, 3);
    x[ix("slider.x")] = 0.7, x[ix("slider.y")] = 0.8;
    x[ix("rocker.theta")] = 1.3, x[ix("rocker.x")] = 0.1, x[ix("rocker.y")] = 0.3;
    x[ix("rod.theta")] = 3.4, x[ix("rod.x")] = 0.5, x[ix("rod.y")] = 0.7;
    x[ix("crank.y")] = 0.3;
    std::vector<bool> gq(W::kNq, false), gu(W::kNu, false);
    gq[ix("crank.theta")] = true, gu[ix("crank.w") - W::kNq] = true;
    const double u[1] = {0.0};
    check_counts(MBSC_TEST_ASSEMBLY_MODEL(W), x, gq, gu, u, W::kParamDefaults, gruebler, gruebler);
  }
}

TEST_CASE("DOF: 3RRR parallel mechanism", "[numeric][dof]") {
  // Gruebler: ground, platform and two links per leg (8 links), 9 revolutes:
  // 3 (8 - 1) - 2 * 9 = 3.
  const int gruebler = 3 * (8 - 1) - 2 * 9;
  namespace R = mbsc_gen::three_rrr;
  CHECK(R::kNdof == gruebler);
  auto ix = [](const char* n) { return static_cast<std::size_t>(index_of(R::kStateNames, R::kNx, n)); };
  for (int k = 0; k < 5; ++k) {
    // The platform near the origin (given), the legs from the guesses of shipped_planar_test.cpp.
    std::vector<double> x(R::kNx, 0.0);
    std::vector<bool> gq(R::kNq, false), gu(R::kNu, false);
    x[ix("platform.x")] = uniform(-0.2, 0.2), x[ix("platform.y")] = uniform(-0.2, 0.2);
    x[ix("platform.theta")] = uniform(-0.2, 0.2);
    for (const char* n : {"platform.x", "platform.y", "platform.theta"}) gq[ix(n)] = true;
    for (const char* n : {"platform.u", "platform.v", "platform.w"}) {
      x[ix(n)] = uniform(-1, 1);
      gu[ix(n) - R::kNq] = true;
    }
    const double guess_prox[3] = {2.0, 3.8, 6.0}, guess_dist[3] = {1.0, 3.1, 5.2};
    const double bx[3] = {3.0, -1.5, -1.5}, by[3] = {0.0, 1.5 * std::sqrt(3.0), -1.5 * std::sqrt(3.0)};
    const char* legs[3] = {"HA", "HB", "HC"};
    for (int l = 0; l < 3; ++l) {
      const std::string leg = legs[l];
      x[ix((leg + ".proximal.theta").c_str())] = guess_prox[l];
      x[ix((leg + ".proximal.x").c_str())] = bx[l];
      x[ix((leg + ".proximal.y").c_str())] = by[l];
      x[ix((leg + ".distal.theta").c_str())] = guess_dist[l];
    }
    const double u[3] = {0.0, 0.0, 0.0};
    check_counts(MBSC_TEST_ASSEMBLY_MODEL(R), x, gq, gu, u, R::kParamDefaults, gruebler, gruebler);
  }
}

TEST_CASE("DOF: five-bar with geared motors", "[numeric][dof]") {
  // Linkage, Gruebler: ground, two upper and two lower bars (5 links), 5 revolutes (two
  // base pivots, two elbows, the payload joint): 3 (5 - 1) - 2 * 5 = 2. In the model's
  // coordinates: 4 bars (12) + payload particle (2) + theta, phi of each arm and chi (5)
  // = 19, less 17 independent position rows. The motors add (w, i) each, 4 speeds, and
  // the two gears tie each w to its arm: kNdof = 2 + 4 - 2 = 4 (the armature currents).
  const int linkage = 3 * (5 - 1) - 2 * 5;
  const int ndof = linkage + 4 - 2;
  namespace F = mbsc_gen::five_bar;
  CHECK(F::kNdof == ndof);
  auto ix = [](const char* n) { return static_cast<std::size_t>(index_of(F::kStateNames, F::kNx, n)); };
  for (int k = 0; k < 5; ++k) {
    // Base angles near those of assembly_test.cpp, rough guesses for the elbows.
    std::vector<double> x(F::kNx, 0.0);
    x[ix("linkage.left.theta")] = 2.0 + uniform(-0.2, 0.2);
    x[ix("linkage.right.theta")] = 1.1 + uniform(-0.2, 0.2);
    x[ix("linkage.left.phi")] = 1.0, x[ix("linkage.right.phi")] = 2.1;
    x[ix("linkage.left.dtheta")] = uniform(-1, 1), x[ix("linkage.right.dtheta")] = uniform(-1, 1);
    x[ix("motor_left.i")] = uniform(-1, 1), x[ix("motor_right.i")] = uniform(-1, 1);
    std::vector<bool> gq(F::kNq, false), gu(F::kNu, false);
    gq[ix("linkage.left.theta")] = gq[ix("linkage.right.theta")] = true;
    for (const char* n : {"linkage.left.dtheta", "linkage.right.dtheta", "motor_left.i", "motor_right.i"})
      gu[ix(n) - F::kNq] = true;
    const double u[2] = {0.0, 0.0};
    check_counts(MBSC_TEST_ASSEMBLY_MODEL(F), x, gq, gu, u, F::kParamDefaults, linkage, ndof);
  }
}

TEST_CASE("DOF: ring and disc (rolling, velocity constraints)", "[numeric][dof]") {
  // Two rigid bodies, each rolling contact (ring on the incline, disc in the ring) a
  // contact and a no-slip condition: 3 * 2 - 2 - 2 = 2; the extra coordinate theta comes
  // with its own speed and the centre-line condition that fixes it (+1 - 1). There are no
  // position constraints: only the velocity count applies.
  const int gruebler = 3 * 2 - 2 - 2 + 1 - 1;
  namespace D = mbsc_gen::ring_disc;
  CHECK(D::kNdof == gruebler);
  REQUIRE(D::kNposc == 0);
  const AssemblyModel model{D::kNq,  D::kNu,  0,       D::kNc, nullptr, nullptr, D::velocity_constraints, D::constraint_jacobian,
                            nullptr, D::kConstraintNames};
  for (int k = 0; k < 5; ++k) {
    std::vector<double> x(D::kNx);
    for (double& e : x) e = uniform(-1, 1);
    std::vector<bool> gq(D::kNq, true), gu(D::kNu, false);
    for (int j = 0; j < D::kNdof; ++j) gu[index_of(D::kStateNames, D::kNx, D::kDofNames[j]) - D::kNq] = true;
    check_counts(model, x, gq, gu, nullptr, D::kParamDefaults, 0, gruebler);
  }
}

TEST_CASE("DOF: four-bar through toggles, every partition", "[numeric][dof]") {
  // The same Gruebler count as the four-bar: 3 (4 - 1) - 2 * 4 = 1, whichever of its three
  // independent sets is used (all of them are derived at generation time).
  const int gruebler = 3 * (4 - 1) - 2 * 4;
  namespace T = mbsc_gen::four_bar_toggle;
  CHECK(T::kNdof == gruebler);
  CHECK(T::kNpartitions == 3);
  auto ix = [](const char* n) { return static_cast<std::size_t>(index_of(T::kStateNames, T::kNx, n)); };
  for (int k = 0; k < 5; ++k) {
    std::vector<double> x(T::kNx, 0.0);
    const double th = uniform(-1.5, 1.5);
    x[ix("crank.theta")] = th;
    x[ix("crank.x")] = 0.3 * std::cos(th), x[ix("crank.y")] = 0.3 * std::sin(th);
    x[ix("rocker.theta")] = 1.2, x[ix("rocker.x")] = 1.0 + 0.45 * std::cos(1.2), x[ix("rocker.y")] = 0.45 * std::sin(1.2);
    x[ix("coupler.theta")] = 0.9, x[ix("coupler.x")] = 0.6, x[ix("coupler.y")] = 0.7;
    x[ix("crank.w")] = uniform(-1, 1);
    std::vector<bool> gq(T::kNq, false), gu(T::kNu, false);
    gq[ix("crank.theta")] = true;
    gu[ix("crank.w") - T::kNq] = true;
    check_counts(MBSC_TEST_ASSEMBLY_MODEL(T), x, gq, gu, nullptr, T::kParamDefaults, gruebler, gruebler);
  }
}

TEST_CASE("DOF: ring and disc with rolling joints", "[numeric][dof]") {
  // Two rigid bodies; each rolling joint is a contact (position) and a no-slip
  // (velocity) condition: 3 * 2 - 2 - 2 = 2 at the velocity level, 6 - 2 = 4 positions.
  const int gruebler = 3 * 2 - 2 - 2;
  namespace J = mbsc_gen::ring_disc_joints;
  CHECK(J::kNdof == gruebler);
  REQUIRE(J::kNposc == 2);
  auto ix = [](const char* n) { return static_cast<std::size_t>(index_of(J::kStateNames, J::kNx, n)); };
  for (int k = 0; k < 5; ++k) {
    std::vector<double> x(J::kNx, 0.0);
    const double a = uniform(-3, 3);
    x[ix("R.x")] = uniform(-1, 1);
    x[ix("R.y")] = 1.0;
    x[ix("D.x")] = x[ix("R.x")] + 0.7 * std::sin(a);
    x[ix("D.y")] = 1.0 - 0.7 * std::cos(a) + 0.01;  // a little off: assembly moves it
    x[ix("R.w")] = uniform(-1, 1), x[ix("D.w")] = uniform(-1, 1);
    std::vector<bool> gq(J::kNq, false), gu(J::kNu, false);
    gq[ix("R.x")] = gq[ix("D.x")] = true;
    gu[ix("R.w") - J::kNq] = gu[ix("D.w") - J::kNq] = true;
    check_counts(MBSC_TEST_ASSEMBLY_MODEL(J), x, gq, gu, nullptr, J::kParamDefaults, J::kNq - 2, gruebler);
  }
}
