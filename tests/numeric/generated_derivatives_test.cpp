// SPDX-License-Identifier: GPL-2.0-or-later
// The generated rhs_jacobian and inverse_dynamics_jacobian (generate --derivatives,
// docs/derivatives.md) against central differences of rhs and inverse_dynamics
// (derivative_check.hpp) at random states: shipped models of every kind (a tree in joint
// coordinates, closed loops, nonholonomic rolling, a quaternion body, Coulomb friction,
// custom leaves with inputs; inverse dynamics with as many, more and state-dependent
// inputs), both state layouts and both formulations. A model whose
// multipliers are solved by a minimum-norm solve (redundant constraints) gets a
// rhs_jacobian that returns 4 with NaN, and the rhs itself works.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "derivative_check.hpp"
#include "mbsc/runtime/assemble.hpp"
#include "mbsc/runtime/linear_model.hpp"
#include "arm_lin_d/arm_lin_d.hpp"
#include "arm3_tree_d/arm3_tree_d.hpp"
#include "arm_torques_min_d/arm_torques_min_d.hpp"
#include "dc_motor_d/dc_motor_d.hpp"
#include "dc_motor_mult_d/dc_motor_mult_d.hpp"
#include "dp_d/dp_d.hpp"
#include "dp_min_d/dp_min_d.hpp"
#include "fbq_d/fbq_d.hpp"
#include "five_bar_d/five_bar_d.hpp"
#include "four_bar_d/four_bar_d.hpp"
#include "four_bar_lin_d/four_bar_lin_d.hpp"
#include "four_bar_min_d/four_bar_min_d.hpp"
#include "four_bar_mult_d/four_bar_mult_d.hpp"
#include "heavy_top_d/heavy_top_d.hpp"
#include "humanoid_tree_d/humanoid_tree_d.hpp"
#include "lever_input_d/lever_input_d.hpp"
#include "parallelogram_red_mult_d/parallelogram_red_mult_d.hpp"
#include "rolling_disc_d/rolling_disc_d.hpp"
#include "slider_crank_3d_d/slider_crank_3d_d.hpp"
#include "sph_tree_d/sph_tree_d.hpp"
#include "ssd_d/ssd_d.hpp"
#include "two_inputs_d/two_inputs_d.hpp"
#include "wbj_d/wbj_d.hpp"

namespace {

using Fn = mbsc_test::DerivativeModel::Fn;
using mbsc_test::DerivativeModel;

}  // namespace

TEST_CASE("generated derivatives agree with central differences", "[derivatives]") {
  const DerivativeModel models[] = {MBSC_DERIVATIVE_MODEL(dp_d),      MBSC_DERIVATIVE_MODEL(dp_min_d),        MBSC_DERIVATIVE_MODEL(four_bar_d),  MBSC_DERIVATIVE_MODEL(four_bar_min_d),
                          MBSC_DERIVATIVE_MODEL(four_bar_mult_d), MBSC_DERIVATIVE_MODEL(five_bar_d), MBSC_DERIVATIVE_MODEL(fbq_d),      MBSC_DERIVATIVE_MODEL(heavy_top_d),
                          MBSC_DERIVATIVE_MODEL(humanoid_tree_d), MBSC_DERIVATIVE_MODEL(rolling_disc_d), MBSC_DERIVATIVE_MODEL(slider_crank_3d_d), MBSC_DERIVATIVE_MODEL(ssd_d),
                          MBSC_DERIVATIVE_MODEL(wbj_d),     MBSC_DERIVATIVE_MODEL(dc_motor_d),      MBSC_DERIVATIVE_MODEL(dc_motor_mult_d),
                          MBSC_DERIVATIVE_MODEL(two_inputs_d), MBSC_DERIVATIVE_MODEL(lever_input_d),
                          MBSC_DERIVATIVE_MODEL(arm_torques_min_d),
                          MBSC_DERIVATIVE_MODEL(arm3_tree_d),     MBSC_DERIVATIVE_MODEL(sph_tree_d)};
  std::mt19937 rng(20261206);
  for (int trial = 0; trial < 3; ++trial)
    for (const DerivativeModel& m : models) mbsc_test::check_derivatives(m, rng);
}

// The implicit form (the tree recursion's rhs: residual partials solved with its pivots)
// and forward mode through the dense rhs are two derivations of the same Jacobian: the
// 3R arm in joint coordinates generated both ways agrees to rounding at any state.
TEST_CASE("the implicit form agrees with forward mode through the dense rhs", "[derivatives]") {
  namespace Tree = mbsc_gen::arm3_tree_d;
  namespace Dense = mbsc_gen::arm_lin_d;
  static_assert(Tree::kNx == Dense::kNx && Tree::kNin == Dense::kNin, "one model, one layout");
  for (int i = 0; i < Tree::kNx; ++i) REQUIRE(std::string(Tree::kStateNames[i]) == Dense::kStateNames[i]);
  const std::vector<double> p(Tree::kParamDefaults, Tree::kParamDefaults + Tree::kNp);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> d(-1.5, 1.5);
  for (int trial = 0; trial < 5; ++trial) {
    std::vector<double> x(Tree::kNx), u(static_cast<std::size_t>(Tree::kNin));
    for (double& e : x) e = d(rng);
    for (double& e : u) e = d(rng);
    const double* up = u.empty() ? nullptr : u.data();
    const std::size_t n = static_cast<std::size_t>(Tree::kNx * (Tree::kNx + Tree::kNin));
    std::vector<double> Jt(n), Jd(n);
    REQUIRE(Tree::rhs_jacobian(0.0, x.data(), up, p.data(), Jt.data()) == 0);
    REQUIRE(Dense::rhs_jacobian(0.0, x.data(), up, p.data(), Jd.data()) == 0);
    double size = 1.0;
    for (double v : Jd) size = std::max(size, std::abs(v));
    int moving = 0;
    for (std::size_t k = 0; k < n; ++k) {
      INFO("entry " << k);
      CHECK(std::abs(Jt[k] - Jd[k]) <= 1e-12 * size);
      moving += Jd[k] != 0.0;
    }
    CHECK(moving > Tree::kNx);  // more than the identity block: the dynamics' own entries
  }
}

TEST_CASE("a minimum-norm multiplier solve: rhs_jacobian returns 4 and NaN, the rhs works", "[derivatives]") {
  namespace M = mbsc_gen::parallelogram_red_mult_d;
  const std::vector<double> p(M::kParamDefaults, M::kParamDefaults + M::kNp);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> d(-0.5, 0.5);
  int evaluated = 0;
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<double> x(M::kNx), xd(M::kNx), J(static_cast<std::size_t>(M::kNx * (M::kNx + M::kNin)));
    for (double& e : x) e = d(rng);
    if (M::rhs(0.0, x.data(), nullptr, p.data(), xd.data()) != 0) continue;
    ++evaluated;
    REQUIRE(M::rhs_jacobian(0.0, x.data(), nullptr, p.data(), J.data()) == 4);
    for (double v : J) CHECK(std::isnan(v));
  }
  CHECK(evaluated > 0);
}

// The linear model `mbsc linearize` forms (linear_parts through runtime/linear_model.hpp,
// exact Taylor coefficients) is the same derivative taken another way: along every
// direction the invariants allow (lin.tangent, the model's own motion), A V = J_x V, and
// B = J_u. An arm in joint coordinates (no invariant: V = I) and the four-bar (a loop).
template <class Parts>
void check_against_linearization(const Parts& parts, int nx, int nin, int np, const double* defaults, Fn rhs_jacobian,
                                 const std::vector<double>& x, const char* name) {
  INFO("model " << name);
  const std::vector<double> p(defaults, defaults + np), u(static_cast<std::size_t>(nin), 0.1);
  const double* up = u.empty() ? nullptr : u.data();
  mbsc::runtime::LinearModel lin;
  std::string why;
  REQUIRE(mbsc::runtime::linear_model(parts, 0.0, x.data(), up, p.data(), lin, why) == 0);
  std::vector<double> J(static_cast<std::size_t>(nx * (nx + nin)));
  REQUIRE(rhs_jacobian(0.0, x.data(), up, p.data(), J.data()) == 0);
  REQUIRE(lin.n == nx);
  double size = 1.0;
  for (double v : J) size = std::max(size, std::abs(v));
  for (int k = 0; k < lin.m; ++k)
    for (int i = 0; i < nx; ++i) {
      double av = 0, jv = 0;
      for (int j = 0; j < nx; ++j) {
        const double v = lin.tangent[static_cast<std::size_t>(j * lin.m + k)];
        av += lin.A[static_cast<std::size_t>(i * nx + j)] * v;
        jv += J[static_cast<std::size_t>(i * nx + j)] * v;
      }
      INFO("row " << i << ", tangent direction " << k);
      CHECK(std::abs(av - jv) <= 1e-10 * size);
    }
  for (int i = 0; i < nx * nin; ++i)
    CHECK(std::abs(lin.B[static_cast<std::size_t>(i)] - J[static_cast<std::size_t>(nx * nx + i)]) <= 1e-10 * size);
}

// The full state with the named values (given: kept), the rest assembled onto the invariants.
struct Value {
  const char* name;
  double v;
  bool given;
};
std::vector<double> assembled(const mbsc::runtime::AssemblyModel& am, const char* const* names, const double* p,
                              const std::vector<Value>& values) {
  const int nx = am.nq + am.nu;
  std::vector<double> x(static_cast<std::size_t>(nx), 0.0);
  std::vector<bool> given_q(static_cast<std::size_t>(am.nq), false), given_u(static_cast<std::size_t>(am.nu), false);
  for (const Value& v : values) {
    int at = -1;
    for (int i = 0; i < nx; ++i)
      if (std::string(names[i]) == v.name) at = i;
    INFO("state " << v.name);
    REQUIRE(at >= 0);
    x[static_cast<std::size_t>(at)] = v.v;
    if (v.given) (at < am.nq ? given_q[static_cast<std::size_t>(at)] : given_u[static_cast<std::size_t>(at - am.nq)]) = true;
  }
  REQUIRE(mbsc::runtime::assemble(am, 0.0, x, given_q, given_u, nullptr, p).status ==
          mbsc::runtime::AssemblyResult::Status::Ok);
  return x;
}

#define ASSEMBLY(M)                                                                                                  \
  mbsc::runtime::AssemblyModel {                                                                                     \
    M::kNq, M::kNu, M::kNposc, M::kNc, M::position_constraints, M::position_jacobian, M::velocity_constraints,        \
        M::constraint_jacobian, M::kPositionConstraintNames, M::kConstraintNames                                     \
  }

TEST_CASE("rhs_jacobian equals the linearization of mbsc linearize", "[derivatives][linear_model]") {
  {
    namespace M = mbsc_gen::arm_lin_d;
    const std::vector<double> x = assembled(ASSEMBLY(M), M::kStateNames, M::kParamDefaults,
                                            {{"q1", 0.3, true}, {"q2", -0.7, true}, {"q3", 1.1, true},
                                             {"q1_dot", 0.5, true}, {"q2_dot", -0.2, true}, {"q3_dot", 0.9, true}});
    check_against_linearization(MBSC_LINEAR_PARTS(M), M::kNx, M::kNin, M::kNp, M::kParamDefaults, M::rhs_jacobian, x,
                                "three_r_arm_joint");
  }
  {
    namespace M = mbsc_gen::four_bar_lin_d;
    const std::vector<double> x = assembled(ASSEMBLY(M), M::kStateNames, M::kParamDefaults,
                                            {{"crank.theta", 1.0, true}, {"coupler.theta", 0.3, false},
                                             {"rocker.theta", 1.5, false}, {"crank.w", 3.0, true}});
    check_against_linearization(MBSC_LINEAR_PARTS(M), M::kNx, M::kNin, M::kNp, M::kParamDefaults, M::rhs_jacobian, x,
                                "four_bar");
  }
}
