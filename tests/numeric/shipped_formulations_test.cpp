// SPDX-License-Identifier: GPL-2.0-or-later
// Every shipped model (models/*.mbs) in both formulations: the complement (modular) form
// and the Lagrange-multiplier form with Baumgarte stabilization must describe the same
// motion. One table drives all models alike:
//   - consistent random states: a per-model nominal configuration is assembled from rough
//     guesses; each trial perturbs it, gives the independent coordinates and the
//     independent speeds (kDofNames) random values, and lets mbsc::runtime::assemble solve
//     the rest (positions by Newton, speeds from the velocity constraints). A trial whose
//     assembly fails or ends near a singular configuration is retried, but most must
//     succeed;
//   - at 12 such states the full state derivatives agree to 1e-9 relative
//     (scale = max(1, max |xdot|) of the complement);
//   - RK4 over 1 s (h = 1.25e-4, see kStep) from the nominal state gives trajectories whose largest
//     state difference stays below 1e-7.
// Models with inputs run with fixed nonzero inputs. Other tests check some of these pairs
// in more depth; this one is the single place that holds the rule for all of them.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "chaplygin_sleigh/chaplygin_sleigh.hpp"
#include "chaplygin_sleigh_mult/chaplygin_sleigh_mult.hpp"
#include "double_pendulum/double_pendulum.hpp"
#include "double_pendulum_mult/double_pendulum_mult.hpp"
#include "five_bar/five_bar.hpp"
#include "five_bar_mult/five_bar_mult.hpp"
#include "four_bar/four_bar.hpp"
#include "four_bar_mult/four_bar_mult.hpp"
#include "four_bar_toggle/four_bar_toggle.hpp"
#include "four_bar_toggle_mult/four_bar_toggle_mult.hpp"
#include "free_body_euler/free_body_euler.hpp"
#include "free_body_euler_mult/free_body_euler_mult.hpp"
#include "free_body_quaternion/free_body_quaternion.hpp"
#include "free_body_quaternion_mult/free_body_quaternion_mult.hpp"
#include "heavy_top/heavy_top.hpp"
#include "heavy_top_mult/heavy_top_mult.hpp"
#include "sssp/sssp.hpp"
#include "sssp_mult/sssp_mult.hpp"
#include "slider_crank_3d/slider_crank_3d.hpp"
#include "slider_crank_3d_mult/slider_crank_3d_mult.hpp"
#include "massless_rod_pendulum/massless_rod_pendulum.hpp"
#include "massless_rod_pendulum_mult/massless_rod_pendulum_mult.hpp"
#include "mbsc/runtime/assemble.hpp"
#include "mbsc/runtime/rk4.hpp"
#include "parallelogram_chain/parallelogram_chain.hpp"
#include "parallelogram_chain_mult/parallelogram_chain_mult.hpp"
#include "rolling_disc/rolling_disc.hpp"
#include "rolling_disc_mult/rolling_disc_mult.hpp"
#include "rolling_disc_incline/rolling_disc_incline.hpp"
#include "rolling_disc_incline_mult/rolling_disc_incline_mult.hpp"
#include "sphere_trough/sphere_trough.hpp"
#include "sphere_trough_mult/sphere_trough_mult.hpp"
#include "ring_disc/ring_disc.hpp"
#include "ring_disc_joints/ring_disc_joints.hpp"
#include "ring_disc_joints_mult/ring_disc_joints_mult.hpp"
#include "ring_disc_mult/ring_disc_mult.hpp"
#include "slider_crank/slider_crank.hpp"
#include "slider_crank_mult/slider_crank_mult.hpp"
#include "spherical_pendulum_angles/spherical_pendulum_angles.hpp"
#include "spherical_pendulum_angles_mult/spherical_pendulum_angles_mult.hpp"
#include "spherical_pendulum_cartesian/spherical_pendulum_cartesian.hpp"
#include "spherical_pendulum_cartesian_mult/spherical_pendulum_cartesian_mult.hpp"
#include "spherical_pendulum_extra_speed/spherical_pendulum_extra_speed.hpp"
#include "spherical_pendulum_extra_speed_mult/spherical_pendulum_extra_speed_mult.hpp"
#include "stiff_spring_damper/stiff_spring_damper.hpp"
#include "stiff_spring_damper_mult/stiff_spring_damper_mult.hpp"
#include "test_support.hpp"
#include "three_r_arm/three_r_arm.hpp"
#include "three_r_arm_mult/three_r_arm_mult.hpp"
#include "three_r_arm_joint/three_r_arm_joint.hpp"
#include "three_r_arm_joint_mult/three_r_arm_joint_mult.hpp"
#include "three_rrr/three_rrr.hpp"
#include "three_rrr_mult/three_rrr_mult.hpp"
#include "whipple_bicycle/whipple_bicycle.hpp"
#include "whipple_bicycle_mult/whipple_bicycle_mult.hpp"
#include "whipple_bicycle_joints/whipple_bicycle_joints.hpp"
#include "whipple_bicycle_joints_mult/whipple_bicycle_joints_mult.hpp"
#include "whitworth/whitworth.hpp"
#include "gantry_crane/gantry_crane.hpp"
#include "gantry_crane_mult/gantry_crane_mult.hpp"
#include "spatial_arm/spatial_arm.hpp"
#include "spatial_arm_mult/spatial_arm_mult.hpp"
#include "whitworth_mult/whitworth_mult.hpp"

using mbsc::runtime::AssemblyModel;
using mbsc::runtime::AssemblyResult;
using mbsc_test::index_of;

namespace {

constexpr double kAlpha = 10.0, kBeta = 10.0;  // Baumgarte gains of the multipliers builds
constexpr int kStates = 12;                     // consistent random states per model
constexpr int kAttempts = 24;                   // at most this many assembly tries for them
// RK4 over the 1 s trajectories. Off the constraint manifold the two formulations are
// different vector fields (Baumgarte pulls the multipliers run back, the complement run
// drifts), so the trajectory difference is of the order of RK4's own constraint drift,
// O(h^4): with h = 5e-4 the fast runs (five_bar, four_bar_toggle, slider_crank) differ by
// 3e-7 to 4e-7, with 2.5e-4 by 2e-8 to 3e-8 and with 1.25e-4 by 1e-9 to 2e-9 (halving h
// divides it by 16). h = 1.25e-4 keeps the integration error well below the 1e-7 bound.
constexpr double kStep = 1.25e-4;
constexpr int kSteps = 8000;

using Fn = int (*)(double, const double*, const double*, const double*, double*);

/// One shipped model generated twice: the complement build (sizes, names, the functions
/// assembly needs) and its multipliers twin (same state layout, p[] = model's + alpha, beta).
struct Pair {
  const char* name;
  int nq, nu, nx, ndof, nin, np, nposc, nc;
  const char* const* state_names;
  const char* const* dof_names;
  const double* params;
  Fn rhs;
  Fn position_constraints;  // nullptr when the model has no position constraints
  Fn velocity_constraints;
  AssemblyModel assembly;
  int m_nx, m_np, m_nc;
  const char* const* m_state_names;
  const double* m_params;
  Fn m_rhs;
};

// Generated namespaces cannot be template arguments, so a macro gathers each model's
// constants and function pointers. A model without position constraints has no
// position_constraints / position_jacobian functions: PAIR_VELOCITY_ONLY passes nullptr.
#define PAIR_WITH(NAME, C, M, POSC, POSJ)                                                                             \
  Pair {                                                                                                              \
    NAME, C::kNq, C::kNu, C::kNx, C::kNdof, C::kNin, C::kNp, C::kNposc, C::kNc, C::kStateNames, C::kDofNames,        \
        C::kParamDefaults, C::rhs, POSC, C::velocity_constraints,                                                     \
        AssemblyModel{C::kNq,  C::kNu, C::kNposc, C::kNc, POSC, POSJ, C::velocity_constraints, C::constraint_jacobian, \
                      C::kPositionConstraintNames, C::kConstraintNames},                                             \
        M::kNx, M::kNp, M::kNc, M::kStateNames, M::kParamDefaults, M::rhs                                            \
  }
#define PAIR(NAME) PAIR_WITH(#NAME, mbsc_gen::NAME, mbsc_gen::NAME##_mult, mbsc_gen::NAME::position_constraints, \
                             mbsc_gen::NAME::position_jacobian)
#define PAIR_VELOCITY_ONLY(NAME) PAIR_WITH(#NAME, mbsc_gen::NAME, mbsc_gen::NAME##_mult, nullptr, nullptr)

/// A state entry drawn uniformly from nominal +- spread.
struct Range {
  const char* name;
  double nominal, spread;
};

/// One row of the table.
struct Case {
  Pair pair;
  std::vector<std::pair<const char*, double>> guess;  // rough guesses of the other coordinates (rest 0)
  std::vector<Range> coordinates;                     // the independent coordinates (kept by assembly)
  std::vector<Range> speeds;                          // the independent speeds, exactly kDofNames
  std::vector<double> inputs;                         // fixed inputs, kNin values
  std::vector<const char*> nonlinear_speeds;          // speeds of nonlinear velocity constraints (see complete)
  int substeps = 1;  // RK4 steps per kStep: a stiff model needs steps inside RK4's stability interval
};

std::size_t at(const Pair& m, const char* name) { return static_cast<std::size_t>(index_of(m.state_names, m.nx, name)); }

double largest_abs(const std::vector<double>& v) {
  double w = 0.0;
  for (double e : v) w = std::max(w, std::abs(e));
  return w;
}

/// The multipliers build's parameters: the model's defaults, then alpha and beta.
std::vector<double> multiplier_params(const Pair& m) {
  std::vector<double> p(m.params, m.params + m.np);
  p.push_back(kAlpha);
  p.push_back(kBeta);
  return p;
}

/// Completes x (the table's coordinates and speeds already set) to a consistent state.
/// The assembly tolerance is 1e-14 (default 1e-12): the multipliers rhs adds the Baumgarte
/// terms 2 alpha f' + beta^2 f, so at a state that is consistent only to 1e-12 the two
/// formulations differ by design. Whitworth amplifies that most: at the default tolerance
/// its crank.w' differed by up to 1.9e-9 relative (1e-14 with alpha = beta = 0); at 1e-14
/// the difference is 3e-11.
/// assemble() solves the velocity constraints as affine in the speeds (once, with the free
/// speeds at zero). A constraint that is nonlinear in the speeds (the extra speed
/// v2 = |r'|^2) is then right only in the speeds it is affine in; a second pass that keeps
/// every coordinate and every other speed solves the speeds named in nonlinear_speeds.
AssemblyResult complete(const Case& c, std::vector<double>& x) {
  const Pair& m = c.pair;
  std::vector<bool> gq(static_cast<std::size_t>(m.nq), false), gu(static_cast<std::size_t>(m.nu), false);
  for (const Range& r : c.coordinates) gq[at(m, r.name)] = true;
  for (const Range& r : c.speeds) gu[at(m, r.name) - static_cast<std::size_t>(m.nq)] = true;
  const double* u = c.inputs.empty() ? nullptr : c.inputs.data();
  mbsc::runtime::AssemblyOptions opt;
  opt.tolerance = 1e-14;
  AssemblyResult res = mbsc::runtime::assemble(m.assembly, 0.0, x, gq, gu, u, m.params, opt);
  if (c.nonlinear_speeds.empty() || res.status != AssemblyResult::Status::VelocityNotSolved) return res;
  const bool near_singular = res.near_singular;
  std::fill(gq.begin(), gq.end(), true);
  std::fill(gu.begin(), gu.end(), true);
  for (const char* s : c.nonlinear_speeds) gu[at(m, s) - static_cast<std::size_t>(m.nq)] = false;
  res = mbsc::runtime::assemble(m.assembly, 0.0, x, gq, gu, u, m.params, opt);
  res.near_singular = res.near_singular || near_singular;
  return res;
}

/// The largest position and velocity constraint residuals at x (independent of assembly).
double residual(const Case& c, const std::vector<double>& x) {
  const Pair& m = c.pair;
  const double* u = c.inputs.empty() ? nullptr : c.inputs.data();
  std::vector<double> g(static_cast<std::size_t>(std::max(m.nposc, 1))), r(static_cast<std::size_t>(std::max(m.nc, 1)));
  double worst = 0.0;
  if (m.nposc > 0) {
    REQUIRE(m.position_constraints(0.0, x.data(), u, m.params, g.data()) == 0);
    worst = std::max(worst, largest_abs(g));
  }
  if (m.nc > 0) {
    REQUIRE(m.velocity_constraints(0.0, x.data(), u, m.params, r.data()) == 0);
    worst = std::max(worst, largest_abs(r));
  }
  return worst;
}

/// The nominal state: the table's coordinates and speeds at their nominal values, the rest
/// from the rough guesses, assembled.
std::vector<double> nominal_state(const Case& c) {
  const Pair& m = c.pair;
  std::vector<double> x(static_cast<std::size_t>(m.nx), 0.0);
  for (const auto& g : c.guess) x[at(m, g.first)] = g.second;
  for (const Range& r : c.coordinates) x[at(m, r.name)] = r.nominal;
  for (const Range& r : c.speeds) x[at(m, r.name)] = r.nominal;
  const AssemblyResult res = complete(c, x);
  INFO("nominal: " << res.message);
  REQUIRE(res.ok());
  REQUIRE_FALSE(res.near_singular);
  return x;
}

struct Summary {
  int states = 0, failures = 0;
  double worst_relative = 0.0;   // largest |xdot_c - xdot_m| / max(1, max |xdot_c|) over the states
  double worst_residual = 0.0;   // largest constraint residual of the assembled states
  double trajectory = 0.0;       // largest state difference over the 1 s runs
  double travelled = 0.0;        // largest change of a state entry over the run (it moved)
  double drift = 0.0;            // the complement run's constraint residual after 1 s
};

/// Both formulations' state derivatives at x; returns the scaled largest difference.
double compare_rhs(const Case& c, const std::vector<double>& x, const std::vector<double>& pm) {
  const Pair& m = c.pair;
  const double* u = c.inputs.empty() ? nullptr : c.inputs.data();
  std::vector<double> a(static_cast<std::size_t>(m.nx)), b(static_cast<std::size_t>(m.nx));
  REQUIRE(m.rhs(0.0, x.data(), u, m.params, a.data()) == 0);
  REQUIRE(m.m_rhs(0.0, x.data(), u, pm.data(), b.data()) == 0);
  const double scale = std::max(1.0, largest_abs(a));
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    INFO(c.pair.name << ": " << m.state_names[i] << "' complement " << a[i] << ", multipliers " << b[i]);
    CHECK(std::abs(a[i] - b[i]) <= 1e-9 * scale);
    worst = std::max(worst, std::abs(a[i] - b[i]) / scale);
  }
  return worst;
}

Summary check_case(const Case& c, unsigned seed) {
  const Pair& m = c.pair;
  INFO("model " << m.name);
  Summary s;
  // The two builds share the state layout; the multipliers p[] = the model's + alpha, beta.
  REQUIRE(m.m_nx == m.nx);
  REQUIRE(m.m_np == m.np + 2);
  REQUIRE(m.m_nc == m.nc);
  for (int i = 0; i < m.nx; ++i) REQUIRE(std::string(m.state_names[i]) == m.m_state_names[i]);
  for (int i = 0; i < m.np; ++i) REQUIRE(m.params[i] == m.m_params[i]);
  REQUIRE((m.position_constraints != nullptr) == (m.nposc > 0));
  // The table's independent speeds are exactly the model's kDofNames, and it has inputs for all.
  REQUIRE(static_cast<int>(c.speeds.size()) == m.ndof);
  for (int j = 0; j < m.ndof; ++j) REQUIRE(std::string(c.speeds[static_cast<std::size_t>(j)].name) == m.dof_names[j]);
  REQUIRE(static_cast<int>(c.inputs.size()) == m.nin);
  for (double e : c.inputs) REQUIRE(e != 0.0);
  const std::vector<double> pm = multiplier_params(m);

  const std::vector<double> nominal = nominal_state(c);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int attempt = 0; attempt < kAttempts && s.states < kStates; ++attempt) {
    // Perturb the whole nominal configuration (the guess), then draw the independent
    // coordinates and speeds; the other speeds are solved (their guess is irrelevant).
    std::vector<double> x = nominal;
    for (int i = 0; i < m.nq; ++i) x[static_cast<std::size_t>(i)] += 0.02 * unit(rng);
    for (const Range& r : c.coordinates) x[at(m, r.name)] = r.nominal + r.spread * unit(rng);
    for (const Range& r : c.speeds) x[at(m, r.name)] = r.nominal + r.spread * unit(rng);
    const AssemblyResult res = complete(c, x);
    if (!res.ok() || res.near_singular) {
      ++s.failures;
      UNSCOPED_INFO(m.name << ": trial " << attempt << " not assembled: " << res.message);
      continue;
    }
    ++s.states;
    const double r = residual(c, x);
    CHECK(r <= 1e-10 * std::max(1.0, largest_abs(x)));
    s.worst_residual = std::max(s.worst_residual, r);
    s.worst_relative = std::max(s.worst_relative, compare_rhs(c, x, pm));
  }
  CHECK(s.states == kStates);
  CHECK(s.failures <= kStates / 3);  // most trials assemble

  // One second of RK4 in each formulation from the nominal state.
  const double* u = c.inputs.empty() ? nullptr : c.inputs.data();
  auto fc = [&](double t, const double* xs, double* xd) { return m.rhs(t, xs, u, m.params, xd); };
  auto fm = [&](double t, const double* xs, double* xd) { return m.m_rhs(t, xs, u, pm.data(), xd); };
  std::vector<double> xc = nominal, xm = nominal;
  const double h = kStep / c.substeps;
  for (int k = 0; k < kSteps * c.substeps; ++k) {
    INFO("RK4 step " << k);
    REQUIRE(mbsc::runtime::rk4_step(fc, k * h, h, xc) == 0);
    REQUIRE(mbsc::runtime::rk4_step(fm, k * h, h, xm) == 0);
    for (std::size_t i = 0; i < xc.size(); ++i) {
      s.trajectory = std::max(s.trajectory, std::abs(xc[i] - xm[i]));
      s.travelled = std::max(s.travelled, std::abs(xc[i] - nominal[i]));
    }
  }
  CHECK(s.trajectory < 1e-7);
  s.drift = residual(c, xc);
  CHECK(s.travelled > 1e-2);  // the run is not trivial
  std::printf("%-31s states %2d (failed %d)  rhs rel. diff %.1e  residual %.1e  trajectory diff %.1e  drift %.1e  moved %.2f\n",
              m.name, s.states, s.failures, s.worst_relative, s.worst_residual, s.trajectory, s.drift, s.travelled);
  return s;
}

/// The table: every model in models/*.mbs. Nominal configurations are rough (assembly
/// polishes them); spreads keep each mechanism on one assembly branch and away from its
/// singular configurations (named per row).
std::vector<Case> shipped_models() {
  const double pi = std::acos(-1.0);
  std::vector<Case> cases;
  // Angles of the two rods; the bobs follow (constraints linear in them).
  cases.push_back({PAIR(double_pendulum), {}, {{"th1", 0.5, 1.0}, {"th2", -0.3, 1.0}}, {{"w1", 1.0, 2.0}, {"w2", -0.5, 2.0}}, {}, {}});
  // Thesis Ex 2.7: the upper-arm angles given; the lower arms meet at the payload
  // (guesses from tests/numeric/assembly_test.cpp). Motor currents and arm rates are the
  // independent speeds; the motor speeds follow through the gears.
  cases.push_back({PAIR(five_bar),
                   {{"linkage.left.phi", 1.0}, {"linkage.right.phi", 2.1}},
                   {{"linkage.left.theta", 2.0, 0.3}, {"linkage.right.theta", 1.1, 0.3}},
                   {{"motor_left.i", 0.2, 0.5},
                    {"motor_right.i", -0.1, 0.5},
                    {"linkage.left.dtheta", 0.3, 1.0},
                    {"linkage.right.dtheta", -0.2, 1.0}},
                   {2.0, -1.0},
                   {}});
  // Crank-rocker (Grashof); positions enter linearly, angles guessed.
  cases.push_back({PAIR(four_bar), {{"coupler.theta", 0.4}, {"rocker.theta", 1.9}}, {{"crank.theta", 1.2, 0.6}},
                   {{"crank.w", 1.0, 3.0}}, {}, {}});
  // Non-Grashof: the crank's toggle (coupler and rocker collinear, where the crank.w
  // partition of the complement is singular) is at |crank.theta| = 2.4068; crank kept in
  // [0.5, 1.5]. Upper branch: B near (0.80, 0.88).
  cases.push_back({PAIR(four_bar_toggle),
                   {{"crank.x", 0.16},
                    {"crank.y", 0.25},
                    {"coupler.x", 0.56},
                    {"coupler.y", 0.69},
                    {"coupler.theta", 0.67},
                    {"rocker.x", 0.90},
                    {"rocker.y", 0.44},
                    {"rocker.theta", 1.80}},
                   {{"crank.theta", 1.0, 0.5}},
                   {{"crank.w", 0.5, 2.0}},
                   {},
                   {}});
  // N = 3 parallelograms hanging below the ground line (flat, at 0 or -pi, is singular).
  {
    std::vector<std::pair<const char*, double>> guess;
    static const char* const cranks[][3] = {{"crank_0.x", "crank_0.y", "crank_0.theta"},
                                            {"crank_1.x", "crank_1.y", "crank_1.theta"},
                                            {"crank_2.x", "crank_2.y", "crank_2.theta"},
                                            {"crank_3.x", "crank_3.y", "crank_3.theta"}};
    static const char* const couplers[][2] = {{"coupler_1.x", "coupler_1.y"}, {"coupler_2.x", "coupler_2.y"},
                                              {"coupler_3.x", "coupler_3.y"}};
    for (int i = 0; i < 4; ++i) {
      guess.push_back({cranks[i][0], 0.5 * i + 0.08});
      guess.push_back({cranks[i][1], -0.13});
      guess.push_back({cranks[i][2], -1.0});
    }
    for (int j = 0; j < 3; ++j) {
      guess.push_back({couplers[j][0], 0.5 * j + 0.41});
      guess.push_back({couplers[j][1], -0.25});
    }
    cases.push_back({PAIR(parallelogram_chain), guess, {{"crank_0.theta", -1.0, 0.6}}, {{"crank_0.w", 0.5, 2.0}}, {}, {}});
  }
  // Thesis Ex 4.2, velocity constraints only: every coordinate is free data. The
  // complement solves R.w through cos(xi - theta), singular at theta = xi -+ pi/2
  // (-0.64, 2.50); theta kept in [-0.3, 0.9].
  cases.push_back({PAIR_VELOCITY_ONLY(ring_disc),
                   {},
                   {{"R.x", 0.0, 1.0},
                    {"R.y", 1.0, 0.1},
                    {"R.theta", 0.0, 3.0},
                    {"D.x", 0.2, 0.3},
                    {"D.y", 0.33, 0.1},
                    {"D.theta", 0.0, 3.0},
                    {"theta", 0.3, 0.6}},
                   {{"dtheta", 0.5, 1.0}, {"D.w", 1.0, 3.0}},
                   {},
                   {}});
  // The same at the library level: the contacts fix R.y and D.y (disc below the ring's
  // centre), the rest is free.
  cases.push_back({PAIR(ring_disc_joints),
                   {{"R.y", 1.0}, {"D.y", 0.33}},
                   {{"R.x", 0.0, 0.2}, {"R.theta", 0.0, 2.0}, {"D.x", 0.2, 0.2}, {"D.theta", 0.0, 2.0}},
                   {{"R.w", -1.0, 2.0}, {"D.w", 2.0, 3.0}},
                   {},
                   {}});
  // Slider to the right of the crank (rod angle -asin(r sin(theta) / l)).
  cases.push_back({PAIR(slider_crank),
                   {{"crank.x", 0.04}, {"crank.y", 0.06}, {"rod.x", 0.22}, {"rod.y", 0.06}, {"rod.theta", -0.43}, {"slider.x", 0.35}},
                   {{"crank.theta", 1.0, 1.0}},
                   {{"crank.w", 3.0, 10.0}},
                   {0.3, -1.0},
                   {}});
  // Thesis Ex 4.1 in three forms. Angles: singular at sin(theta) = 0, so theta in
  // [0.6, 1.4] and an azimuth rate that keeps it off the axis.
  cases.push_back({PAIR(spherical_pendulum_angles), {}, {{"theta", 1.0, 0.4}, {"phi", 0.5, 1.0}},
                   {{"dtheta", 0.3, 1.0}, {"dphi", 2.0, 1.0}}, {}, {}});
  // Cartesian: the complement divides by x (singular with the rod horizontal); the bob
  // hangs at x ~ 0.8 with little energy to climb.
  cases.push_back({PAIR(spherical_pendulum_cartesian), {{"bob.x", 0.8}}, {{"bob.y", 0.5, 0.2}, {"bob.z", 0.3, 0.2}},
                   {{"bob.v", 0.5, 1.0}, {"bob.w", -0.3, 1.0}}, {}, {}});
  // With the extra speed v2 = |r'|^2: a velocity constraint nonlinear in the speeds.
  cases.push_back({PAIR(spherical_pendulum_extra_speed), {{"bob.x", 0.8}}, {{"bob.y", 0.5, 0.2}, {"bob.z", 0.3, 0.2}},
                   {{"bob.v", 0.5, 1.0}, {"bob.w", -0.3, 1.0}}, {}, {"v2"}});
  // 3RRR: the platform pose is the data (inverse kinematics, one elbow branch per leg:
  // the thesis's elbows (2, sqrt3), (-5/2, sqrt3/2), (1/2, -3 sqrt3/2) at the origin).
  cases.push_back({PAIR(three_rrr),
                   {{"HA.proximal.x", 3.0},
                    {"HA.proximal.theta", 2.1},
                    {"HA.distal.x", 1.5},
                    {"HA.distal.y", 0.87},
                    {"HA.distal.theta", 1.0},
                    {"HB.proximal.x", -1.5},
                    {"HB.proximal.y", 2.6},
                    {"HB.proximal.theta", 4.2},
                    {"HB.distal.x", -1.5},
                    {"HB.distal.y", 0.87},
                    {"HB.distal.theta", 3.1},
                    {"HC.proximal.x", -1.5},
                    {"HC.proximal.y", -2.6},
                    {"HC.proximal.theta", 6.2},
                    {"HC.distal.x", 0.0},
                    {"HC.distal.y", -1.73},
                    {"HC.distal.theta", 5.2}},
                   {{"platform.x", 0.0, 0.3}, {"platform.y", 0.0, 0.3}, {"platform.theta", 0.0, 0.2}},
                   {{"HA.proximal.w", 0.3, 0.5}, {"HB.proximal.w", -0.2, 0.5}, {"HC.proximal.w", 0.1, 0.5}},
                   {0.1, -0.2, 0.3},
                   {}});
  // Planar 3R arm: the joint angles given; the rods' centres follow (guesses near
  // th = (0.5, 0.2, -0.3)).
  cases.push_back({PAIR(three_r_arm),
                   {{"link1.x", 0.22}, {"link1.y", 0.12}, {"link2.x", 0.6}, {"link2.y", 0.28}, {"link3.x", 0.9},
                    {"link3.y", 0.28}},
                   {{"link1.theta", 0.5, 0.3}, {"link2.theta", 0.2, 0.3}, {"link3.theta", -0.3, 0.3}},
                   {{"link1.w", 1.0, 1.0}, {"link2.w", -0.5, 1.0}, {"link3.w", 0.5, 1.0}},
                   {},
                   {}});
  // The same arm in joint angles: the joint angles given, the rods follow.
  cases.push_back({PAIR(three_r_arm_joint),
                   {{"link1.x", 0.22}, {"link1.y", 0.12}, {"link1.theta", 0.5}, {"link2.x", 0.6}, {"link2.y", 0.28},
                    {"link2.theta", 0.2}, {"link3.x", 0.9}, {"link3.y", 0.28}, {"link3.theta", -0.3}},
                   {{"q1", 0.5, 0.3}, {"q2", -0.3, 0.3}, {"q3", -0.5, 0.3}},
                   {{"q1_dot", 1.0, 1.0}, {"q2_dot", -0.5, 1.0}, {"q3_dot", 0.5, 1.0}},
                   {},
                   {}});
  // The tutorial's gantry crane (a force on the cart) and spatial arm (a torque at each
  // joint): joint coordinates place the bodies, so the guesses only start assembly.
  cases.push_back({PAIR(gantry_crane),
                   {{"load.x", 0.3}, {"load.y", -0.95}, {"load.theta", 0.3}},
                   {{"x", 0.2, 0.5}, {"theta", 0.3, 0.5}},
                   {{"v", 0.5, 1.0}, {"w", -0.3, 1.0}},
                   {1.5},
                   {}});
  cases.push_back({PAIR(spatial_arm),
                   {{"upper.z", 0.25}, {"fore.x", 0.15}, {"fore.z", 0.24}},
                   {{"q1", 0.3, 0.5}, {"q2", 2.6, 0.4}},
                   {{"w1", 0.5, 1.0}, {"w2", -0.3, 1.0}},
                   {0.3, -0.5},
                   {}});
  // Whitworth quick-return: the thesis's configuration at crank = pi/4 (guesses from
  // tests/numeric/shipped_planar_test.cpp).
  cases.push_back({PAIR(whitworth),
                   {{"slider.x", 0.7},
                    {"slider.y", 0.8},
                    {"rocker.theta", 1.3},
                    {"rocker.x", 0.1},
                    {"rocker.y", 0.3},
                    {"rod.theta", 3.4},
                    {"rod.x", 0.5},
                    {"rod.y", 0.7},
                    {"crank.y", 0.3}},
                   {{"crank.theta", pi / 4, 0.4}},
                   {{"crank.w", pi / 2, 2.0}},
                   {0.02},
                   {}});
  // The pendulum on a massless rod: the angle is the data, the bob follows.
  cases.push_back({PAIR(massless_rod_pendulum),
                   {{"bob.x", 0.54}, {"bob.y", -0.84}},
                   {{"rod.theta", -1.0, 1.0}},
                   {{"rod.w", 0.5, 2.0}},
                   {},
                   {}});
  // The Chaplygin sleigh: a velocity constraint only, every coordinate is free data and
  // the blade fixes the yaw rate.
  cases.push_back({PAIR_VELOCITY_ONLY(chaplygin_sleigh),
                   {},
                   {{"sleigh.x", 0.0, 1.0}, {"sleigh.y", 0.0, 1.0}, {"sleigh.theta", 0.0, 3.0}},
                   {{"sleigh.u", 0.5, 1.0}, {"sleigh.v", -0.3, 1.0}},
                   {},
                   {}});
  // The stiff spring-damper: both blocks slide on the x axis (y = 0 by the guides). Its
  // fast mode (-3.3e4 1/s) needs RK4 steps below 2.79 / 3.3e4 = 8.4e-5 s: four per kStep.
  cases.push_back({PAIR(stiff_spring_damper),
                   {},
                   {{"b1.x", 0.6, 0.05}, {"b2.x", 0.92, 0.02}},
                   {{"b1.u", 0.5, 0.5}, {"b2.u", -0.3, 0.5}},
                   {},
                   {},
                   4});
  // The free body (no constraints): the two forms are the same Newton-Euler equations;
  // any attitude and any motion. The quaternion is near unit (its norm is not a
  // constraint; the rhs is right for any e).
  const std::vector<Range> body_speeds{{"b.u", 0.5, 1.0}, {"b.v", 0.0, 1.0}, {"b.w", 3.0, 1.0},
                                       {"b.wx", 1.0, 1.0}, {"b.wy", -0.5, 1.0}, {"b.wz", 2.0, 1.0}};
  cases.push_back({PAIR_VELOCITY_ONLY(free_body_quaternion),
                   {{"b.e0", 1.0}},
                   {{"b.x", 0.0, 1.0}, {"b.z", 0.0, 1.0}, {"b.e1", 0.1, 0.05}, {"b.e2", -0.2, 0.05}, {"b.e3", 0.1, 0.05}},
                   body_speeds,
                   {},
                   {}});
  // Away from gimbal lock (theta = +-pi/2).
  cases.push_back({PAIR_VELOCITY_ONLY(free_body_euler),
                   {},
                   {{"b.phi", 0.3, 1.0}, {"b.theta", 0.2, 0.4}, {"b.psi", -0.2, 1.0}},
                   body_speeds,
                   {},
                   {}});
  // The heavy top (a spherical joint at its tip): any attitude near upright, the mass
  // centre placed by assembly; the independent speeds are the body-frame angular speeds.
  cases.push_back({PAIR(heavy_top),
                   {{"top.e0", 1.0}, {"top.z", 0.1}},
                   {{"top.e1", 0.1, 0.1}, {"top.e2", -0.1, 0.1}, {"top.e3", 0.2, 0.1}},
                   {{"top.wx", 1.0, 1.0}, {"top.wy", -0.5, 1.0}, {"top.wz", 30.0, 5.0}},
                   {},
                   {}});
  // Thesis Ex 2.2-2.4, the S-S-S-P mechanism: z1 and x2 given, p1 on the branch y1 > 0
  // (Ex 2.4's independent set needs y1 != 0), away from the rods in line (x2 < 3).
  cases.push_back({PAIR(sssp),
                   {{"tip1.x", 0.42}, {"tip1.y", 0.68}, {"theta", 1.61}, {"mid1.x", 0.21}, {"mid1.y", 0.34}, {"mid1.z", 0.3},
                    {"mid2.x", 1.31}, {"mid2.y", 0.34}, {"mid2.z", 0.3}},
                   {{"tip1.z", 0.6, 0.2}, {"slider.x", 2.2, 0.2}},
                   {{"tip1.w", 0.0, 1.0}, {"slider.u", 0.0, 1.0}},
                   {},
                   {}});
  // Thesis Ex 4.5, the 3-D slider-crank: the crank angle (quaternion e1 with e0 near 1)
  // given, the rod and slider placed by assembly; a crank torque (the friction is closed
  // in the generated code).
  cases.push_back({PAIR(slider_crank_3d),
                   {{"crank.e0", 1.0}, {"rod.x", 1.0}, {"rod.y", -0.5}, {"slider.e0", 1.0}, {"slider.x", 1.41},
                    {"slider.y", -0.5}},
                   {{"crank.e1", 0.3, 0.2}},
                   {{"crank.wx", 2.0, 2.0}},
                   {0.3},
                   {}});
  // The rolling disc (spatial `rolling` joint): near upright (the spin axis near space y),
  // the height placed by assembly; the independent speeds are the body-frame angular speeds.
  cases.push_back({PAIR(rolling_disc),
                   {{"disc.z", 0.3}},
                   {{"disc.x", 0.0, 1.0},
                    {"disc.y", 0.0, 1.0},
                    {"disc.e0", 0.7071, 0.1},
                    {"disc.e1", -0.7071, 0.1},
                    {"disc.e2", 0.0, 0.2},
                    {"disc.e3", 0.0, 0.2}},
                   {{"disc.wx", 0.0, 1.0}, {"disc.wy", 0.0, 1.0}, {"disc.wz", 5.0, 2.0}},
                   {},
                   {}});
  // The Whipple bicycle: near upright (guesses at the reference pose, where every body's
  // axes are the space axes), the rear contact, a lean, a steer and both wheels' angles
  // given (through quaternion entries), the rest placed by assembly; riding at about 5 m/s.
  cases.push_back({PAIR(whipple_bicycle),
                   {{"rear_wheel.z", -0.3},
                    {"rear_wheel.e0", 1.0},
                    {"rear_frame.x", 0.3},
                    {"rear_frame.z", -0.9},
                    {"rear_frame.e0", 1.0},
                    {"front_frame.x", 0.9},
                    {"front_frame.z", -0.7},
                    {"front_frame.e0", 1.0},
                    {"front_wheel.x", 1.02},
                    {"front_wheel.z", -0.35},
                    {"front_wheel.e0", 1.0}},
                   {{"rear_wheel.x", 0.0, 1.0},
                    {"rear_wheel.y", 0.0, 1.0},
                    {"rear_wheel.e2", 0.0, 0.5},
                    {"rear_frame.e1", 0.0, 0.05},
                    {"front_frame.e3", 0.0, 0.1},
                    {"front_wheel.e2", 0.0, 0.5}},
                   {{"rear_wheel.wy", -5.0 / 0.3, 3.0}, {"rear_frame.wx", 0.0, 1.0}, {"front_frame.wx", 0.0, 1.0}},
                   {},
                   {}});
  // The same bicycle in joint coordinates: the rear frame's yaw and lean, the steer and
  // both wheels' angles given, the reference points placed by assembly.
  cases.push_back({PAIR(whipple_bicycle_joints),
                   {{"rear_wheel.z", -0.3},
                    {"rear_frame.x", 0.3},
                    {"rear_frame.z", -0.9},
                    {"front_frame.x", 0.9},
                    {"front_frame.z", -0.7},
                    {"front_wheel.x", 1.02},
                    {"front_wheel.z", -0.35}},
                   {{"rear_wheel.x", 0.0, 1.0},
                    {"rear_wheel.y", 0.0, 1.0},
                    {"rear_frame.phi", 0.0, 1.0},
                    {"rear_frame.theta", 0.0, 0.1},
                    {"delta", 0.0, 0.2},
                    {"theta_R", 0.0, 1.0},
                    {"theta_F", 0.0, 1.0}},
                   {{"theta_R_dot", -5.0 / 0.3, 3.0}, {"rear_frame.wx", 0.0, 1.0}, {"delta_dot", 0.0, 1.0}},
                   {},
                   {}});
  // The thick disc on the incline: near its start attitude (leaning 0.25 rad), the
  // height placed by assembly.
  cases.push_back({PAIR(rolling_disc_incline),
                   {{"coin.z", 0.25}},
                   {{"coin.x", 0.0, 1.0},
                    {"coin.y", 0.0, 1.0},
                    {"coin.e0", 0.6104, 0.05},
                    {"coin.e1", -0.7858, 0.05},
                    {"coin.e2", 0.0612, 0.05},
                    {"coin.e3", 0.0788, 0.05}},
                   {{"coin.wx", 0.0, 1.0}, {"coin.wy", 0.0, 1.0}, {"coin.wz", 12.0, 2.0}},
                   {},
                   {}});
  // The sphere on the parabolic trough (the field on, t = 0.3): the contact point anywhere
  // across the trough's bottom, the centre placed by assembly.
  cases.push_back({PAIR(sphere_trough),
                   {{"ball.z", 0.01}},
                   {{"roll.xc", 0.0, 0.5},
                    {"roll.yc", 0.0, 0.3},
                    {"ball.e0", 0.9, 0.1},
                    {"ball.e1", 0.0, 0.3},
                    {"ball.e2", 0.0, 0.3},
                    {"ball.e3", 0.0, 0.3}},
                   {{"ball.wx", 0.0, 20.0}, {"ball.wy", 0.0, 20.0}, {"ball.wz", 0.0, 20.0}},
                   {},
                   {}});
  return cases;
}

}  // namespace

TEST_CASE("every shipped model: complement and multipliers agree (states 1e-9, trajectories 1e-7)",
          "[numeric][multipliers][shipped]") {
  const auto cases = shipped_models();
  // The table holds exactly the models shipped in models/ (a new model fails here until
  // it gets a row).
  std::vector<std::string> shipped, tabled;
  for (const auto& e : std::filesystem::directory_iterator(std::string(MBSC_SOURCE_DIR) + "/models"))
    if (e.path().extension() == ".mbs") shipped.push_back(e.path().stem().string());
  for (const Case& c : cases) tabled.push_back(c.pair.name);
  std::sort(shipped.begin(), shipped.end());
  std::sort(tabled.begin(), tabled.end());
  REQUIRE(shipped.size() == 30);
  REQUIRE(tabled == shipped);
  unsigned seed = 101;
  for (const Case& c : cases) {
    SECTION(c.pair.name) { check_case(c, seed); }
    ++seed;
  }
}

// The status contract of every generated rhs (both formulations): a NaN or infinite
// input (one parameter, one state entry) gives 2 (non-finite), never 1 (singular) and
// never 0 with a NaN in the output; a regular consistent state with finite inputs gives 0.
TEST_CASE("every shipped model: non-finite inputs give status 2, never 1", "[numeric][status][shipped]") {
  for (const Case& c : shipped_models()) {
    const Pair& m = c.pair;
    INFO("model " << m.name);
    std::vector<double> x0 = nominal_state(c);
    const double* u = c.inputs.empty() ? nullptr : c.inputs.data();
    struct Build {
      Fn rhs;
      int nx;
      std::vector<double> p;
    };
    for (const Build& b : {Build{m.rhs, m.nx, std::vector<double>(m.params, m.params + m.np)},
                           Build{m.m_rhs, m.m_nx, multiplier_params(m)}}) {
      std::vector<double> out(static_cast<std::size_t>(b.nx));
      REQUIRE(b.rhs(0.0, x0.data(), u, b.p.data(), out.data()) == 0);
      auto expect_not_finite = [&](const std::vector<double>& x, const std::vector<double>& p, const std::string& what) {
        INFO(what);
        std::fill(out.begin(), out.end(), 0.0);
        const int status = b.rhs(0.0, x.data(), u, p.data(), out.data());
        bool finite = true;
        for (double v : out) finite = finite && std::isfinite(v);
        // 0 only when the value does not reach the outputs (a parameter the rhs does not read).
        CHECK((status == 2 || (status == 0 && finite)));
      };
      for (std::size_t k = 0; k < b.p.size(); ++k)
        for (double bad : {std::nan(""), HUGE_VAL}) {
          std::vector<double> p = b.p;
          p[k] = bad;
          expect_not_finite(x0, p, "p[" + std::to_string(k) + "] = " + std::to_string(bad));
        }
      for (std::size_t i = 0; i < x0.size(); ++i) {
        std::vector<double> x = x0;
        x[i] = std::nan("");
        expect_not_finite(x, b.p, "x[" + std::to_string(i) + "] = nan");
      }
    }
  }
}
