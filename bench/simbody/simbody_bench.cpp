// SPDX-License-Identifier: GPL-2.0-or-later
// The Simbody peer of `mbsc bench`: integrates one shipped closed-loop model, rebuilt with
// Simbody's API (models/*.cpp), from the initial state of initial_states.txt with one of
// Simbody's integrators at one accuracy, and prints one CSV line:
//
//   tool,model,method,tol,t_end,cpu_s,repeats,steps,rejected,rhs_evals,projections,
//   pos_residual,vel_residual,energy_drift,<independent coordinates and speeds>
//
//   cpu_s         process CPU time of one integration (initialize + stepping to t_end),
//                 the mean over `repeats` runs (enough runs for at least --min-cpu s);
//                 assembly and the statistics run below are not counted
//   steps         accepted steps; rejected: attempted - accepted
//   rhs_evals     Simbody's state realizations (each an evaluation of the accelerations)
//   projections   position + velocity projections onto the constraint manifold
//   pos_residual, vel_residual  largest |position| / |velocity| constraint error
//                 (Simbody's qerr, uerr) over the accepted steps of a second, untimed run
//   energy_drift  largest |E(t) - E(0)| over the same steps (kinetic + gravity; the
//                 five-bar is dissipative, so there it is not a drift)
//   last columns  the final values (t = t_end) of the model's independent coordinates
//                 and speeds, named as in mbsc (crank.theta, crank.w, ...)
//
// Usage: simbody_bench MODEL TOL T_END METHOD [--states FILE] [--header] [--min-cpu S]
//        simbody_bench MODEL TOL T_END METHOD --trajectory DT   (t and the independents
//                 every DT, stepping exactly to each time, no timing)
// METHOD: rkmerson, rkfeldberg, rk3, cpodes_bdf, cpodes_adams, semieuler2, verlet.
// Exit 1 on bad arguments or input, 2 when the integration fails (message on stderr).
#include <time.h>

#include <Simbody.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>

#include "assemble.hpp"
#include "initial_states.hpp"
#include "mechanism.hpp"

#ifndef SIMBENCH_STATES_FILE
#define SIMBENCH_STATES_FILE "bench/simbody/initial_states.txt"
#endif

using namespace SimTK;
using simbench::Mechanism;

namespace {

const char* const kMethods[] = {"rkmerson", "rkfeldberg", "rk3", "cpodes_bdf", "cpodes_adams", "semieuler2", "verlet"};

std::unique_ptr<Integrator> make_integrator(const std::string& method, const MultibodySystem& sys) {
  if (method == "rkmerson") return std::make_unique<RungeKuttaMersonIntegrator>(sys);
  if (method == "rkfeldberg") return std::make_unique<RungeKuttaFeldbergIntegrator>(sys);
  if (method == "rk3") return std::make_unique<RungeKutta3Integrator>(sys);
  if (method == "cpodes_bdf") return std::make_unique<CPodesIntegrator>(sys, CPodes::BDF);
  if (method == "cpodes_adams") return std::make_unique<CPodesIntegrator>(sys, CPodes::Adams);
  if (method == "semieuler2") return std::make_unique<SemiExplicitEuler2Integrator>(sys);
  if (method == "verlet") return std::make_unique<VerletIntegrator>(sys);
  throw std::invalid_argument("unknown method '" + method +
                              "' (rkmerson, rkfeldberg, rk3, cpodes_bdf, cpodes_adams, semieuler2, verlet)");
}

double cpu_now() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double max_abs(const Vector& v) {
  double out = 0.0;
  for (int i = 0; i < v.size(); ++i) out = std::max(out, std::fabs(v[i]));
  return out;
}

struct Run {
  std::string method;
  double tol, t_end;
};

std::unique_ptr<Integrator> configured(const Mechanism& m, const Run& r) {
  auto integ = make_integrator(r.method, m.system);
  integ->setAccuracy(r.tol);
  integ->setConstraintTolerance(r.tol);
  integ->setFinalTime(r.t_end);
  integ->setInternalStepLimit(100000000);
  return integ;
}

// One integration from s0 to t_end; `each_step` (if set) sees every accepted step.
template <class F>
std::unique_ptr<Integrator> integrate(const Mechanism& m, const Run& r, const State& s0, F&& each_step, bool every_step) {
  auto integ = configured(m, r);
  integ->setReturnEveryInternalStep(every_step);
  integ->initialize(s0);
  while (integ->getTime() < r.t_end) {
    const auto status = integ->stepTo(r.t_end);
    each_step(integ->getState());
    if (status == Integrator::EndOfSimulation) break;
  }
  return integ;
}

std::string fmt(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

}  // namespace

int main(int argc, char** argv) {
  std::string model, method, states = SIMBENCH_STATES_FILE;
  double tol = 0, t_end = 0, traj_dt = 0, min_cpu = 0.05;
  bool header = false;
  try {
    std::vector<std::string> pos;
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      auto next = [&]() -> std::string {
        if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
        return argv[++i];
      };
      if (a == "--states") states = next();
      else if (a == "--header") header = true;
      else if (a == "--trajectory") traj_dt = std::stod(next());
      else if (a == "--min-cpu") min_cpu = std::stod(next());
      else pos.push_back(a);
    }
    if (pos.size() != 4) throw std::invalid_argument("usage: simbody_bench MODEL TOL T_END METHOD [--states FILE] [--header] [--min-cpu S] [--trajectory DT]");
    model = pos[0], tol = std::stod(pos[1]), t_end = std::stod(pos[2]), method = pos[3];
    if (!(tol > 0) || !(t_end > 0)) throw std::invalid_argument("TOL and T_END must be positive");
    if (std::none_of(std::begin(kMethods), std::end(kMethods), [&](const char* k) { return method == k; }))
      throw std::invalid_argument("unknown method '" + method +
                                  "' (rkmerson, rkfeldberg, rk3, cpodes_bdf, cpodes_adams, semieuler2, verlet)");
  } catch (const std::exception& e) {
    std::cerr << "simbody_bench: error: " << e.what() << "\n";
    return 1;
  }

  std::unique_ptr<Mechanism> m;
  State s0;
  try {
    m = simbench::make_mechanism(model);
    simbench::add_speed_locks(*m);
    m->system.realizeTopology();
    s0 = simbench::assemble_initial_state(*m, simbench::find_initial_state(states, model));
    m->system.realize(s0, Stage::Acceleration);
  } catch (const std::exception& e) {
    std::cerr << "simbody_bench: " << model << ": error: " << e.what() << "\n";
    return 1;
  }
  const Run run{method, tol, t_end};

  try {
    if (traj_dt > 0) {
      std::cout << "t";
      for (const auto& n : m->independent) std::cout << "," << n;
      std::cout << "\n";
      auto integ = configured(*m, run);
      integ->setAllowInterpolation(false);  // land on each output time exactly
      integ->initialize(s0);
      const int n_out = static_cast<int>(std::lround(t_end / traj_dt));
      for (int k = 0; k <= n_out; ++k) {
        const double t = std::min(t_end, k * traj_dt);
        while (k > 0 && integ->getTime() < t) integ->stepTo(t);
        std::cout << fmt(integ->getTime());
        for (const auto& n : m->independent) std::cout << "," << fmt(m->get(integ->getState(), n));
        std::cout << "\n";
      }
      return 0;
    }

    // Timing: repeat whole integrations until they add up to min_cpu seconds.
    auto nothing = [](const State&) {};
    int repeats = 1;
    double cpu = 0;
    std::unique_ptr<Integrator> last;
    for (;;) {
      const double c0 = cpu_now();
      for (int k = 0; k < repeats; ++k) last = integrate(*m, run, s0, nothing, false);
      cpu = cpu_now() - c0;
      if (cpu >= min_cpu) break;
      repeats = static_cast<int>(std::ceil(repeats * std::min(100.0, 1.2 * min_cpu / std::max(cpu, 1e-7))));
    }
    const State& sf = last->getState();
    const int steps = last->getNumStepsTaken(), rejected = last->getNumStepsAttempted() - steps;
    const int realizations = last->getNumRealizations(), projections = last->getNumProjections();
    std::vector<double> finals;
    for (const auto& n : m->independent) finals.push_back(m->get(sf, n));

    // Residuals and energy over the accepted steps (untimed).
    double pos_res = max_abs(s0.getQErr()), vel_res = max_abs(s0.getUErr()), drift = 0;
    const double e0 = m->system.calcEnergy(s0);
    integrate(*m, run, s0,
              [&](const State& s) {
                State c = s;
                m->system.realize(c, Stage::Dynamics);
                pos_res = std::max(pos_res, max_abs(c.getQErr()));
                vel_res = std::max(vel_res, max_abs(c.getUErr()));
                drift = std::max(drift, std::fabs(m->system.calcEnergy(c) - e0));
              },
              true);

    if (header) {
      std::cout << "tool,model,method,tol,t_end,cpu_s,repeats,steps,rejected,rhs_evals,projections,pos_residual,"
                   "vel_residual,energy_drift";
      for (const auto& n : m->independent) std::cout << "," << n;
      std::cout << "\n";
    }
    std::cout << "simbody," << model << "," << method << "," << fmt(tol) << "," << fmt(t_end) << "," << fmt(cpu / repeats)
              << "," << repeats << "," << steps << "," << rejected << "," << realizations << "," << projections << ","
              << fmt(pos_res) << "," << fmt(vel_res) << "," << fmt(drift);
    for (double v : finals) std::cout << "," << fmt(v);
    std::cout << "\n";
  } catch (const std::exception& e) {
    std::cerr << "simbody_bench: " << model << " " << method << " tol " << tol << ": integration failed: " << e.what()
              << "\n";
    return 2;
  }
  return 0;
}
