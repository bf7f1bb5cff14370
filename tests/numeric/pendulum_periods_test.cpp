// SPDX-License-Identifier: GPL-2.0-or-later
// A pendulum at a large amplitude (170 degrees from the bottom) for many periods, through
// the runtime's simulation loop (include/mbsc/runtime/simulate.hpp), per integrator and
// tolerance. The model is a bar on a ground pin in absolute coordinates (x, y, theta:
// two constraints, so the loop's projection is at work); its period is the closed form
//   T = 4 sqrt(L / g) K(sin(theta0 / 2)),  L = I_O / (m d) = 2a/3,
// with the complete elliptic integral K from the arithmetic-geometric mean. The run ends
// at N T + T/4, where the exact motion passes the bottom at its fastest: the phase error
// there is (theta - theta_bottom) / omega, in seconds. Checked per method: phase error and
// energy drift small, the adaptive methods' phase error proportional to rtol (two decades
// of rtol buy about two of error), RK4's falling at least like h^4.
// PERIODS is 50 for the default suite and 1000 for the `slow` run (CMakeLists).
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "mbsc/runtime/simulate.hpp"
#include "pendulum/pendulum.hpp"
#include "test_support.hpp"

#ifndef PERIODS
#define PERIODS 50
#endif

namespace P = mbsc_gen::pendulum;
using mbsc_test::index_of;

namespace {

/// K(k) = pi / (2 AGM(1, sqrt(1 - k^2))).
double elliptic_k(double k) {
  double a = 1.0, b = std::sqrt(1.0 - k * k);
  for (int i = 0; i < 40 && std::abs(a - b) > 1e-16 * a; ++i) {
    const double an = 0.5 * (a + b);
    b = std::sqrt(a * b);
    a = an;
  }
  return M_PI / (2.0 * a);
}

double param(const char* name) { return P::kParamDefaults[index_of(P::kParamNames, P::kNp, name)]; }

struct Outcome {
  double phase_error;   // seconds, at the last bottom passage
  double energy_drift;  // relative
  double position_residual;
  long rhs_evals;
  long projections;
};

Outcome run(const std::string& integrator, double rtol, double h, double theta0, double period, int periods) {
  const auto model = MBSC_MODEL_TABLE(P);
  const double a = param("a");
  std::vector<double> x0(P::kNx, 0.0);
  x0[static_cast<std::size_t>(index_of(P::kStateNames, P::kNx, "bar.theta"))] = theta0;
  x0[static_cast<std::size_t>(index_of(P::kStateNames, P::kNx, "bar.x"))] = 0.5 * a * std::cos(theta0);
  x0[static_cast<std::size_t>(index_of(P::kStateNames, P::kNx, "bar.y"))] = 0.5 * a * std::sin(theta0);
  mbsc::runtime::StepperOptions so;
  so.rtol = rtol;
  so.atol = rtol * 1e-2;
  so.h = h;
  mbsc::runtime::SimulationOptions opt;
  opt.t_end = periods * period + period / 4;
  opt.dt_out = 0.0;  // the end state only
  const auto r = mbsc::runtime::simulate(model, integrator, so, opt, x0, {}, P::kParamDefaults);
  INFO(r.message);
  REQUIRE(r.ok());
  const double theta = r.x[static_cast<std::size_t>(index_of(P::kStateNames, P::kNx, "bar.theta"))];
  const double omega = r.x[static_cast<std::size_t>(index_of(P::kStateNames, P::kNx, "bar.w"))];
  REQUIRE(r.energy_defined);
  return {std::abs((theta + M_PI / 2) / omega), r.energy_relative_drift, r.max_position_residual, r.rhs_evals,
          r.projections};
}

}  // namespace

TEST_CASE("pendulum at 170 degrees: phase against the elliptic-integral period, per integrator and tolerance",
          "[numeric][simulate][pendulum]") {
  const double a = param("a"), g = param("g"), m = param("m"), J = param("J");
  const double L = (J + m * a * a / 4) / (m * a / 2);  // equivalent simple-pendulum length
  REQUIRE(L == Approx(2 * a / 3));
  const double amplitude = 170.0 * M_PI / 180.0;
  const double theta0 = -M_PI / 2 + amplitude;  // the bar hangs along -y at rest
  const double period = 4.0 * std::sqrt(L / g) * elliptic_k(std::sin(amplitude / 2));
  // Small-amplitude sanity of the AGM: K(0) = pi/2 gives 2 pi sqrt(L/g).
  REQUIRE(4.0 * elliptic_k(0.0) == Approx(2 * M_PI));
  const int N = PERIODS;
  const double total = N * period;

  for (const char* method : {"dopri5", "dop853"}) {
    double previous = 0.0;
    for (double rtol : {1e-6, 1e-8, 1e-10}) {
      const Outcome o = run(method, rtol, 0.0, theta0, period, N);
      INFO(method << " rtol " << rtol << " over " << N << " periods (" << total << " s): phase error " << o.phase_error
                  << " s (" << o.phase_error / total << " relative), energy drift " << o.energy_drift << ", residual "
                  << o.position_residual << ", " << o.rhs_evals << " rhs evaluations, " << o.projections
                  << " projections");
      CHECK(o.phase_error / total < 30 * rtol * N);  // global error grows with the number of periods
      CHECK(o.energy_drift < 100 * rtol * N);
      CHECK(o.position_residual < 10 * rtol);  // drift of one step, projected away after it
      if (previous > 0.0) {
        // Proportional to the tolerance: 100x smaller rtol, 100x smaller phase error
        // (within a factor 10 either way, and above rounding's floor).
        const double gain = previous / std::max(o.phase_error, 1e-13 * total);
        CHECK(gain > 10.0);
        if (o.phase_error > 1e-9 * total) CHECK(gain < 1e4);
      }
      previous = o.phase_error;
    }
  }
  // RK4 at fixed steps: the error falls at least like h^4 (here close to h^5). Steps
  // fine enough for the phase error to stay well inside a period (its measure above is
  // linear in it).
  const int steps = N > 100 ? 600 : 200;
  const Outcome coarse = run("rk4", 0.0, period / steps, theta0, period, N);
  const Outcome fine = run("rk4", 0.0, period / (2 * steps), theta0, period, N);
  INFO("rk4: phase error " << coarse.phase_error << " s with T/" << steps << ", " << fine.phase_error << " s with T/"
                           << 2 * steps << "; energy drift " << coarse.energy_drift << ", " << fine.energy_drift << "; "
                           << fine.rhs_evals << " rhs evaluations");
  CHECK(coarse.phase_error / fine.phase_error > 10.0);
  CHECK(coarse.phase_error / fine.phase_error < 40.0);
  CHECK(fine.phase_error / total < 1e-4);
}

TEST_CASE("pendulum: the projection keeps the integrated independent motion", "[numeric][simulate][pendulum]") {
  // The projection that keeps the independent speed (bar.w) and its coordinate
  // (bar.theta) and moves the dependent ones (projection_keeps_independent): the phase
  // is as accurate as without any projection, while the constraints and the energy are
  // held. The default, shortest correction in all coordinates moves theta too and costs
  // phase accuracy here (the pendulum's angle is integrated on its own; the four-bar's
  // simulation_test shows the opposite case).
  const auto model = MBSC_MODEL_TABLE(P);
  const double a = param("a"), g = param("g");
  const double amplitude = 170.0 * M_PI / 180.0, theta0 = -M_PI / 2 + amplitude;
  const double period = 4.0 * std::sqrt(2 * a / 3 / g) * elliptic_k(std::sin(amplitude / 2));
  std::vector<double> x0(P::kNx, 0.0);
  x0[static_cast<std::size_t>(index_of(P::kStateNames, P::kNx, "bar.theta"))] = theta0;
  x0[static_cast<std::size_t>(index_of(P::kStateNames, P::kNx, "bar.x"))] = 0.5 * a * std::cos(theta0);
  x0[static_cast<std::size_t>(index_of(P::kStateNames, P::kNx, "bar.y"))] = 0.5 * a * std::sin(theta0);
  mbsc::runtime::StepperOptions so;
  so.rtol = 1e-12;
  so.atol = 1e-14;
  const std::size_t th = static_cast<std::size_t>(index_of(P::kStateNames, P::kNx, "bar.theta")),
                    w = static_cast<std::size_t>(index_of(P::kStateNames, P::kNx, "bar.w"));
  struct Run {
    double phase, residual, energy;
    long projections;
  };
  auto run_with = [&](mbsc::runtime::SimulationOptions::Projection mode, bool keep) {
    mbsc::runtime::SimulationOptions opt;
    opt.t_end = 50 * period + period / 4;
    opt.dt_out = 0.0;
    opt.projection = mode;
    opt.projection_keeps_independent = keep;
    const auto r = mbsc::runtime::simulate(model, "dop853", so, opt, x0, {}, P::kParamDefaults);
    INFO(r.message);
    REQUIRE(r.ok());
    return Run{std::abs((r.x[th] + M_PI / 2) / r.x[w]), r.max_position_residual, r.energy_relative_drift, r.projections};
  };
  using Mode = mbsc::runtime::SimulationOptions::Projection;
  const Run off = run_with(Mode::Off, true), keep = run_with(Mode::Auto, true), shortest = run_with(Mode::Auto, false);
  INFO("phase error / residual / energy drift / projections: none " << off.phase << " / " << off.residual << " / "
                                                                    << off.energy << " / " << off.projections
                                                                    << "; keeping the independent " << keep.phase << " / "
                                                                    << keep.residual << " / " << keep.energy << " / "
                                                                    << keep.projections << "; shortest " << shortest.phase
                                                                    << " / " << shortest.residual << " / "
                                                                    << shortest.energy);
  CHECK(off.projections == 0);
  CHECK(keep.projections > 0);
  CHECK(std::abs(keep.phase - off.phase) < 0.1 * off.phase);
  CHECK(keep.residual <= 2e-10);  // the threshold (1e-10) plus one step's drift
  CHECK(keep.energy < off.energy);
  CHECK(shortest.phase > 3 * keep.phase);
}
