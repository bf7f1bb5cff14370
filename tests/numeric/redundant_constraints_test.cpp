// SPDX-License-Identifier: GPL-2.0-or-later
// Constraints redundant on the mechanism (docs/formulation.md, "Redundant constraints"):
// rows independent at a generic configuration and dependent wherever the constraints hold.
//   - Bricard's linkage (tests/data/redundant/bricard.mbs, IFToMM A04: Gruebler 0, true
//     mobility 1) and the parallelogram with a third crank
//     (tests/data/linear/parallelogram_redundant.mbs) get one degree of freedom;
//   - 10 s runs in both formulations keep the energy to 1e-9 (relative) and the
//     constraints to their tolerance;
//   - the parallelogram follows the compound pendulum's equation, integrated on its own;
//   - Bricard follows its non-redundant twin (the last joint a universal joint that keeps
//     the same independent rows) until the twin's own singular pose near t = 2.2 s;
//   - the multipliers formulation returns the minimum-norm multipliers: orthogonal to the
//     left null space of A, with the twin's generalized reactions A^T lambda.
#include <catch2/catch.hpp>
#include <Eigen/Dense>
#include <cmath>
#include <string>
#include <vector>

#include "bricard/bricard.hpp"
#include "bricard_mult/bricard_mult.hpp"
#include "bricard_twin/bricard_twin.hpp"
#include "bricard_twin_mult/bricard_twin_mult.hpp"
#include "mbsc/runtime/assemble.hpp"
#include "mbsc/runtime/dop853.hpp"
#include "mbsc/runtime/model_table.hpp"
#include "mbsc/runtime/simulate.hpp"
#include "parallelogram_red/parallelogram_red.hpp"
#include "parallelogram_red_mult/parallelogram_red_mult.hpp"
#include "test_support.hpp"

using mbsc_test::index_of;

namespace {

/// Bricard's start (the cube pose, the first joint turning at 1 rad/s about y), assembled
/// for model NS: positions as the file gives them, the speeds from rod1.wy.
template <class Names>
std::vector<double> bricard_start(const Names& names, int nx, int nq, int nu, const mbsc::runtime::AssemblyModel& am,
                                  const double* p) {
  std::vector<double> x(static_cast<std::size_t>(nx), 0.0);
  auto set = [&](const std::string& n, double v) { x[static_cast<std::size_t>(index_of(names, nx, n))] = v; };
  const double centres[5][3] = {{0.5, 0, 0}, {1, 0.5, 0}, {1, 1, 0.5}, {0.5, 1, 1}, {0, 0.5, 1}};
  for (int i = 0; i < 5; ++i) {
    const std::string rod = "rod" + std::to_string(i + 1);
    set(rod + ".x", centres[i][0]);
    set(rod + ".y", centres[i][1]);
    set(rod + ".z", centres[i][2]);
    set(rod + ".e0", 1.0);
  }
  set("rod1.wy", 1.0);
  std::vector<bool> gq(static_cast<std::size_t>(nq), true), gu(static_cast<std::size_t>(nu), false);
  gu[static_cast<std::size_t>(index_of(names, nx, "rod1.wy") - nq)] = true;
  const auto r = mbsc::runtime::assemble(am, 0.0, x, gq, gu, nullptr, p);
  INFO(r.message);
  REQUIRE(r.ok());
  return x;
}

mbsc::runtime::SimulationResult run(const mbsc::runtime::ModelTable& m, const std::vector<double>& x0, double t_end,
                                    double rtol) {
  mbsc::runtime::StepperOptions so;
  so.rtol = rtol;
  so.atol = rtol * 1e-2;
  mbsc::runtime::SimulationOptions opt;
  opt.t_end = t_end;
  opt.dt_out = 0.0;
  const auto r = mbsc::runtime::simulate(m, "dop853", so, opt, x0, {}, m.param_defaults);
  INFO(r.message);
  REQUIRE(r.ok());
  return r;
}

double largest_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double d = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, std::fabs(a[i] - b[i]));
  return d;
}

}  // namespace

TEST_CASE("redundant constraints: Bricard's linkage moves with one degree of freedom in both formulations",
          "[numeric][redundant]") {
  namespace B = mbsc_gen::bricard;
  namespace BM = mbsc_gen::bricard_mult;
  namespace T = mbsc_gen::bricard_twin;
  REQUIRE(B::kNc == 30);
  REQUIRE(T::kNc == 29);
  CHECK(B::kNdof == 1);  // Gruebler's count is 0
  CHECK(T::kNdof == 1);
  const auto bm = MBSC_MODEL_TABLE(B), mm = MBSC_MODEL_TABLE_MULTIPLIERS(BM), tm = MBSC_MODEL_TABLE(T);
  const std::vector<double> x0 = bricard_start(B::kStateNames, B::kNx, B::kNq, B::kNu, MBSC_TEST_ASSEMBLY_MODEL(B), B::kParamDefaults);
  const std::vector<double> xt0 = bricard_start(T::kStateNames, T::kNx, T::kNq, T::kNu, MBSC_TEST_ASSEMBLY_MODEL(T), T::kParamDefaults);
  REQUIRE(largest_difference(x0, xt0) < 1e-12);  // the same start: the twin's rows hold the same speeds
  std::vector<double> xd(x0.size());
  REQUIRE(B::rhs(0.0, x0.data(), nullptr, B::kParamDefaults, xd.data()) == 0);

  SECTION("10 s keep energy and constraints; the formulations agree") {
    const auto rc = run(bm, x0, 10.0, 1e-11);
    const auto rm = run(mm, x0, 10.0, 1e-12);
    WARN("Bricard, 10 s: complement: energy " << rc.energy_relative_drift << ", residual " << rc.max_position_residual << ", "
                               << rc.rhs_evals << " rhs; multipliers: energy " << rm.energy_relative_drift << ", residual "
                               << rm.max_position_residual << ", " << rm.rhs_evals << " rhs; final states differ by "
                               << largest_difference(rc.x, rm.x));
    CHECK(rc.energy_relative_drift < 1e-9);
    CHECK(rm.energy_relative_drift < 1e-9);
    CHECK(rc.max_position_residual < 1e-9);
    CHECK(rm.max_position_residual < 1e-9);
    CHECK(largest_difference(rc.x, rm.x) < 1e-6);
    // It moved: the first rod turned by more than a radian about its ground axis.
    bool turned = false;
    mbsc::runtime::StepperOptions so;
    const auto probe = [&](double, const std::vector<double>& x) {
      turned = turned || std::fabs(x[static_cast<std::size_t>(index_of(B::kStateNames, B::kNx, "rod1.e2"))]) > 0.5;
    };
    mbsc::runtime::SimulationOptions opt;
    opt.t_end = 10.0;
    opt.dt_out = 0.1;
    so.rtol = 1e-8;
    so.atol = 1e-10;
    REQUIRE(mbsc::runtime::simulate(bm, "dop853", so, opt, x0, {}, bm.param_defaults, probe).ok());
    CHECK(turned);
  }

  SECTION("the twin's motion, until its own singular pose") {
    const auto rc = run(bm, x0, 2.0, 1e-11);
    const auto rt = run(tm, xt0, 2.0, 1e-11);
    WARN("Bricard and its twin: largest state difference at t = 2: " << largest_difference(rc.x, rt.x));
    CHECK(largest_difference(rc.x, rt.x) < 1e-8);
  }

  SECTION("minimum-norm multipliers with the twin's reactions") {
    namespace TM = mbsc_gen::bricard_twin_mult;
    std::vector<double> pm(BM::kParamDefaults, BM::kParamDefaults + BM::kNp), ptm(TM::kParamDefaults, TM::kParamDefaults + TM::kNp);
    std::vector<double> lambda(BM::kNc), lambda_t(TM::kNc), reaction(BM::kNu), reaction_t(TM::kNu);
    REQUIRE(BM::multipliers(0.0, x0.data(), nullptr, pm.data(), lambda.data()) == 0);
    REQUIRE(TM::multipliers(0.0, x0.data(), nullptr, ptm.data(), lambda_t.data()) == 0);
    REQUIRE(BM::reaction_forces(0.0, x0.data(), nullptr, pm.data(), reaction.data()) == 0);
    REQUIRE(TM::reaction_forces(0.0, x0.data(), nullptr, ptm.data(), reaction_t.data()) == 0);
    double scale = 0.0;
    for (double r : reaction_t) scale = std::max(scale, std::fabs(r));
    REQUIRE(scale > 1.0);  // gravity and the spin load the joints
    CHECK(largest_difference(reaction, reaction_t) < 1e-9 * scale);
    // lambda has no part along the left null space of A (the redundant combination).
    std::vector<double> A(static_cast<std::size_t>(BM::kNc * BM::kNu));
    REQUIRE(BM::constraint_jacobian(0.0, x0.data(), nullptr, pm.data(), A.data()) == 0);
    const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> Am(A.data(), BM::kNc, BM::kNu);
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(Am.transpose(), Eigen::ComputeFullV);
    const Eigen::VectorXd s = svd.singularValues();
    REQUIRE(s(BM::kNc - 2) > 1e-3 * s(0));   // rank 29 ...
    REQUIRE(s(BM::kNc - 1) < 1e-12 * s(0));  // ... of 30
    const Eigen::VectorXd n = svd.matrixV().col(BM::kNc - 1);
    const Eigen::Map<const Eigen::VectorXd> l(lambda.data(), BM::kNc);
    WARN("minimum-norm multipliers: n . lambda = " << n.dot(l) << ", |lambda| = " << l.norm()
                                                   << "; reactions differ from the twin's by "
                                                   << largest_difference(reaction, reaction_t) << " of " << scale);
    CHECK(std::fabs(n.dot(l)) < 1e-10 * l.norm());
  }
}

TEST_CASE("redundant constraints: the parallelogram with a third crank is a compound pendulum",
          "[numeric][redundant]") {
  namespace P = mbsc_gen::parallelogram_red;
  namespace PM = mbsc_gen::parallelogram_red_mult;
  CHECK(P::kNdof == 1);
  auto par = [](const char* n) { return P::kParamDefaults[index_of(P::kParamNames, P::kNp, n)]; };
  const double a = par("a"), L = par("L"), g = par("g"), mc = par("m_crank"), mp = par("m_coupler");
  const double K = g * (1.5 * mc + mp) / ((mc + mp) * a);
  // The parallelogram branch in closed form: every crank at phi, the coupler level.
  auto state = [&](double phi, double w) {
    std::vector<double> x(P::kNx, 0.0);
    auto set = [&](const std::string& n, double v) { x[static_cast<std::size_t>(index_of(P::kStateNames, P::kNx, n))] = v; };
    const double c = std::cos(phi), s = std::sin(phi);
    for (int i = 0; i < 3; ++i) {
      const std::string b = "crank" + std::to_string(i + 1);
      set(b + ".x", i * L + a / 2 * c);
      set(b + ".y", a / 2 * s);
      set(b + ".theta", phi);
      set(b + ".u", -a / 2 * s * w);
      set(b + ".v", a / 2 * c * w);
      set(b + ".w", w);
    }
    set("coupler.x", L + a * c);
    set("coupler.y", a * s);
    set("coupler.u", -a * s * w);
    set("coupler.v", a * c * w);
    return x;
  };
  const double phi0 = -1.0, w0 = 2.5;  // swings through horizontal cranks, about 80 degrees each way
  const std::vector<double> x0 = state(phi0, w0);
  // The pendulum phi'' = -K cos(phi) on its own, by the same method at a tighter tolerance.
  mbsc::runtime::StepperOptions so;
  so.rtol = 1e-13;
  so.atol = 1e-15;
  mbsc::runtime::Dop853 pendulum(
      [K](double, const double* s, double* d) {
        d[0] = s[1];
        d[1] = -K * std::cos(s[0]);
        return 0;
      },
      2, so);
  REQUIRE(pendulum.reset(0.0, {phi0, w0}) == mbsc::runtime::Stepper::Status::Ok);
  while (pendulum.t() < 10.0) REQUIRE(pendulum.step(10.0) == mbsc::runtime::Stepper::Status::Ok);
  const std::vector<double> y = pendulum.x();
  const auto pt = MBSC_MODEL_TABLE(P), pmt = MBSC_MODEL_TABLE_MULTIPLIERS(PM);
  for (const auto* table : {&pt, &pmt}) {
    const auto r = run(*table, x0, 10.0, 1e-11);
    WARN("parallelogram, 10 s, " << (table->multipliers ? "multipliers" : "complement") << ": energy "
                                  << r.energy_relative_drift << ", residual " << r.max_position_residual << ", " << r.rhs_evals
                                  << " rhs; against the pendulum " << largest_difference(r.x, state(y[0], y[1])));
    CHECK(r.energy_relative_drift < 1e-9);
    CHECK(r.max_position_residual < 1e-9);
    const std::vector<double> exact = state(y[0], y[1]);
    INFO("closed-form state at t = 10: phi = " << y[0] << ", phi' = " << y[1]);
    CHECK(largest_difference(r.x, exact) < 1e-7);
  }
}
