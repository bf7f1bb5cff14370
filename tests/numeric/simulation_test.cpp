// SPDX-License-Identifier: GPL-2.0-or-later
// The runtime's projection (include/mbsc/runtime/projection.hpp) and simulation loop
// (simulate.hpp) on the four-bar that runs through its toggle positions
// (models/four_bar_toggle.mbs, three declared independent sets):
//   - the minimum-norm solve against a closed form, with a redundant row;
//   - projection of a perturbed state: residuals to rounding, the position correction
//     orthogonal to the mechanism's motion (the shortest way back);
//   - the loop's bookkeeping: output times, failures (samples before it delivered, t and
//     the cause named), a non-finite initial value named, an unknown integrator;
//   - the toggles: the complement form with re-selection and projection follows the
//     multipliers form (no independent set, so no toggle problem) along the physical
//     branch, residuals below 1e-8, switches reported;
//   - Baumgarte: the multipliers form without stabilisation (alpha = beta = 0) drifts
//     off the constraints, with the default gains it stays bounded.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "four_bar_toggle/four_bar_toggle.hpp"
#include "four_bar_toggle_mult/four_bar_toggle_mult.hpp"
#include "mbsc/runtime/assemble.hpp"
#include "mbsc/runtime/simulate.hpp"
#include "test_support.hpp"

namespace F = mbsc_gen::four_bar_toggle;
namespace FM = mbsc_gen::four_bar_toggle_mult;
namespace rt = mbsc::runtime;
using mbsc_test::index_of;

namespace {

std::size_t ix(const char* name) { return static_cast<std::size_t>(index_of(F::kStateNames, F::kNx, name)); }
double p_of(const char* name) { return F::kParamDefaults[index_of(F::kParamNames, F::kNp, name)]; }

/// A consistent state: crank at theta turning at w, pin B on the `side` branch of the
/// two circles about A and Q (closed form), speeds by assembly.
std::vector<double> state_at(double theta, double w, int side) {
  const double a = p_of("a"), b = p_of("b"), c = p_of("c"), d = p_of("d");
  const double ax = a * std::cos(theta), ay = a * std::sin(theta);
  const double ex = d - ax, ey = -ay, dist = std::hypot(ex, ey);
  const double along = (dist * dist + b * b - c * c) / (2 * dist), across = std::sqrt(std::max(0.0, b * b - along * along));
  const double bx = ax + (along * ex - side * across * ey) / dist, by = ay + (along * ey + side * across * ex) / dist;
  std::vector<double> x(F::kNx, 0.0);
  x[ix("crank.theta")] = theta;
  x[ix("crank.x")] = ax / 2;
  x[ix("crank.y")] = ay / 2;
  x[ix("coupler.theta")] = std::atan2(by - ay, bx - ax);
  x[ix("coupler.x")] = (ax + bx) / 2;
  x[ix("coupler.y")] = (ay + by) / 2;
  x[ix("rocker.theta")] = std::atan2(by, bx - d);
  x[ix("rocker.x")] = (d + bx) / 2;
  x[ix("rocker.y")] = by / 2;
  x[ix("crank.w")] = w;
  std::vector<bool> gq(F::kNq, false), gu(F::kNu, false);
  gq[ix("crank.theta")] = true;
  gu[ix("crank.w") - F::kNq] = true;
  const auto r = rt::assemble(MBSC_TEST_ASSEMBLY_MODEL(F), 0.0, x, gq, gu, nullptr, F::kParamDefaults);
  INFO(r.message);
  REQUIRE(r.ok());
  return x;
}

std::vector<double> params_without_gravity() {
  std::vector<double> p(F::kParamDefaults, F::kParamDefaults + F::kNp);
  p[static_cast<std::size_t>(index_of(F::kParamNames, F::kNp, "g"))] = 0.0;
  return p;
}

/// The multipliers twin's parameters: the same, then the Baumgarte gains.
std::vector<double> mult_params(std::vector<double> p, double alpha, double beta) {
  p.push_back(alpha);
  p.push_back(beta);
  REQUIRE(static_cast<int>(p.size()) == FM::kNp);
  return p;
}

struct Trajectory {
  std::vector<double> t, crank, crank_w;
};

rt::Observer record(Trajectory& tr) {
  return [&tr](double t, const std::vector<double>& x) {
    tr.t.push_back(t);
    tr.crank.push_back(x[ix("crank.theta")]);
    tr.crank_w.push_back(x[ix("crank.w")]);
  };
}

}  // namespace

TEST_CASE("projection: minimum-norm solve with a redundant row", "[numeric][simulate][projection]") {
  // x1 + x2 = 2 (twice), 2 x3 = 4: the shortest solution is (1, 1, 2).
  const std::vector<double> A{1, 1, 0, 1, 1, 0, 0, 0, 2}, r{2, 2, 4};
  std::vector<double> dx;
  CHECK(rt::minimum_norm_solve(A, r, 3, 3, dx) == 2);
  CHECK(dx[0] == Approx(1.0));
  CHECK(dx[1] == Approx(1.0));
  CHECK(dx[2] == Approx(2.0));
  // Underdetermined, full rank: x1 + 2 x2 + 2 x3 = 9 -> (1, 2, 2).
  CHECK(rt::minimum_norm_solve({1, 2, 2}, {9}, 1, 3, dx) == 1);
  CHECK(dx[0] == Approx(1.0));
  CHECK(dx[1] == Approx(2.0));
  CHECK(dx[2] == Approx(2.0));
}

TEST_CASE("projection: a perturbed four-bar state goes back the shortest way", "[numeric][simulate][projection]") {
  const auto model = MBSC_MODEL_TABLE(F);
  std::mt19937 gen(11);
  std::normal_distribution<double> noise(0.0, 1e-4);
  for (int trial = 0; trial < 10; ++trial) {
    const auto exact = state_at(-1.0 + 0.2 * trial, 1.5, trial % 2 ? 1 : -1);
    auto x = exact;
    for (double& e : x) e += noise(gen);
    const auto perturbed = x;
    const auto rep = rt::project(model, 0.0, x, nullptr, F::kParamDefaults);
    INFO(rep.message << ": position residual " << rep.position_before << " -> " << rep.position_after << ", velocity "
                     << rep.velocity_before << " -> " << rep.velocity_after << " in " << rep.iterations << " steps");
    REQUIRE(rep.ok());
    CHECK(rep.position_before > 1e-6);
    CHECK(rep.position_after < 1e-13);
    CHECK(rep.velocity_after < 1e-12);
    CHECK(rep.position_rank == F::kNposc);
    // The mechanism's motion direction at the exact state (its consistent speeds: the
    // constraints are scleronomic) spans the null space of J; the position correction has
    // no component along it, to first order in the perturbation.
    double dot = 0.0, n_dir = 0.0, n_dq = 0.0;
    for (int i = 0; i < F::kNq; ++i) {
      const double v = exact[static_cast<std::size_t>(F::kNq + i)];
      const double dq = x[static_cast<std::size_t>(i)] - perturbed[static_cast<std::size_t>(i)];
      dot += v * dq;
      n_dir += v * v;
      n_dq += dq * dq;
    }
    CHECK(std::abs(dot) < 1e-2 * std::sqrt(n_dir * n_dq));
    // Back on the same branch, close to where it started.
    CHECK(std::abs(x[ix("crank.theta")] - exact[ix("crank.theta")]) < 1e-3);
  }
  // Nothing to do for a consistent state.
  auto y = state_at(0.4, 1.0, 1);
  const auto before = y;
  const auto rep = rt::project(model, 0.0, y, nullptr, F::kParamDefaults);
  CHECK(rep.iterations == 0);
  for (std::size_t i = 0; i < y.size(); ++i) CHECK(std::abs(y[i] - before[i]) < 1e-13);
}

TEST_CASE("simulate: output times, failures with their samples, bad setups", "[numeric][simulate]") {
  const auto model = MBSC_MODEL_TABLE(F);
  const auto x0 = state_at(0.3, 2.0, 1);
  rt::StepperOptions so;
  so.rtol = 1e-8;
  so.atol = 1e-10;
  rt::SimulationOptions opt;
  opt.t_end = 1.05;
  opt.dt_out = 0.1;
  for (const auto& name : rt::stepper_names()) {
    so.h = name == "rk4" ? 1e-3 : 0.0;
    Trajectory tr;
    const auto r = rt::simulate(model, name, so, opt, x0, {}, F::kParamDefaults, record(tr));
    INFO(name << ": " << r.message);
    REQUIRE(r.ok());
    REQUIRE(tr.t.size() == 12u);  // 0, 0.1, ..., 1.0, and t_end
    for (std::size_t k = 0; k + 1 < tr.t.size(); ++k) CHECK(tr.t[k] == Approx(0.1 * static_cast<double>(k)).margin(1e-15));
    CHECK(tr.t.back() == 1.05);
    CHECK(r.t == 1.05);
    CHECK(r.samples == 12);
    CHECK(r.rhs_evals >= r.stats.accepted);
    CHECK(r.energy_defined);
    CHECK(r.energy_relative_drift < 1e-6);
    // The last sample is the final state.
    CHECK(tr.crank.back() == r.x[ix("crank.theta")]);
  }

  // A model whose rhs fails (a singular solve) from t = 0.55 on: every sample before is
  // delivered, the status and message say what and when.
  auto failing = model;
  failing.npartitions = 1;
  failing.rhs = [](double t, const double* x, const double* u, const double* p, double* out) {
    return t > 0.55 ? 1 : F::rhs(t, x, u, p, out);
  };
  for (const auto& name : rt::stepper_names()) {
    so.h = name == "rk4" ? 1e-2 : 0.0;
    Trajectory tr;
    const auto r = rt::simulate(failing, name, so, opt, x0, {}, F::kParamDefaults, record(tr));
    INFO(name << ": " << r.message);
    CHECK(r.status == rt::SimulationResult::Status::RhsFailed);
    CHECK(r.message.find("singular") != std::string::npos);
    CHECK(r.message.find("t = 0.5") != std::string::npos);
    REQUIRE(tr.t.size() == 6u);  // 0 .. 0.5
    CHECK(tr.t.back() == Approx(0.5));
    CHECK(r.t <= 0.55);
    CHECK(r.t > 0.5);
  }

  // A non-finite initial value is named; an unknown integrator is listed against the known.
  auto bad = x0;
  bad[ix("rocker.w")] = std::nan("");
  auto r = rt::simulate(model, "dopri5", so, opt, bad, {}, F::kParamDefaults);
  CHECK(r.status == rt::SimulationResult::Status::NonFiniteState);
  CHECK(r.message.find("'rocker.w'") != std::string::npos);
  r = rt::simulate(model, "euler", so, opt, x0, {}, F::kParamDefaults);
  CHECK(r.status == rt::SimulationResult::Status::BadSetup);
  CHECK(r.message.find("dop853") != std::string::npos);

  // A consistent start has no warning; one off a position constraint names the row that
  // is off the most and by how much (the run goes on).
  r = rt::simulate(model, "dopri5", so, opt, x0, {}, F::kParamDefaults);
  CHECK(r.warnings.empty());
  std::vector<double> g(static_cast<std::size_t>(F::kNposc));
  auto off = x0;
  off[ix("crank.theta")] += 0.05;
  REQUIRE(F::position_constraints(0.0, off.data(), nullptr, F::kParamDefaults, g.data()) == 0);
  std::size_t worst = 0;
  for (std::size_t i = 1; i < g.size(); ++i)
    if (std::abs(g[i]) > std::abs(g[worst])) worst = i;
  r = rt::simulate(model, "dopri5", so, opt, off, {}, F::kParamDefaults);
  REQUIRE(r.warnings.size() == 1);
  CHECK(r.warnings[0].find(std::string("off position constraint '") + F::kPositionConstraintNames[worst] + "'") !=
        std::string::npos);
}

TEST_CASE("simulate: the four-bar through its toggles stays on the physical branch", "[numeric][simulate][partition]") {
  const auto model = MBSC_MODEL_TABLE(F);
  const auto model_mult = MBSC_MODEL_TABLE_MULTIPLIERS(FM);
  const auto p = params_without_gravity();  // constant kinetic energy: the path is the whole closed curve
  const auto pm = mult_params(p, 10.0, 10.0);
  const auto x0 = state_at(0.3, 2.0, 1);
  rt::SimulationOptions opt;
  opt.t_end = 3.0;
  opt.dt_out = 0.005;
  struct Case {
    const char* integrator;
    double rtol;
  };
  for (const Case c : {Case{"dopri5", 1e-8}, Case{"dop853", 1e-10}}) {
    rt::StepperOptions so;
    so.rtol = c.rtol;
    so.atol = c.rtol * 1e-2;
    Trajectory tr, trm;
    const auto r = rt::simulate(model, c.integrator, so, opt, x0, {}, p.data(), record(tr));
    const auto rm = rt::simulate(model_mult, c.integrator, so, opt, x0, {}, pm.data(), record(trm));
    INFO(c.integrator << " rtol " << c.rtol << ": " << r.message << " / " << rm.message);
    REQUIRE(r.ok());
    REQUIRE(rm.ok());
    REQUIRE(tr.t.size() == trm.t.size());
    double diff = 0.0;
    int reversals = 0;
    for (std::size_t k = 0; k < tr.t.size(); ++k) {
      diff = std::max(diff, std::abs(tr.crank[k] - trm.crank[k]));
      if (k > 0) reversals += (tr.crank_w[k] > 0) != (tr.crank_w[k - 1] > 0);
    }
    std::string switches;
    for (const auto& s : r.switches) switches += " t=" + std::to_string(s.t) + "->" + s.name;
    INFO("complement vs multipliers: crank angle differs by " << diff << "; crank reversals " << reversals << "; switches"
                                                              << switches << "; residuals " << r.max_position_residual
                                                              << " / " << r.max_velocity_residual << "; "
                                                              << r.projections << " projections; energy drift "
                                                              << r.energy_relative_drift);
    CHECK(reversals >= 2);  // through the crank's toggles
    CHECK(r.switches.size() >= 2);
    for (const auto& s : r.switches) CHECK(s.name == F::kPartitionNames[s.to]);
    CHECK(r.max_position_residual < 1e-8);
    CHECK(r.max_velocity_residual < 1e-8);
    CHECK(diff < 1e4 * c.rtol);
    CHECK(r.energy_relative_drift < 1e3 * c.rtol);
    // Keeping the independent coordinates in the projection instead: here every
    // coordinate feeds the accelerations, and the shortest correction is the better one.
    rt::SimulationOptions keep = opt;
    keep.projection_keeps_independent = true;
    Trajectory trk;
    const auto rk = rt::simulate(model, c.integrator, so, keep, x0, {}, p.data(), record(trk));
    REQUIRE(rk.ok());
    double diff_keep = 0.0;
    for (std::size_t k = 0; k < trk.t.size(); ++k) diff_keep = std::max(diff_keep, std::abs(trk.crank[k] - trm.crank[k]));
    INFO(c.integrator << " rtol " << c.rtol << ": crank angle against the multipliers form " << diff
                      << " with the shortest projection (" << r.projections << " projections), " << diff_keep
                      << " keeping the independent coordinates (" << rk.projections << ")");
    CHECK(rk.max_position_residual < 1e-8);
  }
  // Without re-selection the crank partition meets singular blocks at the crank's
  // toggles; an adaptive run may still get through (steps never land on the toggle
  // exactly), at a cost in rejected steps. Reported, not required either way.
  rt::StepperOptions so;
  so.rtol = 1e-8;
  so.atol = 1e-10;
  opt.reselect = false;
  Trajectory tr;
  const auto r = rt::simulate(model, "dopri5", so, opt, x0, {}, p.data(), record(tr));
  INFO("four-bar toggles without re-selection (dopri5, rtol 1e-8): " << (r.ok() ? "ran" : r.message) << ", "
                                                                     << r.stats.rejected << " rejected steps, "
                                                                     << r.rhs_evals << " rhs evaluations");
  CHECK(r.switches.empty());
}

TEST_CASE("simulate: Baumgarte gains keep the multipliers form on the constraints", "[numeric][simulate][baumgarte]") {
  const auto model_mult = MBSC_MODEL_TABLE_MULTIPLIERS(FM);
  const std::vector<double> p(F::kParamDefaults, F::kParamDefaults + F::kNp);  // with gravity
  const auto x0 = state_at(0.3, 2.0, 1);
  rt::StepperOptions so;
  so.rtol = 1e-6;
  so.atol = 1e-8;
  rt::SimulationOptions opt;
  opt.dt_out = 0.0;
  opt.projection = rt::SimulationOptions::Projection::Off;  // the gains alone
  auto drift = [&](double alpha, double beta, double t_end) {
    opt.t_end = t_end;
    const auto pm = mult_params(p, alpha, beta);
    const auto r = rt::simulate(model_mult, "dopri5", so, opt, x0, {}, pm.data());
    INFO(r.message);
    REQUIRE(r.ok());
    CHECK(r.projections == 0);
    return r;
  };
  const auto free5 = drift(0.0, 0.0, 5.0), free20 = drift(0.0, 0.0, 20.0);
  const auto held5 = drift(FM::kParamDefaults[FM::kNp - 2], FM::kParamDefaults[FM::kNp - 1], 5.0),
             held20 = drift(FM::kParamDefaults[FM::kNp - 2], FM::kParamDefaults[FM::kNp - 1], 20.0);
  INFO("alpha = beta = 0: position drift " << free5.max_position_residual << " after 5 s, " << free20.max_position_residual
                                           << " after 20 s; default gains: " << held5.max_position_residual << ", "
                                           << held20.max_position_residual << "; velocity " << free20.max_velocity_residual
                                           << " vs " << held20.max_velocity_residual);
  CHECK(free20.max_position_residual > 2 * free5.max_position_residual);  // grows without bound
  CHECK(free20.max_position_residual > 10 * held20.max_position_residual);
  CHECK(held20.max_position_residual < 2 * held5.max_position_residual);  // bounded
  CHECK(held20.max_position_residual < 1e-4);
}
