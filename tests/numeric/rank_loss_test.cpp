// SPDX-License-Identifier: GPL-2.0-or-later
// Rank loss of the whole constraint set: the chain of parallelogram four-bars
// (models/parallelogram_chain.mbs) spinning through its flat poses, where every window's
// constraints become redundant for an instant, run with the runtime's branch
// continuation (include/mbsc/runtime/branch_continuation.hpp) around a fixed-step RK4.
//   - plain, the generated rhs of both formulations fails at a flat pose (status 1);
//   - continued, runs of 20 s from exactly flat, at several step sizes, keep energy
//     (relative drift against the start), keep every crank parallel to the first (the
//     parallelogram branch, not the anti-parallelogram that crosses it there) and keep
//     the constraints; the complement and multipliers formulations agree on the angle;
//   - the 40-window chain (the same file, N frozen at 40) does the same;
//   - that chain's O(N) rhs (what --solver auto takes for it: the loop eliminated speeds
//     first) fails at a flat pose like the dense one, its conditioning reports 0 there,
//     and falls like the distance in the complement form (square_law) but like its square
//     in the multipliers form, as the dense forms' do.
#include <catch2/catch.hpp>
#include <array>
#include <cmath>
#include <ctime>
#include <string>
#include <vector>

#include "chain40/chain40.hpp"
#include "chain40_mult/chain40_mult.hpp"
#include "chain_rl/chain_rl.hpp"
#include "chain_rl_mult/chain_rl_mult.hpp"
#include "mbsc/runtime/branch_continuation.hpp"
#include "mbsc/runtime/model_table.hpp"
#include "mbsc/runtime/rk4.hpp"
#include "mbsc/runtime/simulate.hpp"
#include "test_support.hpp"

using mbsc::runtime::ModelTable;
using mbsc_test::index_of;

namespace {

/// The parallelogram branch in closed form for an N-window chain: every crank at theta
/// turning at w, the couplers level and translating.
std::vector<double> parallelogram(const ModelTable& m, int N, double theta, double w, const double* p = nullptr) {
  if (p == nullptr) p = m.param_defaults;
  const double L = p[index_of(m.param_names, m.np, "L")];
  const double a = p[index_of(m.param_names, m.np, "a")];
  std::vector<double> x(static_cast<std::size_t>(m.nx), 0.0);
  auto set = [&](const std::string& name, double v) { x[static_cast<std::size_t>(index_of(m.state_names, m.nx, name))] = v; };
  const double c = std::cos(theta), s = std::sin(theta);
  for (int i = 0; i <= N; ++i) {
    const std::string b = "crank_" + std::to_string(i);
    set(b + ".x", i * L + a / 2 * c);
    set(b + ".y", a / 2 * s);
    set(b + ".theta", theta);
    set(b + ".u", -a / 2 * s * w);
    set(b + ".v", a / 2 * c * w);
    set(b + ".w", w);
  }
  for (int j = 1; j <= N; ++j) {
    const std::string b = "coupler_" + std::to_string(j);
    set(b + ".x", (j - 1) * L + a * c + L / 2);
    set(b + ".y", a * s);
    set(b + ".u", -a * s * w);
    set(b + ".v", a * c * w);
  }
  return x;
}

struct Run {
  int status = 0;
  double t = 0.0;               // where it stopped
  double energy_drift = 0.0;    // max |E - E0| / |T0|
  double crank_spread = 0.0;    // max |theta_i - theta_0|
  double residual = 0.0;        // max position constraint residual
  int flat_crossings = 0;       // sign changes of sin(theta_0)
  double final_angle = 0.0;     // crank_0.theta at the end
  long bridged = 0, projected = 0;
};

/// RK4 with step h for t_end seconds from x; `continued`: through BranchContinuation
/// (and its correction after each step), else the plain generated rhs.
Run run(const ModelTable& m, int N, std::vector<double> x, const std::vector<double>& p, double h, double t_end,
        bool continued, mbsc::runtime::BranchSettings settings = {}) {
  Run r;
  mbsc::runtime::BranchContinuation bc(m, nullptr, p.data(), settings);
  auto f = [&](double t, const double* s, double* sd) {
    return continued ? bc.rhs(t, s, sd) : m.rhs(t, s, nullptr, p.data(), sd);
  };
  const int th0 = index_of(m.state_names, m.nx, "crank_0.theta");
  double e0[3];
  REQUIRE(m.energy(0.0, x.data(), nullptr, p.data(), e0) == 0);
  std::vector<double> g(static_cast<std::size_t>(m.nposc));
  const int steps = static_cast<int>(std::lround(t_end / h));
  double last_sin = std::sin(x[static_cast<std::size_t>(th0)]);
  for (int k = 0; k < steps; ++k) {
    r.status = mbsc::runtime::rk4_step(f, k * h, h, x);
    if (r.status == 0 && continued) r.status = bc.correct((k + 1) * h, x);
    if (r.status != 0) {
      r.t = k * h;
      return r;
    }
    double e[3];
    REQUIRE(m.energy(0.0, x.data(), nullptr, p.data(), e) == 0);
    r.energy_drift = std::max(r.energy_drift, std::abs(e[2] - e0[2]) / std::abs(e0[0]));
    REQUIRE(m.position_constraints(0.0, x.data(), nullptr, p.data(), g.data()) == 0);
    for (double v : g) r.residual = std::max(r.residual, std::abs(v));
    const double theta0 = x[static_cast<std::size_t>(th0)];
    for (int i = 1; i <= N; ++i) {
      const double ti = x[static_cast<std::size_t>(index_of(m.state_names, m.nx, "crank_" + std::to_string(i) + ".theta"))];
      r.crank_spread = std::max(r.crank_spread, std::abs(ti - theta0));
    }
    const double sn = std::sin(theta0);
    if ((sn > 0) != (last_sin > 0)) ++r.flat_crossings;
    last_sin = sn;
  }
  r.t = t_end;
  r.final_angle = x[static_cast<std::size_t>(th0)];
  r.bridged = bc.bridged();
  r.projected = bc.projected();
  return r;
}

std::vector<double> params(const ModelTable& m, bool multipliers) {
  std::vector<double> p(m.param_defaults, m.param_defaults + m.np);
  if (multipliers) p[static_cast<std::size_t>(m.np - 2)] = p[static_cast<std::size_t>(m.np - 1)] = 10.0;
  return p;
}

}  // namespace

TEST_CASE("rank loss: the plain rhs of both formulations fails at the flat pose", "[numeric][rank_loss]") {
  const ModelTable c = MBSC_MODEL_TABLE(mbsc_gen::chain_rl);
  const ModelTable mm = MBSC_MODEL_TABLE_MULTIPLIERS(mbsc_gen::chain_rl_mult);
  for (const ModelTable* m : {&c, &mm}) {
    const Run r = run(*m, 3, parallelogram(*m, 3, 0.0, 10.0), params(*m, m->multipliers), 1e-3, 1.0, false);
    CHECK(r.status == 1);
    CHECK(r.t == 0.0);
  }
}

TEST_CASE("rank loss: 20 s through every flat pose, complement and multipliers, several steps", "[numeric][rank_loss]") {
  const ModelTable c = MBSC_MODEL_TABLE(mbsc_gen::chain_rl);
  const ModelTable mm = MBSC_MODEL_TABLE_MULTIPLIERS(mbsc_gen::chain_rl_mult);
  // Exactly flat at t = 0, fast enough to go over the top (about 50 flat poses in 20 s).
  for (double h : {1e-3, 2.7e-3, 5e-3}) {
    double angle[2] = {0.0, 0.0};
    for (int form = 0; form < 2; ++form) {
      const ModelTable& m = form == 0 ? c : mm;
      const Run r = run(m, 3, parallelogram(m, 3, 0.0, 10.0), params(m, m.multipliers), h, 20.0, true);
      INFO("h = " << h << (form ? " multipliers" : " complement") << ": stopped at " << r.t << " status " << r.status
                  << ", energy drift " << r.energy_drift << ", crank spread " << r.crank_spread << ", residual "
                  << r.residual << ", flat poses " << r.flat_crossings << ", bridged " << r.bridged << ", projected "
                  << r.projected);
      REQUIRE(r.status == 0);
      CHECK(r.flat_crossings > 2 * CHAIN40_SECONDS);
      // RK4's own energy error: small on the complement form; the multipliers form's
      // Baumgarte terms make its off-manifold field stiffer (1e-6 to 5e-5 here).
      CHECK(r.energy_drift < (form == 0 ? 1e-6 : 1e-4));
      // The cranks' spread is RK4's error accumulated over ~50 flat poses: rounding moves
      // it (1.2e-8 at h = 1e-3 once the back end's sum rewrites reordered the arithmetic).
      CHECK(r.crank_spread < 2e-8);
      CHECK(r.residual < 1e-9);
      angle[form] = r.final_angle;
    }
    INFO("h = " << h << ": final crank angle " << angle[0] << " (complement), " << angle[1] << " (multipliers)");
    CHECK(std::abs(angle[0] - angle[1]) < 1e-4 * std::abs(angle[0]));
  }
}

#ifndef CHAIN40_SECONDS
#define CHAIN40_SECONDS 20.0
#endif

// Hidden from the default run ([.]): ctest runs it as rank_loss_chain40_test, label slow.
TEST_CASE("rank loss: the 40-window chain through its flat poses", "[.][chain40][numeric][rank_loss]") {
  const ModelTable m = MBSC_MODEL_TABLE(mbsc_gen::chain40);
  // Projections of 243 coordinates cost a dense least-squares solve each: only when the
  // residuals pass 1e-9. Large steps keep the test short (each rhs solves an 80x80 block
  // and its conditioning).
  mbsc::runtime::BranchSettings settings;
  settings.drift_tol = 1e-9;
  // CHAIN40_SECONDS: 20 s; 2 s (6 flat poses) in the sanitizer build, -O0 and ten times slower.
  const Run r = run(m, 40, parallelogram(m, 40, 0.0, 10.0), params(m, false), 2e-2, CHAIN40_SECONDS, true, settings);
  INFO("stopped at " << r.t << " status " << r.status << ", energy drift " << r.energy_drift << ", crank spread "
                     << r.crank_spread << ", residual " << r.residual << ", flat poses " << r.flat_crossings << ", bridged "
                     << r.bridged << ", projected " << r.projected);
  REQUIRE(r.status == 0);
  CHECK(r.flat_crossings > 2 * CHAIN40_SECONDS);
  // 20 ms steps are 0.2 rad of the cranks: RK4's own energy error is about 3e-5 here.
  CHECK(r.energy_drift < 1e-4);
  CHECK(r.crank_spread < 1e-8);
  CHECK(r.residual < 1e-8);
}

#ifndef A02_SECONDS
#define A02_SECONDS 4.0
#endif

TEST_CASE("rank loss: IFToMM A02, the 40-window chain at DOP853 1e-10, crosses its flat poses by extrapolation",
          "[numeric][rank_loss][a02]") {
  // Benchmark A02: 81 bars of 1 m and 1 kg, cranks vertical, the first crank's tip at
  // 1 m/s. On its branch the chain is one pendulum, J theta'' = -K cos theta, with
  // J = (N + 1) m a^2 / 3 + N m a^2 (cranks about their pivots, couplers translating) and
  // K = g ((N + 1) m a / 2 + N m a): the reference, by RK4 at 1e-4 s. Before the crossings
  // by extrapolation (singular_crossing.hpp) this run crawled at the first flat pose.
  const ModelTable m = MBSC_MODEL_TABLE(mbsc_gen::chain40);
  const int N = 40;
  std::vector<double> p(m.param_defaults, m.param_defaults + m.np);
  for (const char* n : {"L", "a", "m_crank", "m_coupler"}) p[static_cast<std::size_t>(index_of(m.param_names, m.np, n))] = 1.0;
  const double g = p[static_cast<std::size_t>(index_of(m.param_names, m.np, "g"))], pi = std::acos(-1.0);
  const double J = (N + 1) / 3.0 + N, K = g * ((N + 1) / 2.0 + N);
  mbsc::runtime::ModelDynamics dyn(m, p);
  dyn.continue_through_rank_loss();
  auto stepper = mbsc::runtime::make_stepper("dop853", dyn.rhs(), m.nx, {1e-10, 1e-10});
  REQUIRE(stepper);
  mbsc::runtime::SimulationOptions o;
  o.t_end = A02_SECONDS;  // 4 s, four flat poses; 1 s, the first, in the sanitizer build
  o.dt_out = 0.01;
  o.projection_threshold = 2e-10;  // as `mbsc run` sets it: rtol + atol
  o.crossing.rtol = o.crossing.atol = 1e-10;
  const std::clock_t cpu0 = std::clock();
  o.stop_requested = [&](double) { return std::clock() - cpu0 > 120 * CLOCKS_PER_SEC; };  // a crawl fails, not hangs
  // The reference alongside the samples, and the flat poses it passes.
  std::array<double, 2> ref = {pi / 2, 1.0};
  double t_ref = 0.0, worst = 0.0, spread = 0.0;
  int flat = 0;
  const int th0 = index_of(m.state_names, m.nx, "crank_0.theta");
  auto observe = [&](double t, const std::vector<double>& x) {
    const double h = 1e-4;
    auto f = [&](const std::array<double, 2>& y) { return std::array<double, 2>{y[1], -K / J * std::cos(y[0])}; };
    while (t_ref < t - 1e-12) {
      const double hh = std::min(h, t - t_ref);
      const auto k1 = f(ref), k2 = f({ref[0] + hh / 2 * k1[0], ref[1] + hh / 2 * k1[1]});
      const auto k3 = f({ref[0] + hh / 2 * k2[0], ref[1] + hh / 2 * k2[1]}), k4 = f({ref[0] + hh * k3[0], ref[1] + hh * k3[1]});
      const double before = std::sin(ref[0]);
      for (std::size_t i = 0; i < 2; ++i) ref[i] += hh / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
      if ((std::sin(ref[0]) > 0) != (before > 0)) ++flat;
      t_ref += hh;
    }
    worst = std::max(worst, std::abs(x[static_cast<std::size_t>(th0)] - ref[0]));
    for (int i = 1; i <= N; ++i)
      spread = std::max(spread, std::abs(x[static_cast<std::size_t>(index_of(m.state_names, m.nx, "crank_" + std::to_string(i) + ".theta"))] -
                                         x[static_cast<std::size_t>(th0)]));
  };
  const auto r = mbsc::runtime::simulate(dyn, *stepper, o, parallelogram(m, N, pi / 2, 1.0, p.data()), observe);
  INFO(r.message << "; crossings " << r.crossings << " (estimate " << r.crossing_error << "), flat poses " << flat
                 << ", worst angle error " << worst << ", crank spread " << spread << ", " << r.cpu_seconds << " s CPU");
  REQUIRE(r.ok());
  CHECK(flat >= 1);
  CHECK(r.crossings == flat);  // every flat pose crossed by extrapolation
  CHECK(r.crossing_error <= 10.0);
  CHECK(worst < 1e-8);   // measured 5e-9 over the 4 s
  CHECK(spread < 1e-9);  // the parallelogram branch, not the anti-parallelogram
}

TEST_CASE("rank loss: the Hermite polynomial through values and rates", "[numeric][rank_loss]") {
  // Exact for a polynomial of degree 2k - 1 (k nodes), and past its last node on sin its
  // error falls like the spacing to the power 2k.
  const std::vector<double> t = {0.0, 0.3, 0.5, 1.1};
  std::vector<std::vector<double>> x, f;
  auto poly = [](double s) { return 2 - s + 3 * s * s * s - 0.5 * std::pow(s, 7); };
  auto dpoly = [](double s) { return -1 + 9 * s * s - 3.5 * std::pow(s, 6); };
  for (double s : t) {
    x.push_back({poly(s), std::sin(s)});
    f.push_back({dpoly(s), std::cos(s)});
  }
  std::vector<double> out;
  mbsc::runtime::HermitePolynomial(t, x, f).evaluate(1.7, out);
  CHECK(out[0] == Approx(poly(1.7)).epsilon(1e-12));
  double last = 0.0;
  for (double h : {0.2, 0.1, 0.05}) {
    std::vector<double> ts;
    std::vector<std::vector<double>> xs, fs;
    for (int k = 0; k < 3; ++k) {
      ts.push_back(k * h);
      xs.push_back({std::sin(k * h)});
      fs.push_back({std::cos(k * h)});
    }
    mbsc::runtime::HermitePolynomial(ts, xs, fs).evaluate(3 * h, out);
    const double err = std::abs(out[0] - std::sin(3 * h));
    if (last > 0) CHECK(last / err > 40.0);  // 2^6 = 64 for degree 5
    last = err;
  }
}

TEST_CASE("rank loss: the 40-window chain's O(N) rhs at and near a flat pose", "[numeric][rank_loss]") {
  const ModelTable c = MBSC_MODEL_TABLE(mbsc_gen::chain40);
  const ModelTable mm = MBSC_MODEL_TABLE_MULTIPLIERS(mbsc_gen::chain40_mult);
  // The smallest conditioning the rhs reports (conditioning_partition: 0 where a solve of
  // the rhs fails).
  auto worst_conditioning = [](const ModelTable& m, const std::vector<double>& x, const std::vector<double>& p) {
    double rc = -1.0;
    REQUIRE(m.conditioning_partition(0, 0.0, x.data(), nullptr, p.data(), &rc) == 0);
    return rc;
  };
  std::vector<double> accel[2];
  for (const ModelTable* m : {&c, &mm}) {
    INFO((m->multipliers ? "multipliers" : "complement"));
    const auto p = params(*m, m->multipliers);
    std::vector<double> xdot(static_cast<std::size_t>(m->nx));
    // Exactly flat: rhs and conditioning return status 1 (as the dense forms do), and
    // conditioning_partition, what --continuation reads, reports 0.
    const auto flat = parallelogram(*m, 40, 0.0, 10.0);
    CHECK(m->rhs(0.0, flat.data(), nullptr, p.data(), xdot.data()) == 1);
    std::vector<double> rc(static_cast<std::size_t>(m->multipliers ? mbsc_gen::chain40_mult::kNblocks : mbsc_gen::chain40::kNblocks));
    CHECK(m->conditioning(0.0, flat.data(), nullptr, p.data(), rc.data()) == 1);
    CHECK(worst_conditioning(*m, flat, p) == 0.0);
    // Away from it: finite accelerations.
    const auto x = parallelogram(*m, 40, 0.7, 3.0);
    REQUIRE(m->rhs(0.0, x.data(), nullptr, p.data(), xdot.data()) == 0);
    for (double v : xdot) REQUIRE(std::isfinite(v));
    accel[m->multipliers ? 1 : 0] = xdot;
    // Near it: the conditioning falls like the distance (complement) or its square
    // (multipliers) between 1e-2 and 1e-3 rad, the scaling --continuation's thresholds assume.
    const double r2 = worst_conditioning(*m, parallelogram(*m, 40, 1e-2, 3.0), p);
    const double r3 = worst_conditioning(*m, parallelogram(*m, 40, 1e-3, 3.0), p);
    INFO("conditioning at 1e-2 rad " << r2 << ", at 1e-3 rad " << r3);
    REQUIRE(r3 > 0.0);
    const double slope = std::log10(r2 / r3);
    CHECK(std::abs(slope - (m->multipliers ? 2.0 : 1.0)) < 0.2);
  }
  // On the manifold the two formulations give the same accelerations (the Baumgarte terms
  // vanish there).
  double scale = 1.0, diff = 0.0;
  for (std::size_t i = 0; i < accel[0].size(); ++i) {
    scale = std::max(scale, std::abs(accel[0][i]));
    diff = std::max(diff, std::abs(accel[0][i] - accel[1][i]));
  }
  CHECK(diff < 1e-9 * scale);
}
