// SPDX-License-Identifier: GPL-2.0-or-later
// Closed loops (four-bar, five-bar with motors): at random consistent states,
//  - B C = 0 at every subsystem and A S = 0 for the whole tree (complements are right);
//  - the generated rhs equals an un-CSE'd GiNaC evaluation of the same equations.
#include <catch2/catch.hpp>
#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "five_bar/five_bar.hpp"
#include "four_bar/four_bar.hpp"
#include "mbsc/driver/pipeline.hpp"
#include "mbsc/sym/full_complement.hpp"
#include "test_support.hpp"

using mbsc_test::index_of;

namespace {

using Fn = int (*)(double, const double*, const double*, const double*, double*);
struct Generated;
std::vector<double> nominal_guess(const std::string& file, const Generated& g);

struct Generated {
  Fn rhs, position_constraints, velocity_constraints, constraint_jacobian;
  const char* const* state_names;
  const char* const* dof_names;
  int nq, nu, nc, nposc, nin;
  const double* params;
};

/// Newton on the position constraints for the coordinates not in `fixed`
/// (finite-difference Jacobian), then the velocity constraints for the speeds not in
/// `fixed_speeds`. Returns a state satisfying all constraints to ~1e-13.
std::vector<double> consistent_state(const Generated& g, std::vector<double> x, const std::vector<int>& fixed,
                                     const std::vector<int>& fixed_speeds) {
  std::vector<int> free_q;
  for (int i = 0; i < g.nq; ++i)
    if (std::find(fixed.begin(), fixed.end(), i) == fixed.end()) free_q.push_back(i);
  std::vector<double> u(std::max(1, g.nin), 0.0);
  std::vector<double> r(g.nposc), r2(g.nposc);
  for (int it = 0; it < 60; ++it) {
    REQUIRE(g.position_constraints(0.0, x.data(), u.data(), g.params, r.data()) == 0);
    Eigen::Map<Eigen::VectorXd> rv(r.data(), g.nposc);
    if (rv.norm() < 1e-14) break;
    Eigen::MatrixXd J(g.nposc, free_q.size());
    for (size_t k = 0; k < free_q.size(); ++k) {
      const double h = 1e-7;
      std::vector<double> xp = x, xm = x;
      xp[free_q[k]] += h;
      xm[free_q[k]] -= h;
      g.position_constraints(0.0, xp.data(), u.data(), g.params, r2.data());
      std::vector<double> rm(g.nposc);
      g.position_constraints(0.0, xm.data(), u.data(), g.params, rm.data());
      for (int i = 0; i < g.nposc; ++i) J(i, k) = (r2[i] - rm[i]) / (2 * h);
    }
    Eigen::VectorXd dx = J.colPivHouseholderQr().solve(-rv);
    for (size_t k = 0; k < free_q.size(); ++k) x[free_q[k]] += dx(k);
  }
  // Velocity constraints are affine in the speeds: A v + r0 = 0.
  std::vector<double> A(g.nc * g.nu), rv0(g.nc);
  std::vector<int> free_u;
  for (int j = 0; j < g.nu; ++j)
    if (std::find(fixed_speeds.begin(), fixed_speeds.end(), j) == fixed_speeds.end()) {
      free_u.push_back(j);
      x[g.nq + j] = 0.0;
    }
  REQUIRE(g.constraint_jacobian(0.0, x.data(), u.data(), g.params, A.data()) == 0);
  REQUIRE(g.velocity_constraints(0.0, x.data(), u.data(), g.params, rv0.data()) == 0);
  Eigen::MatrixXd Af(g.nc, free_u.size());
  for (int i = 0; i < g.nc; ++i)
    for (size_t k = 0; k < free_u.size(); ++k) Af(i, k) = A[i * g.nu + free_u[k]];
  Eigen::VectorXd v = Af.colPivHouseholderQr().solve(-Eigen::Map<Eigen::VectorXd>(rv0.data(), g.nc));
  for (size_t k = 0; k < free_u.size(); ++k) x[g.nq + free_u[k]] = v(k);
  REQUIRE(g.velocity_constraints(0.0, x.data(), u.data(), g.params, rv0.data()) == 0);
  REQUIRE(Eigen::Map<Eigen::VectorXd>(rv0.data(), g.nc).norm() < 1e-10);
  return x;
}

/// Numeric values of every symbol at state x, with the numeric solves of the tree
/// evaluated (by Eigen) in order: an evaluation path independent of the generated code.
struct Evaluator {
  const mbsc::model::Model& m;
  const mbsc::sym::Eom& eom;
  GiNaC::exmap vals;
  double eval(const GiNaC::ex& e) const {
    GiNaC::ex v = GiNaC::evalf(mbsc::driver::finalize(m, eom, e).subs(vals));
    REQUIRE(GiNaC::is_a<GiNaC::numeric>(v));
    return GiNaC::ex_to<GiNaC::numeric>(v).to_double();
  }
  Evaluator(const mbsc::model::Model& model, const mbsc::sym::Eom& e, const std::vector<double>& x, const double* params)
      : m(model), eom(e) {
    vals[m.time] = 0.0;
    for (size_t i = 0; i < m.coords.size(); ++i) vals[m.coords[i].sym] = x[i];
    for (size_t j = 0; j < m.speeds.size(); ++j) vals[m.speeds[j].sym] = x[m.coords.size() + j];
    for (const auto& in : m.inputs) vals[in.sym] = 0.0;
    for (size_t k = 0; k < eom.free_params.size(); ++k) vals[m.params[eom.free_params[k]].sym] = params[k];
    for (const auto& step : eom.pre_steps) {
      if (const auto* d = std::get_if<mbsc::ir::Define>(&step)) {
        vals[d->sym] = eval(d->value);
        continue;
      }
      const auto& s = std::get<mbsc::ir::Solve>(step);
      Eigen::MatrixXd A(s.n, s.n), B(s.n, s.k);
      for (int i = 0; i < s.n; ++i) {
        for (int j = 0; j < s.n; ++j) A(i, j) = eval(s.A[i * s.n + j]);
        for (int j = 0; j < s.k; ++j) B(i, j) = eval(s.B[i * s.k + j]);
      }
      Eigen::MatrixXd X = A.fullPivLu().solve(B);
      for (int i = 0; i < s.n; ++i)
        for (int j = 0; j < s.k; ++j) vals[s.X[i * s.k + j]] = X(i, j);
    }
  }
};

void check_model(const std::string& file, const Generated& g, const std::vector<std::string>& fixed_coords, unsigned seed) {
  mbsc::Diagnostics diags;
  auto m = mbsc::driver::load_model(std::string(MBSC_SOURCE_DIR) + "/models/" + file, diags);
  REQUIRE(m);
  auto eom = mbsc::sym::derive(*m, {}, diags);
  INFO(diags.format());
  REQUIRE(eom);
  REQUIRE(static_cast<int>(m->coords.size()) == g.nq);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.15, 0.15), speed(-2.0, 2.0);
  for (int trial = 0; trial < 5; ++trial) {
    // Start from the model's reference guess (the test's nominal configuration), perturbed.
    std::vector<double> x(g.nq + g.nu, 0.0);
    std::vector<int> fixed, fixed_speeds;
    for (const auto& name : fixed_coords) fixed.push_back(index_of(g.state_names, g.nq + g.nu, name));
    for (int k = 0; k < eom->ndof(); ++k) fixed_speeds.push_back(index_of(g.state_names, g.nq + g.nu, g.dof_names[k]) - g.nq);
    x = nominal_guess(file, g);
    for (int i : fixed) x[i] += jitter(rng);
    for (int j : fixed_speeds) x[g.nq + j] = speed(rng);
    x = consistent_state(g, x, fixed, fixed_speeds);
    Evaluator ev(*m, *eom, x, g.params);
    // B C = 0 at every subsystem with constraints.
    for (const auto& r : eom->nodes) {
      if (r.rows.empty()) continue;
      GiNaC::matrix BC = r.B.mul(r.C.get());
      for (unsigned i = 0; i < BC.rows(); ++i)
        for (unsigned j = 0; j < BC.cols(); ++j) CHECK(std::abs(ev.eval(BC(i, j))) < 1e-9);
    }
    // A S = 0 over the whole tree, with A from the generated constraint Jacobian.
    std::vector<int> rows;
    GiNaC::matrix S = mbsc::sym::full_complement(*m, *eom, m->root(), rows);
    REQUIRE(static_cast<int>(rows.size()) == g.nu);
    std::vector<double> A(g.nc * g.nu);
    std::vector<double> u(std::max(1, g.nin), 0.0);
    REQUIRE(g.constraint_jacobian(0.0, x.data(), u.data(), g.params, A.data()) == 0);
    Eigen::MatrixXd An = Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(A.data(), g.nc, g.nu);
    Eigen::MatrixXd Sn(g.nu, S.cols());
    for (int i = 0; i < g.nu; ++i)
      for (unsigned j = 0; j < S.cols(); ++j) Sn(rows[i], j) = ev.eval(S(i, j));
    CHECK((An * Sn).norm() < 1e-9 * std::max(1.0, Sn.norm()));
    CHECK(Sn.fullPivLu().rank() == eom->ndof());
    // Generated rhs against the GiNaC evaluation: solve M z' = h, then the dependent rates top-down.
    const int nd = eom->ndof();
    Eigen::MatrixXd M(nd, nd);
    Eigen::VectorXd h(nd);
    for (int i = 0; i < nd; ++i) {
      for (int j = 0; j < nd; ++j) M(i, j) = ev.eval(eom->M(i, j));
      h(i) = ev.eval(eom->h(i, 0));
    }
    CHECK((M - M.transpose()).norm() < 1e-10 * M.norm());
    Eigen::VectorXd z = M.fullPivLu().solve(h);
    for (int i = 0; i < nd; ++i) ev.vals[m->speed_dots[eom->independent[i]]] = z(i);
    for (const auto& d : eom->top_down) ev.vals[d.sym] = ev.eval(d.value);
    std::vector<double> xd(g.nq + g.nu);
    REQUIRE(g.rhs(0.0, x.data(), u.data(), g.params, xd.data()) == 0);
    double scale = 1.0;
    for (int j = 0; j < g.nu; ++j) scale = std::max(scale, std::abs(xd[g.nq + j]));
    for (int j = 0; j < g.nu; ++j) {
      INFO("speed " << m->speeds[j].name);
      CHECK(std::abs(xd[g.nq + j] - ev.eval(m->speed_dots[j])) < 1e-9 * scale);
    }
    for (int i = 0; i < g.nq; ++i) CHECK(std::abs(xd[i] - ev.eval(m->coord_rates[i])) < 1e-12 * scale);
  }
}

// Nominal configurations near which the tests assemble random consistent states.
std::vector<double> nominal_guess(const std::string& file, const Generated& g) {
  std::vector<double> x(g.nq + g.nu, 0.0);
  auto set = [&](const char* n, double v) { x[index_of(g.state_names, g.nq + g.nu, n)] = v; };
  if (file == "four_bar.mbs") {
    const double a = 0.3, b = 1.0, c = 0.8, d = 0.9;
    const double t1 = 1.2, t2 = 0.4, t3 = 1.9;  // rough closure
    set("crank.theta", t1);
    set("crank.x", a / 2 * std::cos(t1));
    set("crank.y", a / 2 * std::sin(t1));
    set("coupler.theta", t2);
    set("coupler.x", a * std::cos(t1) + b / 2 * std::cos(t2));
    set("coupler.y", a * std::sin(t1) + b / 2 * std::sin(t2));
    set("rocker.theta", t3);
    set("rocker.x", d + c / 2 * std::cos(t3));
    set("rocker.y", c / 2 * std::sin(t3));
  } else {
    const double s = 0.1, aU = 0.25, aB = 0.35;
    const double tl = 2.0, tr = 1.1, pl = 0.9, pr = 2.2;
    for (const char* side : {"left", "right"}) {
      const bool left = std::string(side) == "left";
      const double px = left ? -s : s, th = left ? tl : tr, ph = left ? pl : pr;
      const std::string pre = std::string("linkage.") + side + ".";
      set((pre + "theta").c_str(), th);
      set((pre + "phi").c_str(), ph);
      set((pre + "upper.x").c_str(), px + aU / 2 * std::cos(th));
      set((pre + "upper.y").c_str(), aU / 2 * std::sin(th));
      set((pre + "upper.theta").c_str(), th);
      set((pre + "lower.x").c_str(), px + aU * std::cos(th) + aB / 2 * std::cos(ph));
      set((pre + "lower.y").c_str(), aU * std::sin(th) + aB / 2 * std::sin(ph));
      set((pre + "lower.theta").c_str(), ph);
    }
    set("linkage.payload.x", -s + aU * std::cos(tl) + aB * std::cos(pl));
    set("linkage.payload.y", aU * std::sin(tl) + aB * std::sin(pl));
    set("linkage.chi", pr - pl);
  }
  return x;
}

}  // namespace

TEST_CASE("four-bar: complements annihilate the constraints, rhs equals the GiNaC evaluation", "[numeric][four_bar]") {
  namespace F = mbsc_gen::four_bar;
  REQUIRE(F::kNdof == 1);
  Generated g{F::rhs, F::position_constraints, F::velocity_constraints, F::constraint_jacobian, F::kStateNames,
              F::kDofNames, F::kNq, F::kNu, F::kNc, F::kNposc, F::kNin, F::kParamDefaults};
  check_model("four_bar.mbs", g, {"crank.theta"}, 11);
}

TEST_CASE("five-bar with DC motors: complements and rhs", "[numeric][five_bar]") {
  namespace F = mbsc_gen::five_bar;
  REQUIRE(F::kNdof == 4);
  Generated g{F::rhs, F::position_constraints, F::velocity_constraints, F::constraint_jacobian, F::kStateNames,
              F::kDofNames, F::kNq, F::kNu, F::kNc, F::kNposc, F::kNin, F::kParamDefaults};
  check_model("five_bar.mbs", g, {"linkage.left.theta", "linkage.right.theta"}, 12);
}
