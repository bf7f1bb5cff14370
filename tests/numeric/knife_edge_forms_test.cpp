// SPDX-License-Identifier: GPL-2.0-or-later
// The knife edge's `axis` option (a non-unit axis, normalized) and its nodal-body form
// against the same blade written by hand as a `constraint velocity` (tests/data/planar/
// knife_axis*.mbs): at random states the two models have the same velocity residuals,
// the same constraint Jacobian and the same accelerations (for the nodal body at states
// where its nodes move rigidly: elsewhere the joint's frame of A and B and the node P
// tell different stories, as they may).
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "knife_axis/knife_axis.hpp"
#include "knife_axis_hand/knife_axis_hand.hpp"
#include "knife_axis_nodal/knife_axis_nodal.hpp"
#include "knife_axis_nodal_hand/knife_axis_nodal_hand.hpp"

namespace {

using Fn = int (*)(double, const double*, const double*, const double*, double*);

/// What the comparison reads of one generated model.
struct Model {
  int nx, ndof, nc, nu_full;
  const char* const* constraint_names;
  const char* const* state_names;
  const char* const* dof_names;
  const double* params;
  Fn rhs, velocity_constraints, constraint_jacobian;
};

#define MBSC_MODEL(NS)                                                                                      \
  Model {                                                                                                   \
    NS::kNx, NS::kNdof, NS::kNc, NS::kNuFull, NS::kConstraintNames, NS::kStateNames, NS::kDofNames,          \
        NS::kParamDefaults, &NS::rhs, &NS::velocity_constraints, &NS::constraint_jacobian                   \
  }

/// The row of the blade (the joint's `blade.lateral`, the hand-written `lateral`) and the
/// other rows by name.
int row_of(const Model& m, const std::string& name) {
  for (int i = 0; i < m.nc; ++i)
    if (m.constraint_names[i] == name) return i;
  return -1;
}

/// A random state: every entry at random, or (`rigid`, a nodal body with nodes A, B, P
/// at (0, 0), (1, 0), (0.4, 0.2) in the body) one where the nodes move as one rigid body,
/// where the joint's velocity of P (through the frame of A and B) is P's own speeds.
std::vector<double> random_state(const Model& m, std::mt19937& rng, bool rigid) {
  std::uniform_real_distribution<double> any(-2.0, 2.0);
  std::vector<double> x(static_cast<std::size_t>(m.nx));
  for (double& v : x) v = any(rng);
  if (!rigid) return x;
  auto set = [&](const std::string& name, double v) {
    for (int i = 0; i < m.nx; ++i)
      if (m.state_names[i] == name) x[static_cast<std::size_t>(i)] = v;
  };
  const double th = any(rng), ax = any(rng), ay = any(rng), au = any(rng), av = any(rng), w = any(rng);
  const double c = std::cos(th), s = std::sin(th);
  const double bx = 1.0, by = 0.0, px = 0.4, py = 0.2;  // in the body
  for (const auto& [node, lx, ly] : {std::tuple<std::string, double, double>{"A", 0.0, 0.0}, {"B", bx, by}, {"P", px, py}}) {
    const double rx = c * lx - s * ly, ry = s * lx + c * ly;  // R(th) (b - b_A)
    set("s." + node + "_x", ax + rx);
    set("s." + node + "_y", ay + ry);
    set("s." + node + "_u", au - w * ry);
    set("s." + node + "_v", av + w * rx);
  }
  set("s.w", w);
  return x;
}

void compare(const Model& joint, const Model& hand, std::uint32_t seed, bool rigid) {
  REQUIRE(joint.nx == hand.nx);
  REQUIRE(joint.nc == hand.nc);
  REQUIRE(joint.nu_full == hand.nu_full);
  REQUIRE(joint.ndof == hand.ndof);
  for (int i = 0; i < joint.nx; ++i) REQUIRE(std::string(joint.state_names[i]) == hand.state_names[i]);
  for (int i = 0; i < joint.ndof; ++i) REQUIRE(std::string(joint.dof_names[i]) == hand.dof_names[i]);
  std::vector<int> hand_row(static_cast<std::size_t>(joint.nc));
  for (int i = 0; i < joint.nc; ++i) {
    const std::string name = joint.constraint_names[i];
    hand_row[static_cast<std::size_t>(i)] = row_of(hand, name == "blade.lateral" ? "lateral" : name);
    INFO("constraint " << name);
    REQUIRE(hand_row[static_cast<std::size_t>(i)] >= 0);
  }
  std::mt19937 rng(seed);
  const int n = joint.nx, nc = joint.nc, nu = joint.nu_full;
  for (int k = 0; k < 20; ++k) {
    const std::vector<double> x = random_state(joint, rng, rigid);
    std::vector<double> cj(static_cast<std::size_t>(nc)), ch(cj), aj(static_cast<std::size_t>(nc * nu)), ah(aj);
    REQUIRE(joint.velocity_constraints(0.0, x.data(), nullptr, joint.params, cj.data()) == 0);
    REQUIRE(hand.velocity_constraints(0.0, x.data(), nullptr, hand.params, ch.data()) == 0);
    REQUIRE(joint.constraint_jacobian(0.0, x.data(), nullptr, joint.params, aj.data()) == 0);
    REQUIRE(hand.constraint_jacobian(0.0, x.data(), nullptr, hand.params, ah.data()) == 0);
    for (int i = 0; i < nc; ++i) {
      const int h = hand_row[static_cast<std::size_t>(i)];
      INFO("state " << k << ", constraint " << joint.constraint_names[i]);
      CHECK(cj[static_cast<std::size_t>(i)] == Approx(ch[static_cast<std::size_t>(h)]).margin(1e-12));
      if (!rigid) {
        for (int j = 0; j < nu; ++j)
          CHECK(aj[static_cast<std::size_t>(i * nu + j)] == Approx(ah[static_cast<std::size_t>(h * nu + j)]).margin(1e-12));
        continue;
      }
      // The nodal rows may differ by the rigidity rows: they agree on the rigid motions,
      // as the speeds of this state (the last nu entries).
      double dj = 0.0, dh = 0.0;
      for (int j = 0; j < nu; ++j) {
        const double v = x[static_cast<std::size_t>(n - nu + j)];
        dj += aj[static_cast<std::size_t>(i * nu + j)] * v;
        dh += ah[static_cast<std::size_t>(h * nu + j)] * v;
      }
      CHECK(dj == Approx(dh).margin(1e-12));
    }
    std::vector<double> xj(static_cast<std::size_t>(n)), xh(xj);
    const int rj = joint.rhs(0.0, x.data(), nullptr, joint.params, xj.data());
    const int rh = hand.rhs(0.0, x.data(), nullptr, hand.params, xh.data());
    REQUIRE(rj == rh);
    if (rj != 0) continue;  // a singular independent set at this state, in both
    for (int i = 0; i < n; ++i) {
      INFO("state " << k << ", rate of " << joint.state_names[i]);
      CHECK(xj[static_cast<std::size_t>(i)] == Approx(xh[static_cast<std::size_t>(i)]).epsilon(1e-10).margin(1e-10));
    }
  }
}

}  // namespace

TEST_CASE("knife edge: a non-unit axis off the mass centre is the hand-written blade", "[numeric][knife_edge]") {
  compare(MBSC_MODEL(mbsc_gen::knife_axis), MBSC_MODEL(mbsc_gen::knife_axis_hand), 11, false);
}

TEST_CASE("knife edge: on a nodal body, at a node along a non-unit axis, is the hand-written blade",
          "[numeric][knife_edge]") {
  compare(MBSC_MODEL(mbsc_gen::knife_axis_nodal), MBSC_MODEL(mbsc_gen::knife_axis_nodal_hand), 12, true);
}
