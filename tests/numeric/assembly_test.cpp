// SPDX-License-Identifier: GPL-2.0-or-later
// Assembly (include/mbsc/runtime/assemble.hpp): consistent states of the four-bar and the
// five-bar from their driving angles and rates, and a clear failure for data that cannot
// be completed.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "five_bar/five_bar.hpp"
#include "four_bar/four_bar.hpp"
#include "heavy_top/heavy_top.hpp"
#include "mbsc/runtime/assemble.hpp"
#include "slider_crank_3d/slider_crank_3d.hpp"
#include "test_support.hpp"

using mbsc::runtime::AssemblyModel;
using mbsc::runtime::AssemblyResult;
using mbsc_test::index_of;

namespace {

template <class T>
double largest(const T& v) {
  double w = 0.0;
  for (double e : v) w = std::max(w, std::fabs(e));
  return w;
}

}  // namespace

TEST_CASE("assembly: four-bar from the crank angle and rate", "[numeric][assembly]") {
  namespace F = mbsc_gen::four_bar;
  const auto model = MBSC_TEST_ASSEMBLY_MODEL(F);
  auto ix = [](const char* n) { return static_cast<std::size_t>(index_of(F::kStateNames, F::kNx, n)); };
  for (double crank : {0.3, 1.2, 2.5, 4.0, 5.5}) {
    // Only the crank is given; the other bodies start at rough angles, their centres at 0.
    std::vector<double> x(F::kNx, 0.0);
    x[ix("crank.theta")] = crank;
    x[ix("coupler.theta")] = 0.4;
    x[ix("rocker.theta")] = 1.9;
    x[ix("crank.w")] = 2.0;
    std::vector<bool> given_q(F::kNq, false), given_u(F::kNu, false);
    given_q[ix("crank.theta")] = true;
    given_u[ix("crank.w") - F::kNq] = true;
    const AssemblyResult r = mbsc::runtime::assemble(model, 0.0, x, given_q, given_u, nullptr, F::kParamDefaults);
    INFO(r.message);
    REQUIRE(r.ok());
    CHECK(x[ix("crank.theta")] == crank);
    CHECK(x[ix("crank.w")] == 2.0);
    // Independent check with the generated residuals.
    std::vector<double> g(F::kNposc), v(F::kNc);
    REQUIRE(F::position_constraints(0.0, x.data(), nullptr, F::kParamDefaults, g.data()) == 0);
    REQUIRE(F::velocity_constraints(0.0, x.data(), nullptr, F::kParamDefaults, v.data()) == 0);
    CHECK(largest(g) < 1e-12);
    CHECK(largest(v) < 1e-12);
    CHECK(!r.near_singular);
  }
}

TEST_CASE("assembly: data that cannot be completed name the constraint", "[numeric][assembly]") {
  namespace F = mbsc_gen::four_bar;
  const auto model = MBSC_TEST_ASSEMBLY_MODEL(F);
  auto ix = [](const char* n) { return static_cast<std::size_t>(index_of(F::kStateNames, F::kNx, n)); };
  // Crank and rocker both given, at angles the coupler cannot join.
  std::vector<double> x(F::kNx, 0.0);
  x[ix("crank.theta")] = 0.0;
  x[ix("rocker.theta")] = 0.0;
  std::vector<bool> given_q(F::kNq, false), given_u(F::kNu, false);
  given_q[ix("crank.theta")] = true;
  given_q[ix("rocker.theta")] = true;
  const AssemblyResult r = mbsc::runtime::assemble(model, 0.0, x, given_q, given_u, nullptr, F::kParamDefaults);
  CHECK(r.status == AssemblyResult::Status::PositionNotSolved);
  REQUIRE(r.worst_constraint >= 0);
  CHECK(r.message.find(std::string("'") + F::kPositionConstraintNames[r.worst_constraint] + "'") != std::string::npos);
  // Speeds that contradict the constraints: the crank and rocker rates both given.
  std::vector<double> y(F::kNx, 0.0);
  y[ix("crank.theta")] = 1.2;
  y[ix("coupler.theta")] = 0.4;
  y[ix("rocker.theta")] = 1.9;
  y[ix("crank.w")] = 1.0;
  y[ix("rocker.w")] = 5.0;
  std::vector<bool> gq(F::kNq, false), gu(F::kNu, false);
  gq[ix("crank.theta")] = true;
  gu[ix("crank.w") - F::kNq] = true;
  gu[ix("rocker.w") - F::kNq] = true;
  const AssemblyResult s = mbsc::runtime::assemble(model, 0.0, y, gq, gu, nullptr, F::kParamDefaults);
  CHECK(s.status == AssemblyResult::Status::VelocityNotSolved);
  CHECK(s.message.find("velocity constraint '") != std::string::npos);
  // With the state names, the message says which free coordinates the row could not place.
  mbsc::runtime::AssemblyModel named = model;
  named.state_names = F::kStateNames;
  std::vector<double> z(F::kNx, 0.0);
  const AssemblyResult n = mbsc::runtime::assemble(named, 0.0, z, given_q, given_u, nullptr, F::kParamDefaults);
  INFO(n.message);
  CHECK(n.status == AssemblyResult::Status::PositionNotSolved);
  CHECK(n.message.find("the coordinates it could not place: ") != std::string::npos);
  const std::string placed = n.message.substr(n.message.find("could not place: "));
  CHECK(placed.find("rocker.x") != std::string::npos);       // free, read by the row Q_x
  CHECK(placed.find("rocker.theta") == std::string::npos);   // given: not among them
}

TEST_CASE("assembly: a quaternion with no guess starts at the identity", "[numeric][assembly]") {
  namespace H = mbsc_gen::heavy_top;
  mbsc::runtime::AssemblyModel model = MBSC_TEST_ASSEMBLY_MODEL(H);
  auto ix = [](const char* n) { return static_cast<std::size_t>(index_of(H::kStateNames, H::kNx, n)); };
  std::vector<bool> given_q(H::kNq, false), given_u(H::kNu, false);
  // Without the quaternion's indices, all four entries at 0 are kept (no rotation: the
  // tip's row has no solution); with them, the identity and the top upright.
  for (const bool with_indices : {false, true}) {
    model.quaternion_indices = with_indices ? H::kQuaternionIndices : nullptr;
    model.nquaternions = with_indices ? H::kNquaternions : 0;
    std::vector<double> x(H::kNx, 0.0);
    const AssemblyResult r = mbsc::runtime::assemble(model, 0.0, x, given_q, given_u, nullptr, H::kParamDefaults);
    INFO(r.message);
    if (!with_indices) continue;
    REQUIRE(r.ok());
    CHECK(x[ix("top.e0")] == Approx(1.0));
    CHECK(std::fabs(x[ix("top.e1")]) + std::fabs(x[ix("top.e2")]) + std::fabs(x[ix("top.e3")]) < 1e-12);
  }
}

TEST_CASE("assembly: a quaternion that assembly moves stays of unit length", "[numeric][assembly]") {
  // The 3-D slider-crank (thesis Ex 4.5) with its slide given: the crank's attitude, a
  // quaternion held to the x axis by its hinge, must turn from the guess. A Newton step on
  // the position rows alone also scales the quaternion (the hinge's rows read its
  // entries); with the quaternions' indices the row |e|^2 = 1 is solved with them.
  namespace S = mbsc_gen::slider_crank_3d;
  mbsc::runtime::AssemblyModel model = MBSC_TEST_ASSEMBLY_MODEL(S);
  model.state_names = S::kStateNames;
  auto ix = [](const char* n) { return static_cast<std::size_t>(index_of(S::kStateNames, S::kNx, n)); };
  auto par = [](const char* n) { return S::kParamDefaults[index_of(S::kParamNames, S::kNp, n)]; };
  const double l1 = par("l1"), l2 = par("l2"), slide = 1.3;
  for (const bool with_indices : {false, true}) {
    model.quaternion_indices = with_indices ? S::kQuaternionIndices : nullptr;
    model.nquaternions = with_indices ? S::kNquaternions : 0;
    std::vector<double> x(S::kNx, 0.0);
    // The guesses of `mbsc inverse ... --init crank.e0=0.95 --init crank.e1=0.3`, unit.
    x[ix("crank.e0")] = 0.95 / std::hypot(0.95, 0.3), x[ix("crank.e1")] = 0.3 / std::hypot(0.95, 0.3);
    x[ix("rod.x")] = par("gamma2") * l2, x[ix("rod.y")] = -l1;
    x[ix("slider.e0")] = 1.0, x[ix("slider.x")] = slide, x[ix("slider.y")] = -l1;
    std::vector<bool> given_q(S::kNq, false), given_u(S::kNu, false);
    given_q[ix("slider.x")] = true;
    const AssemblyResult r = mbsc::runtime::assemble(model, 0.0, x, given_q, given_u, nullptr, S::kParamDefaults);
    INFO(r.message);
    REQUIRE(r.ok());
    const double e0 = x[ix("crank.e0")], e1 = x[ix("crank.e1")], e2 = x[ix("crank.e2")], e3 = x[ix("crank.e3")];
    const double norm2 = e0 * e0 + e1 * e1 + e2 * e2 + e3 * e3;
    if (!with_indices) {
      CHECK(std::fabs(norm2 - 1.0) > 1e-3);  // the failure the unit rows mend
      continue;
    }
    CHECK(norm2 == Approx(1.0).margin(1e-12));
    // The crank's angle chi about x closes the loop: x2^2 = l2^2 - 2 l1^2 (1 - cos chi)
    // (thesis invariants (d)), with chi = 2 atan2(e1, e0).
    const double chi = 2 * std::atan2(e1, e0);
    CHECK(slide * slide == Approx(l2 * l2 - 2 * l1 * l1 * (1 - std::cos(chi))).epsilon(1e-12));
  }
}

TEST_CASE("assembly: five-bar with motors from the two base angles and rates", "[numeric][assembly]") {
  namespace F = mbsc_gen::five_bar;
  const auto model = MBSC_TEST_ASSEMBLY_MODEL(F);
  auto ix = [](const char* n) { return static_cast<std::size_t>(index_of(F::kStateNames, F::kNx, n)); };
  std::vector<double> x(F::kNx, 0.0);
  // The base angles and their rates (the thesis's inputs), rough guesses for the elbows.
  x[ix("linkage.left.theta")] = 2.0;
  x[ix("linkage.right.theta")] = 1.1;
  x[ix("linkage.left.phi")] = 1.0;
  x[ix("linkage.right.phi")] = 2.1;
  x[ix("linkage.left.dtheta")] = 0.5;
  x[ix("linkage.right.dtheta")] = -0.3;
  std::vector<bool> given_q(F::kNq, false), given_u(F::kNu, false);
  given_q[ix("linkage.left.theta")] = true;
  given_q[ix("linkage.right.theta")] = true;
  given_u[ix("linkage.left.dtheta") - F::kNq] = true;
  given_u[ix("linkage.right.dtheta") - F::kNq] = true;
  const double u[2] = {0.0, 0.0};
  const AssemblyResult r = mbsc::runtime::assemble(model, 0.0, x, given_q, given_u, u, F::kParamDefaults);
  INFO(r.message);
  REQUIRE(r.ok());
  std::vector<double> g(F::kNposc), v(F::kNc);
  REQUIRE(F::position_constraints(0.0, x.data(), u, F::kParamDefaults, g.data()) == 0);
  REQUIRE(F::velocity_constraints(0.0, x.data(), u, F::kParamDefaults, v.data()) == 0);
  CHECK(largest(g) < 1e-12);
  CHECK(largest(v) < 1e-12);
  CHECK(x[ix("linkage.left.theta")] == 2.0);
  CHECK(x[ix("linkage.right.dtheta")] == -0.3);
  // The payload closes the loop: both elbow chains end at it.
  const double s = 0.1, aU = 0.25, aB = 0.35;
  const double lx = -s + aU * std::cos(x[ix("linkage.left.theta")]) + aB * std::cos(x[ix("linkage.left.phi")]);
  const double rx = s + aU * std::cos(x[ix("linkage.right.theta")]) + aB * std::cos(x[ix("linkage.right.phi")]);
  CHECK(lx == Approx(rx).margin(1e-9));
}
