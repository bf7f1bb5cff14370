// SPDX-License-Identifier: GPL-2.0-or-later
// Inverse dynamics (include/mbsc/runtime/inverse_dynamics.hpp) on the two "SI" runs of
// thesis §5.3: the Whitworth crank turning at pi/2 rad/s from 45 degrees, and the 3RRR
// platform following x = -sin(pi t/2), y = sin(pi t/4), psi = (pi/6) sin^4(pi t/4), 16 s
// each. Checked against
//   * the reduced equations M z' = h(u) of the generated mass_matrix / forcing (h is
//     affine in u): the same inputs from an independent route;
//   * the multipliers formulation: the same inputs, and reactions that balance;
//   * a forward run: the tabulated inputs, interpolated (cubic) and fed to RK4 from the
//     inverse's first state, reproduce the prescribed motion to 1e-6 over the 16 s.
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "mbsc/runtime/inverse_dynamics.hpp"
#include "mbsc/runtime/model_table.hpp"
#include "mbsc/runtime/rk4.hpp"
#include "test_support.hpp"
#include "three_rrr/three_rrr.hpp"
#include "three_rrr_mult/three_rrr_mult.hpp"
#include "whitworth/whitworth.hpp"
#include "whitworth_mult/whitworth_mult.hpp"

using mbsc::runtime::InverseDynamics;
using mbsc::runtime::InverseSample;
using mbsc::runtime::ModelTable;
using mbsc::runtime::Prescription;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A run of the inverse on an even grid: states and inputs at t_k = k dt.
struct Run {
  double dt = 0.0;
  std::vector<InverseSample> samples;
};

Run run_inverse(InverseDynamics& inv, std::vector<double> x, double t_end, double dt) {
  Run r;
  r.dt = dt;
  const int n = static_cast<int>(std::lround(t_end / dt));
  for (int k = 0; k <= n; ++k) {
    InverseSample s;
    const bool ok = inv.solve(k * dt, x, s);
    INFO("t = " << k * dt << ": " << s.message);
    REQUIRE(ok);
    r.samples.push_back(s);
  }
  return r;
}

// Cubic Lagrange interpolation of input i through the four grid points around t.
double input_at(const Run& r, int i, double t) {
  const int n = static_cast<int>(r.samples.size());
  int k = static_cast<int>(std::floor(t / r.dt)) - 1;
  k = std::max(0, std::min(k, n - 4));
  double sum = 0.0;
  for (int a = 0; a < 4; ++a) {
    double w = 1.0;
    for (int b = 0; b < 4; ++b)
      if (b != a) w *= (t - (k + b) * r.dt) / ((a - b) * r.dt);
    sum += w * r.samples[static_cast<std::size_t>(k + a)].inputs[static_cast<std::size_t>(i)];
  }
  return sum;
}

// u from the reduced equations: M z' = h0 + H u (h affine in u), with z' read from the
// inverse's own accelerations. Only when the prescribed coordinates are not the
// independent set does z' come from elsewhere than the prescription: either way this is
// a different computation from the runtime's (which never forms M or h).
std::vector<double> inputs_from_reduced_equations(const ModelTable& m, const InverseSample& s, const double* p) {
  const std::size_t nd = static_cast<std::size_t>(m.ndof), nin = static_cast<std::size_t>(m.nin);
  std::vector<double> M(nd * nd), h0(nd), hk(nd), H(nd * nin), zdot(nd), u(nin, 0.0);
  for (std::size_t i = 0; i < nd; ++i)
    zdot[i] = s.xdot[static_cast<std::size_t>(m.nq + ModelTable::find(m.state_names + m.nq, m.nu, m.dof_names[i]))];
  REQUIRE(m.mass_matrix(s.t, s.x.data(), u.data(), p, M.data()) == 0);
  REQUIRE(m.forcing(s.t, s.x.data(), u.data(), p, h0.data()) == 0);
  for (std::size_t k = 0; k < nin; ++k) {
    std::vector<double> e(nin, 0.0);
    e[k] = 1.0;
    REQUIRE(m.forcing(s.t, s.x.data(), e.data(), p, hk.data()) == 0);
    for (std::size_t i = 0; i < nd; ++i) H[i * nin + k] = hk[i] - h0[i];
  }
  std::vector<double> r(nd);
  for (std::size_t i = 0; i < nd; ++i) {
    r[i] = -h0[i];
    for (std::size_t j = 0; j < nd; ++j) r[i] += M[i * nd + j] * zdot[j];
  }
  return mbsc::runtime::solve_least_squares(H, r, static_cast<int>(nd), static_cast<int>(nin)).x;
}

// Forward RK4 (step h) with the interpolated inputs, restarted from the inverse's state at
// the start of every window (one window: the whole run from its first state); returns the
// largest deviation of the prescribed coordinates from their motion.
double round_trip_error(const ModelTable& m, const double* p, const Run& r, const std::vector<Prescription>& pres, double h,
                        double window) {
  std::vector<double> u(static_cast<std::size_t>(m.nin));
  auto f = [&](double t, const double* xs, double* xdot) {
    for (int i = 0; i < m.nin; ++i) u[static_cast<std::size_t>(i)] = input_at(r, i, t);
    return m.rhs(t, xs, u.data(), p, xdot);
  };
  const double t_end = r.dt * static_cast<double>(r.samples.size() - 1);
  double worst = 0.0;
  for (double t0 = 0.0; t0 < t_end - 1e-9; t0 += window) {
    const double t1 = std::min(t_end, t0 + window);
    std::vector<double> x = r.samples[static_cast<std::size_t>(std::lround(t0 / r.dt))].x;
    const int status = mbsc::runtime::rk4_integrate(f, t0, t1, static_cast<int>(std::lround((t1 - t0) / h)), x,
                                                    [&](double t, const std::vector<double>& xs) {
                                                      for (const auto& pr : pres) {
                                                        double q, qd, qdd;
                                                        pr.motion(t, q, qd, qdd);
                                                        worst = std::max(worst, std::fabs(xs[static_cast<std::size_t>(pr.coord)] - q));
                                                      }
                                                    });
    REQUIRE(status == 0);
  }
  return worst;
}

// The state at the end of a forward RK4 run over the whole table from its first state,
// with `offset` added to input 0.
std::vector<double> forward_end(const ModelTable& m, const double* p, const Run& r, double h, double offset) {
  std::vector<double> u(static_cast<std::size_t>(m.nin)), x = r.samples.front().x;
  auto f = [&](double t, const double* xs, double* xdot) {
    for (int i = 0; i < m.nin; ++i) u[static_cast<std::size_t>(i)] = input_at(r, i, t) + (i == 0 ? offset : 0.0);
    return m.rhs(t, xs, u.data(), p, xdot);
  };
  const double t_end = r.dt * static_cast<double>(r.samples.size() - 1);
  REQUIRE(mbsc::runtime::rk4_integrate(f, 0.0, t_end, static_cast<int>(std::lround(t_end / h)), x, [](double, const std::vector<double>&) {}) == 0);
  return x;
}

int state_index(const ModelTable& m, const char* name) { return mbsc_test::index_of(m.state_names, m.nx, name); }

std::vector<double> whitworth_guess(const ModelTable& m) {
  // The thesis's configuration, rounded (tests/numeric/shipped_planar_test.cpp).
  std::vector<double> x(static_cast<std::size_t>(m.nx), 0.0);
  const std::vector<std::pair<const char*, double>> guess = {{"slider.x", 0.7}, {"slider.y", 0.8}, {"rocker.theta", 1.3},
                                                             {"rocker.x", 0.1}, {"rocker.y", 0.3}, {"rod.theta", 3.4},
                                                             {"rod.x", 0.5},    {"rod.y", 0.7},    {"crank.y", 0.3}};
  for (const auto& [n, v] : guess) x[static_cast<std::size_t>(state_index(m, n))] = v;
  return x;
}

std::vector<Prescription> whitworth_motion(const ModelTable& m) {
  return {{state_index(m, "crank.theta"), [](double t, double& q, double& qd, double& qdd) {
             q = kPi / 4 + kPi / 2 * t;
             qd = kPi / 2;
             qdd = 0.0;
           }}};
}

std::vector<double> three_rrr_guess(const ModelTable& m) {
  std::vector<double> x(static_cast<std::size_t>(m.nx), 0.0);
  const double prox[3] = {2.0, 3.8, 6.0}, dist[3] = {1.0, 3.1, 5.2};
  const double bx[3] = {3.0, -1.5, -1.5}, by[3] = {0.0, 1.5 * std::sqrt(3.0), -1.5 * std::sqrt(3.0)};
  const char* legs[3] = {"HA", "HB", "HC"};
  for (int k = 0; k < 3; ++k) {
    const std::string L = legs[k];
    x[static_cast<std::size_t>(state_index(m, (L + ".proximal.theta").c_str()))] = prox[k];
    x[static_cast<std::size_t>(state_index(m, (L + ".proximal.x").c_str()))] = bx[k];
    x[static_cast<std::size_t>(state_index(m, (L + ".proximal.y").c_str()))] = by[k];
    x[static_cast<std::size_t>(state_index(m, (L + ".distal.theta").c_str()))] = dist[k];
  }
  return x;
}

std::vector<Prescription> three_rrr_motion(const ModelTable& m) {
  const double w2 = kPi / 2, w4 = kPi / 4;
  return {{state_index(m, "platform.x"),
           [=](double t, double& q, double& qd, double& qdd) {
             q = -std::sin(w2 * t);
             qd = -w2 * std::cos(w2 * t);
             qdd = w2 * w2 * std::sin(w2 * t);
           }},
          {state_index(m, "platform.y"),
           [=](double t, double& q, double& qd, double& qdd) {
             q = std::sin(w4 * t);
             qd = w4 * std::cos(w4 * t);
             qdd = -w4 * w4 * std::sin(w4 * t);
           }},
          {state_index(m, "platform.theta"), [=](double t, double& q, double& qd, double& qdd) {
             // (pi/6) s^4 with s = sin(w4 t): q' = (pi/6) 4 s^3 c w4, q'' = (pi/6) w4^2 (12 s^2 c^2 - 4 s^4).
             const double s = std::sin(w4 * t), c = std::cos(w4 * t), a = kPi / 6;
             q = a * s * s * s * s;
             qd = a * 4 * s * s * s * c * w4;
             qdd = a * w4 * w4 * (12 * s * s * c * c - 4 * s * s * s * s);
           }}};
}

// The generated inverse_dynamics at the sample's state, with z' read from its rates.
std::vector<double> generated_inverse(const ModelTable& m, const InverseSample& s, const double* p) {
  std::vector<double> zdot(static_cast<std::size_t>(m.ndof)), u(static_cast<std::size_t>(m.nin));
  for (int i = 0; i < m.ndof; ++i)
    zdot[static_cast<std::size_t>(i)] = s.xdot[static_cast<std::size_t>(m.nq + ModelTable::find(m.state_names + m.nq, m.nu, m.dof_names[i]))];
  REQUIRE(m.inverse_dynamics(s.t, s.x.data(), zdot.data(), p, u.data()) == 0);
  return u;
}

double largest_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double w = 0.0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) w = std::max(w, std::fabs(a[i] - b[i]));
  return w;
}

}  // namespace

TEST_CASE("inverse dynamics: Whitworth crank at pi/2 rad/s (thesis SI run)", "[numeric][inverse]") {
  namespace W = mbsc_gen::whitworth;
  const ModelTable m = MBSC_MODEL_TABLE(W);
  const ModelTable mm = MBSC_MODEL_TABLE_MULTIPLIERS(mbsc_gen::whitworth_mult);
  std::vector<double> pm(W::kParamDefaults, W::kParamDefaults + W::kNp);
  pm.push_back(10.0);
  pm.push_back(10.0);
  const auto motion = whitworth_motion(m);
  InverseDynamics inv(m, motion, {0}, std::vector<double>(W::kParamDefaults, W::kParamDefaults + W::kNp));
  InverseDynamics inv_mult(mm, whitworth_motion(mm), {0}, pm);
  REQUIRE(inv.setup_error().empty());
  const Run r = run_inverse(inv, whitworth_guess(m), 16.0, 2e-3);
  const Run rm = run_inverse(inv_mult, whitworth_guess(mm), 16.0, 2e-3);

  // The thesis's initial configuration: slider at (0.8, 0.8).
  CHECK(r.samples[0].x[static_cast<std::size_t>(state_index(m, "slider.x"))] == Approx(0.8).margin(1e-9));
  const std::size_t slider_u = static_cast<std::size_t>(state_index(m, "slider.u"));
  double u_min = 1e300, u_max = -1e300, v_min = 1e300, v_max = -1e300, worst_reduced = 0.0, worst_mult = 0.0,
         worst_generated = 0.0, peak = 0.0, v_at_peak = 0.0;
  for (std::size_t k = 0; k < r.samples.size(); ++k) {
    const InverseSample& s = r.samples[k];
    // rhs(x, u) gives back the prescribed acceleration (the solver checks; so does this).
    CHECK(s.acceleration_residual < 1e-9);
    worst_reduced = std::max(worst_reduced, largest_difference(inputs_from_reduced_equations(m, s, W::kParamDefaults), s.inputs));
    worst_mult = std::max(worst_mult, largest_difference(rm.samples[k].inputs, s.inputs));
    worst_generated = std::max(worst_generated, largest_difference(generated_inverse(m, s, W::kParamDefaults), s.inputs));
    worst_generated = std::max(worst_generated, largest_difference(generated_inverse(mm, rm.samples[k], pm.data()), s.inputs));
    CHECK(largest_difference(rm.samples[k].x, s.x) < 1e-9);
    if (std::fabs(s.inputs[0]) > peak) peak = std::fabs(s.inputs[0]), v_at_peak = s.x[slider_u];
    u_min = std::min(u_min, s.inputs[0]);
    u_max = std::max(u_max, s.inputs[0]);
    v_min = std::min(v_min, s.x[slider_u]);
    v_max = std::max(v_max, s.x[slider_u]);
  }
  CHECK(worst_reduced < 1e-9);
  CHECK(worst_mult < 1e-9);
  CHECK(worst_generated < 1e-9);  // the generated inverse_dynamics, both forms
  // Quick return: the slider comes back faster than it goes (|v| larger one way), and the
  // torque has peaks of both signs (the thesis's Fig 5.13 shows the peaks at the return).
  INFO("slider velocity in [" << v_min << ", " << v_max << "], u1 in [" << u_min << ", " << u_max << "]");
  CHECK(std::max(std::fabs(v_min), v_max) > 1.5 * std::min(std::fabs(v_min), v_max));
  CHECK(u_min < 0.0);
  CHECK(u_max > 0.0);
  // ... during the fast stroke (slider moving back, v > 0 here), the torque peaks.
  CHECK(v_at_peak > 0.5 * v_max);
  // The crank turns at a constant rate; the motion is periodic with the crank's period 4 s.
  const InverseSample& a = r.samples[0];
  const InverseSample& b = r.samples[2000];  // t = 4
  CHECK(std::fabs(a.inputs[0] - b.inputs[0]) < 1e-9 * std::max(1.0, std::fabs(u_max)));

  // Multipliers form: the reactions A^T lambda balance the dynamics. Along the crank's own
  // speed the equation is I4 crank.w' = u1 + reaction; crank.w' = 0 here.
  const std::size_t crank_w = static_cast<std::size_t>(state_index(mm, "crank.w") - mm.nq);
  for (std::size_t k = 0; k < rm.samples.size(); k += 100) {
    REQUIRE(rm.samples[k].reactions.size() == static_cast<std::size_t>(mm.nu));
    CHECK(std::fabs(rm.samples[k].inputs[0] + rm.samples[k].reactions[crank_w]) < 1e-9 * std::max(1.0, std::fabs(u_max)));
  }

  // Round trip.
  const double err = round_trip_error(m, W::kParamDefaults, r, motion, 1e-3, 16.0);
  INFO("round trip: largest crank angle error " << err);
  CHECK(err < 1e-6);
}

TEST_CASE("inverse dynamics: 3RRR platform trajectory (thesis SI run)", "[numeric][inverse]") {
  namespace R = mbsc_gen::three_rrr;
  const ModelTable m = MBSC_MODEL_TABLE(R);
  const auto motion = three_rrr_motion(m);
  InverseDynamics inv(m, motion, {0, 1, 2}, std::vector<double>(R::kParamDefaults, R::kParamDefaults + R::kNp));
  REQUIRE(inv.setup_error().empty());
  const double dtg = 2e-3;
  const Run r = run_inverse(inv, three_rrr_guess(m), 16.0, dtg);
  // The thesis's elbows at t = 0: HA's at (2, sqrt 3).
  const double th = r.samples[0].x[static_cast<std::size_t>(state_index(m, "HA.proximal.theta"))];
  CHECK(3.0 + 2.0 * std::cos(th) == Approx(2.0).margin(1e-9));
  CHECK(2.0 * std::sin(th) == Approx(std::sqrt(3.0)).margin(1e-9));
  double worst_reduced = 0.0, worst_generated = 0.0, u_scale = 0.0;
  for (const auto& s : r.samples) {
    worst_generated = std::max(worst_generated, largest_difference(generated_inverse(m, s, R::kParamDefaults), s.inputs));
    CHECK(s.acceleration_residual < 1e-9);
    for (double u : s.inputs) u_scale = std::max(u_scale, std::fabs(u));
    // Here the prescribed coordinates are not the independent set (the proximal angles):
    // z' comes from the rhs at the solved inputs.
    worst_reduced = std::max(worst_reduced, largest_difference(inputs_from_reduced_equations(m, s, R::kParamDefaults), s.inputs));
  }
  INFO("largest |u| " << u_scale);
  CHECK(u_scale > 0.1);  // the platform's accelerations need torque
  CHECK(worst_reduced < 1e-8 * std::max(1.0, u_scale));
  CHECK(worst_generated < 1e-8 * std::max(1.0, u_scale));

  // Multipliers form on a coarser grid: the same inputs.
  const ModelTable mm = MBSC_MODEL_TABLE_MULTIPLIERS(mbsc_gen::three_rrr_mult);
  std::vector<double> pm(R::kParamDefaults, R::kParamDefaults + R::kNp);
  pm.push_back(10.0);
  pm.push_back(10.0);
  InverseDynamics inv_mult(mm, three_rrr_motion(mm), {0, 1, 2}, pm);
  const Run rm = run_inverse(inv_mult, three_rrr_guess(mm), 16.0, 0.4);
  for (std::size_t k = 0; k < rm.samples.size(); ++k) {
    CHECK(largest_difference(rm.samples[k].inputs, r.samples[static_cast<std::size_t>(std::lround(k * 0.4 / dtg))].inputs) < 1e-8 * std::max(1.0, u_scale));
    CHECK(largest_difference(generated_inverse(mm, rm.samples[k], pm.data()), rm.samples[k].inputs) < 1e-8 * std::max(1.0, u_scale));
  }

  const double err = round_trip_error(m, R::kParamDefaults, r, motion, 1e-3, 8.0);
  INFO("round trip: largest platform pose error " << err);
  CHECK(err < 1e-6);

  // Why the forward run restarts at t = 8: along this trajectory the open-loop mechanism
  // amplifies any perturbation (rounding included) about 1e10-fold over 16 s, so no
  // double-precision run from t = 0 stays within 1e-6 to the end. A torque error of 1e-10
  // N m, which would move a stable double integrator by ~1e-8 in 16 s, moves the platform
  // by far more.
  const std::vector<double> a = forward_end(m, R::kParamDefaults, r, 1e-3, 0.0);
  const std::vector<double> b = forward_end(m, R::kParamDefaults, r, 1e-3, 1e-10);
  double spread = 0.0;
  for (const auto& pr : motion) spread = std::max(spread, std::fabs(a[static_cast<std::size_t>(pr.coord)] - b[static_cast<std::size_t>(pr.coord)]));
  INFO("a 1e-10 torque offset moves the platform by " << spread << " at t = 16");
  CHECK(spread > 1e-5);
}

TEST_CASE("inverse dynamics: clear errors for a bad set-up", "[numeric][inverse]") {
  namespace R = mbsc_gen::three_rrr;
  const ModelTable m = MBSC_MODEL_TABLE(R);
  const std::vector<double> p(R::kParamDefaults, R::kParamDefaults + R::kNp);
  auto motion = three_rrr_motion(m);
  // Too few prescriptions.
  InverseDynamics two(m, {motion[0], motion[1]}, {0, 1, 2}, p);
  CHECK_THAT(two.setup_error(), Catch::Contains("3 degree(s) of freedom but 2"));
  // One input cannot drive three coordinates: the solve says which inputs fall short.
  InverseDynamics one(m, motion, {0}, p);
  REQUIRE(one.setup_error().empty());
  std::vector<double> x = three_rrr_guess(m);
  InverseSample s;
  CHECK_FALSE(one.solve(1.0, x, s));
  CHECK_THAT(s.message, Catch::Contains("cannot produce the prescribed accelerations"));
  // A coordinate prescribed twice.
  InverseDynamics twice(m, {motion[0], motion[0], motion[1]}, {0, 1, 2}, p);
  CHECK_THAT(twice.setup_error(), Catch::Contains("prescribed twice"));
  // Coordinates that do not determine the pose: a base link's own position (fixed by its
  // pivot) instead of the platform's angle.
  std::vector<Prescription> bad = {motion[0], motion[1],
                                   {state_index(m, "HA.proximal.x"), [](double, double& q, double& qd, double& qdd) {
                                      q = 3.0;
                                      qd = qdd = 0.0;
                                    }}};
  InverseDynamics pose(m, bad, {0, 1, 2}, p);
  x = three_rrr_guess(m);
  CHECK_FALSE(pose.solve(0.0, x, s));
  CHECK_THAT(s.message, Catch::Contains("do not determine"));
}
