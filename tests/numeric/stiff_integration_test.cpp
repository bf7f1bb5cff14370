// SPDX-License-Identifier: GPL-2.0-or-later
// The stiff shipped model (models/stiff_spring_damper.mbs): two blocks on a line, a soft
// spring to the ground and a stiff spring-damper (k = 8e5 N/m, c = 4e4 N s/m) between
// them. On the line the equations are linear, z' = A z + b with z = (x1, x2, u1, u2), so
// the motion has a closed form, z(t) = z_eq + V exp(Lambda t) V^-1 (z0 - z_eq) from A's
// eigen-decomposition (computed here from the parameters, independently of mbsc).
//  - the generated rhs is that linear system (at random states on the line);
//  - CVODE BDF follows the closed form to 1e-6 over 2 s (at the step ends and inside the
//    steps) with a small fraction of the explicit Dormand-Prince run's rhs evaluations,
//    with either Jacobian (CVODE's differences or rhs_jacobian_x);
//  - the explicit run is held by stability: its steps stay near the stability limit of
//    the fast mode (|h lambda_fast| <= 3.5) though the motion would allow far longer ones,
//    and under a step budget it stops with a message naming the budget and t;
//  - classical RK4 with a step the slow motion would allow (1 ms) blows up: the generated
//    rhs reports the non-finite state.
// The [.bench] case times both Jacobian sources (docs/benchmarks.md, "Stiff integration").
#include <catch2/catch.hpp>
#include <Eigen/Eigenvalues>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <complex>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "mbsc/runtime/rhs_jacobian.hpp"
#include "mbsc/runtime/rk4.hpp"
#include "run/sundials_stepper.hpp"
#include "stiff_spring_damper/stiff_spring_damper.hpp"
#include "test_support.hpp"

namespace M = mbsc_gen::stiff_spring_damper;
using mbsc::run::JacobianSource;
using mbsc::run::make_sundials_stepper;
using mbsc::runtime::Stepper;
using mbsc::runtime::StepperOptions;
using mbsc_test::index_of;

namespace {

struct Params {
  double m1, m2, k0, L0, k, L, c;
};

Params params() {
  const double* p = M::kParamDefaults;
  auto at = [&](const char* n) { return p[index_of(M::kParamNames, M::kNp, n)]; };
  return {at("m1"), at("m2"), at("k0"), at("L0"), at("k"), at("L"), at("c")};
}

/// The line's linear system z' = A z + b, written from the physics (not from mbsc).
struct Linear {
  Eigen::Matrix4d A;
  Eigen::Vector4d b, z_eq;
  Eigen::Matrix4cd V, V_inv;
  Eigen::Vector4cd lambda;

  Linear() {
    const Params q = params();
    A << 0, 0, 1, 0,  //
        0, 0, 0, 1,   //
        -(q.k0 + q.k) / q.m1, q.k / q.m1, -q.c / q.m1, q.c / q.m1,  //
        q.k / q.m2, -q.k / q.m2, q.c / q.m2, -q.c / q.m2;
    b << 0, 0, (q.k0 * q.L0 - q.k * q.L) / q.m1, q.k * q.L / q.m2;
    z_eq << q.L0, q.L0 + q.L, 0, 0;
    Eigen::EigenSolver<Eigen::Matrix4d> es(A);
    V = es.eigenvectors();
    V_inv = V.inverse();
    lambda = es.eigenvalues();
  }
  Eigen::Vector4d at(double t, const Eigen::Vector4d& z0) const {
    Eigen::Vector4cd w = V_inv * (z0 - z_eq).cast<std::complex<double>>();
    for (int i = 0; i < 4; ++i) w[i] *= std::exp(lambda[i] * t);
    return z_eq + (V * w).real();
  }
  double fastest() const {
    double f = 0.0;
    for (int i = 0; i < 4; ++i) f = std::max(f, std::abs(lambda[i]));
    return f;
  }
};

struct Layout {
  int x1 = index_of(M::kStateNames, M::kNx, "b1.x"), x2 = index_of(M::kStateNames, M::kNx, "b2.x");
  int u1 = index_of(M::kStateNames, M::kNx, "b1.u"), u2 = index_of(M::kStateNames, M::kNx, "b2.u");
  Eigen::Vector4d z(const std::vector<double>& x) const { return {x[x1], x[x2], x[u1], x[u2]}; }
  std::vector<double> state(const Eigen::Vector4d& z) const {
    std::vector<double> x(M::kNx, 0.0);  // y and v are zero on the line
    x[x1] = z[0];
    x[x2] = z[1];
    x[u1] = z[2];
    x[u2] = z[3];
    return x;
  }
};

const Eigen::Vector4d kZ0(0.6, 0.95, 0.5, -0.3);  // the link stretched by 5 cm: 4e4 N
constexpr double kEnd = 2.0;                      // two periods of the slow mode

mbsc::runtime::Rhs model_rhs() {
  return [](double t, const double* x, double* xd) { return M::rhs(t, x, nullptr, M::kParamDefaults, xd); };
}

struct Run {
  Stepper::Status status;
  std::string message;
  mbsc::runtime::StepperStats stats;
  double error = 0.0;     // largest over the step ends and the midpoints (dense output)
  double median_h = 0.0;  // of the accepted steps
  double t = 0.0;
};

Run run(const std::string& name, const StepperOptions& opt, JacobianSource source = JacobianSource::Sundials) {
  const Linear lin;
  const Layout lay;
  mbsc::run::SundialsOptions extra;
  extra.jacobian_source = source;
  auto s = make_sundials_stepper(name, model_rhs(), M::kNx, opt, extra);
  REQUIRE(s);
  REQUIRE(s->reset(0.0, lay.state(kZ0)) == Stepper::Status::Ok);
  Run r{Stepper::Status::Ok, "", {}, 0.0, 0.0, 0.0};
  std::vector<double> hs, mid;
  while (s->t() < kEnd) {
    r.status = s->step(kEnd);
    if (r.status != Stepper::Status::Ok) break;
    hs.push_back(s->t() - s->t_begin());
    r.error = std::max(r.error, (lay.z(s->x()) - lin.at(s->t(), kZ0)).cwiseAbs().maxCoeff());
    const double tm = 0.5 * (s->t_begin() + s->t());
    s->interpolate(tm, mid);
    r.error = std::max(r.error, (lay.z(mid) - lin.at(tm, kZ0)).cwiseAbs().maxCoeff());
  }
  r.message = s->message();
  r.stats = s->stats();
  r.t = s->t();
  if (!hs.empty()) {
    std::nth_element(hs.begin(), hs.begin() + hs.size() / 2, hs.end());
    r.median_h = hs[hs.size() / 2];
  }
  return r;
}

void print(const char* what, const Run& r) {
  std::printf("%-26s steps %6ld rejected %4ld rhs %7ld jac %3ld newton %5ld median h %.2e error %.1e\n", what,
              r.stats.accepted, r.stats.rejected, r.stats.rhs_evals, r.stats.jacobian_evals, r.stats.newton_iterations,
              r.median_h, r.error);
}

}  // namespace

TEST_CASE("stiff spring-damper: the generated rhs is the line's linear system", "[numeric][stiff]") {
  const Linear lin;
  const Layout lay;
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    // One draw per statement (argument order is unspecified: g++ and clang differ), and
    // b2 stays right of b1, where the stiff link's length is b2.x - b1.x (linear).
    const double r1 = d(rng), r2 = d(rng), r3 = d(rng), r4 = d(rng);
    const Eigen::Vector4d z(0.5 + 0.1 * r1, 0.8 + 0.1 * r2, r3, r4);
    std::vector<double> x = lay.state(z), xd(M::kNx);
    REQUIRE(M::rhs(0.0, x.data(), nullptr, M::kParamDefaults, xd.data()) == 0);
    const Eigen::Vector4d expected = lin.A * z + lin.b;
    const double scale = expected.cwiseAbs().maxCoeff();
    CHECK((lay.z(xd) - expected).cwiseAbs().maxCoeff() <= 1e-12 * scale);
  }
  // Stiff indeed: the fast mode decays near c (1/m1 + 1/m2), the slow one turns about once a second.
  CHECK(lin.fastest() > 3e4);
}

TEST_CASE("stiff spring-damper: BDF reaches 1e-6 with a small fraction of the explicit rhs evaluations",
          "[numeric][stiff][sundials]") {
  StepperOptions opt;
  opt.rtol = 1e-9;
  opt.atol = 1e-11;
  const Run bdf = run("bdf", opt);
  const Run bdf_own = run("bdf", opt, JacobianSource::Differences);
  const Run erk = run("ark-erk", opt);
  print("bdf (CVODE differences)", bdf);
  print("bdf (rhs_jacobian_x)", bdf_own);
  print("ark-erk (Dormand-Prince)", erk);
  for (const Run* r : {&bdf, &bdf_own, &erk}) {
    INFO(r->message);
    REQUIRE(r->status == Stepper::Status::Ok);
    CHECK(r->t == kEnd);
    CHECK(r->error < 1e-6);
  }
  CHECK(bdf.stats.rhs_evals * 20 < erk.stats.rhs_evals);
  CHECK(bdf_own.stats.rhs_evals * 20 < erk.stats.rhs_evals);
  // The explicit steps sit at the stability limit of the fast mode (|h lambda| ~ 3.3 for
  // Dormand-Prince), far below what the accuracy of the slow motion asks (BDF's steps).
  const double fast = Linear().fastest();
  CHECK(erk.median_h * fast < 3.5);
  CHECK(erk.median_h * 20 < bdf.median_h);
}

TEST_CASE("stiff spring-damper: the explicit integrator under a step budget stops with a clear message",
          "[numeric][stiff][sundials]") {
  StepperOptions opt;
  opt.rtol = 1e-8;
  opt.atol = 1e-10;
  opt.max_steps = 2000;
  const Run erk = run("ark-erk", opt);
  CHECK(erk.status == Stepper::Status::TooManySteps);
  std::printf("%s\n", erk.message.c_str());
  INFO(erk.message);
  CHECK(erk.message.rfind("ark-erk: step budget of 2000 steps spent at t = ", 0) == 0);
  CHECK(erk.t < 0.5 * kEnd);
  CHECK(erk.error < 1e-6);  // what it did is right, only slow
  const Run bdf = run("bdf", opt);  // the same budget is plenty for BDF
  CHECK(bdf.status == Stepper::Status::Ok);
  CHECK(bdf.stats.accepted < 2000);
}

TEST_CASE("stiff spring-damper: RK4 at a step the slow motion allows blows up", "[numeric][stiff]") {
  const Layout lay;
  std::vector<double> x = lay.state(kZ0);
  int status = 0;
  double t = 0.0;
  const double h = 1e-3;  // |h lambda_fast| = 33, far outside RK4's stability interval (2.79)
  for (int k = 0; k < 2000 && status == 0; ++k, t += h) status = mbsc::runtime::rk4_step(model_rhs(), t, h, x);
  CHECK(status == 2);  // the generated rhs: "an output is not finite"
  CHECK(t < 0.2);
}

// Timing of the two Jacobian sources (not run by default): the integration alone, no
// checks, `repeats` times (MBSC_BENCH_REPEATS, default 2000), at the tolerance of the test above;
// MBSC_BENCH_SOURCE=sundials or differences runs one source only.
// docs/benchmarks.md, "Stiff integration: Jacobian by CVODE or by rhs_jacobian_x".
TEST_CASE("stiff spring-damper: timing of the Jacobian sources", "[.bench]") {
  StepperOptions opt;
  opt.rtol = 1e-9;
  opt.atol = 1e-11;
  const Layout lay;
  const char* env = std::getenv("MBSC_BENCH_REPEATS");
  const int repeats = env ? std::atoi(env) : 2000;
  const char* only = std::getenv("MBSC_BENCH_SOURCE");  // "sundials" or "differences" (callgrind runs)
  for (JacobianSource src : {JacobianSource::Sundials, JacobianSource::Differences}) {
    if (only && std::string(only) != (src == JacobianSource::Sundials ? "sundials" : "differences")) continue;
    mbsc::run::SundialsOptions extra;
    extra.jacobian_source = src;
    auto s = make_sundials_stepper("bdf", model_rhs(), M::kNx, opt, extra);
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < repeats; ++i) {
      REQUIRE(s->reset(0.0, lay.state(kZ0)) == Stepper::Status::Ok);
      while (s->t() < kEnd) REQUIRE(s->step(kEnd) == Stepper::Status::Ok);
    }
    const double per_run = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / repeats;
    const auto& st = s->stats();  // summed over the repeats
    std::printf("%-24s per run: %ld steps, %ld rhs, %ld Jacobians, %ld Newton iterations; %.1f us, %.3f us per Newton "
                "iteration; error %.1e\n",
                src == JacobianSource::Sundials ? "bdf, CVODE differences" : "bdf, rhs_jacobian_x", st.accepted / repeats,
                st.rhs_evals / repeats, st.jacobian_evals / repeats, st.newton_iterations / repeats, per_run * 1e6,
                per_run * 1e6 * repeats / st.newton_iterations,
                (lay.z(s->x()) - Linear().at(kEnd, kZ0)).cwiseAbs().maxCoeff());
  }
  // One Jacobian alone, at the initial state.
  std::vector<double> x = lay.state(kZ0), fx(M::kNx), J(M::kNx * M::kNx);
  auto f = model_rhs();
  REQUIRE(f(0.0, x.data(), fx.data()) == 0);
  const int evals = 100 * repeats;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < evals; ++i) mbsc::runtime::rhs_jacobian_x(f, 0.0, x.data(), fx.data(), M::kNx, J.data());
  const double per = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / evals;
  std::printf("rhs_jacobian_x alone: %.3f us per 8x8 Jacobian (8 rhs calls)\n", per * 1e6);
}
