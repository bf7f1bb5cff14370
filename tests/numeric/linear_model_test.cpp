// SPDX-License-Identifier: GPL-2.0-or-later
// The linear model (include/mbsc/runtime/linear_model.hpp, thesis section 4.5) checked
// three independent ways:
//  1. against central differences of the generated nonlinear rhs, at assembled references
//     that are not equilibria (non-zero speeds and accelerations), in both formulations
//     and against the --state minimal rhs;
//  2. against closed forms: the spherical pendulum (thesis Ex 4.6) and the ring with a
//     disc inside (thesis Ex 4.7), whose steady motion is found here by bisection;
//  3. with a redundant constraint (a parallelogram with a third crank), through the
//     least-squares path, against its non-redundant twin and the compound-pendulum closed form.
#include <catch2/catch.hpp>
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include "linear_model_support.hpp"

#include "dp_lin/dp_lin.hpp"
#include "five_bar_lin/five_bar_lin.hpp"
#include "four_bar_lin/four_bar_lin.hpp"
#include "four_bar_lin_min/four_bar_lin_min.hpp"
#include "four_bar_lin_mult/four_bar_lin_mult.hpp"
#include "heavy_top_lin/heavy_top_lin.hpp"
#include "parallelogram_redundant_lin/parallelogram_redundant_lin.hpp"
#include "parallelogram_twin_lin/parallelogram_twin_lin.hpp"
#include "ring_disc_joints_lin/ring_disc_joints_lin.hpp"
#include "ring_disc_lin/ring_disc_lin.hpp"
#include "ring_disc_lin_min/ring_disc_lin_min.hpp"
#include "ring_disc_lin_mult/ring_disc_lin_mult.hpp"
#include "rolling_disc_lin/rolling_disc_lin.hpp"
#include "rolling_disc_lin_mult/rolling_disc_lin_mult.hpp"
#include "slider_crank_lin/slider_crank_lin.hpp"
#include "slider_crank_lin_mult/slider_crank_lin_mult.hpp"
#include "sp_angles_lin/sp_angles_lin.hpp"
#include "sp_cart_lin/sp_cart_lin.hpp"
#include "sp_cart_lin_min/sp_cart_lin_min.hpp"
#include "sp_cart_lin_mult/sp_cart_lin_mult.hpp"
#include "sp_extra_lin/sp_extra_lin.hpp"
#include "whipple_joints_lin/whipple_joints_lin.hpp"

using lin_test::Gen;
using lin_test::Value;

namespace {

constexpr double kFdTolerance = 1e-6;

/// A consistent state of spherical_pendulum_extra_speed (r = 1) from (y, z, v, w): its
/// velocity constraint v2 = |v|^2 is not affine in the speeds, which assembly needs, so
/// every value is given here (x > 0 and u from the rod's invariants).
std::vector<Value> extra_speed_state(double y, double z, double v, double w) {
  const double x = std::sqrt(1 - y * y - z * z), u = -(y * v + z * w) / x;
  return {{"bob.x", x, true}, {"bob.y", y, true}, {"bob.z", z, true}, {"bob.u", u, true},
          {"bob.v", v, true}, {"bob.w", w, true}, {"v2", u * u + v * v + w * w, true}};
}

std::vector<double> defaults(const Gen& g) { return std::vector<double>(g.params, g.params + g.np); }
std::vector<double> inputs(const Gen& g, std::vector<double> u = {}) {
  u.resize(static_cast<std::size_t>(std::max(1, g.nin)), 0.0);
  return u;
}

/// Assemble, linearize, compare with the rhs's finite differences along the tangent space
/// (asserted), along every full-layout direction (asserted when `all_directions`) and
/// in the inputs. Prints the errors measured. Returns the reference and the model.
struct Checked {
  std::vector<double> x, u, p;
  mbsc::runtime::LinearModel lin;
};
Checked check_against_rhs(const Gen& g, const std::vector<Value>& values, std::vector<double> u_values,
                          bool all_directions) {
  Checked c;
  c.u = inputs(g, std::move(u_values));
  c.p = defaults(g);
  c.x = lin_test::assemble_reference(g, values, c.u, c.p);
  c.lin = lin_test::linear(g, c.x, c.u, c.p);
  const lin_test::FdReport r = lin_test::compare_with_rhs(g, c.lin, c.x, c.u, c.p);
  WARN(g.name << ": m = " << c.lin.m << ", constraint rank " << c.lin.constraint_rank << "/" << g.nc
                << "; FD relative error: tangent " << r.tangent << ", all directions " << r.full << ", inputs "
                << r.inputs);
  CHECK(r.tangent < kFdTolerance);
  if (all_directions) CHECK(r.full < kFdTolerance);
  CHECK(r.inputs < kFdTolerance);
  // The reference is not an equilibrium: some rate is far from zero.
  double largest_rate = 0.0;
  for (double e : c.lin.rates) largest_rate = std::max(largest_rate, std::fabs(e));
  CHECK(largest_rate > 1e-2);
  return c;
}

/// Eigenvalues of A on the tangent space, through the restriction to a minimal set of
/// components (preferred first), sorted by imaginary then real part.
std::vector<std::complex<double>> eigenvalues(const mbsc::runtime::LinearModel& lin, const std::vector<int>& preferred) {
  const std::vector<int> sel = mbsc::runtime::minimal_components(lin, preferred);
  std::vector<double> Am, Bm;
  REQUIRE(mbsc::runtime::restrict_to(lin, sel, Am, Bm));
  Eigen::MatrixXd M(lin.m, lin.m);
  for (int i = 0; i < lin.m; ++i)
    for (int j = 0; j < lin.m; ++j) M(i, j) = Am[static_cast<std::size_t>(i * lin.m + j)];
  Eigen::EigenSolver<Eigen::MatrixXd> es(M, false);
  std::vector<std::complex<double>> ev(es.eigenvalues().data(), es.eigenvalues().data() + lin.m);
  std::sort(ev.begin(), ev.end(), [](auto a, auto b) { return a.imag() != b.imag() ? a.imag() < b.imag() : a.real() < b.real(); });
  return ev;
}

/// Eigenvalues of the full-layout A (n x n).
std::vector<std::complex<double>> full_eigenvalues(const mbsc::runtime::LinearModel& lin) {
  Eigen::MatrixXd M(lin.n, lin.n);
  for (int i = 0; i < lin.n; ++i)
    for (int j = 0; j < lin.n; ++j) M(i, j) = lin.A[static_cast<std::size_t>(i * lin.n + j)];
  Eigen::EigenSolver<Eigen::MatrixXd> es(M, false);
  return std::vector<std::complex<double>>(es.eigenvalues().data(), es.eigenvalues().data() + lin.n);
}

/// |(I - V V^T) A V|: how far A maps the tangent space out of itself (zero at an
/// equilibrium; not in general, where the reference accelerates: the constraint manifold's
/// tangent space moves along the reference motion).
double leaves_tangent(const mbsc::runtime::LinearModel& lin) {
  double worst = 0.0;
  for (int k = 0; k < lin.m; ++k) {
    std::vector<double> Av = lin_test::times(lin.A, lin.n, lin.n, lin_test::column(lin.tangent, lin.n, lin.m, k));
    std::vector<double> r = Av;
    for (int l = 0; l < lin.m; ++l) {
      const std::vector<double> e = lin_test::column(lin.tangent, lin.n, lin.m, l);
      double d = 0.0;
      for (int i = 0; i < lin.n; ++i) d += e[static_cast<std::size_t>(i)] * Av[static_cast<std::size_t>(i)];
      for (int i = 0; i < lin.n; ++i) r[static_cast<std::size_t>(i)] -= d * e[static_cast<std::size_t>(i)];
    }
    worst = std::max(worst, lin_test::norm2(r) / std::max(1.0, lin_test::norm2(Av)));
  }
  return worst;
}

/// Every eigenvalue is 0 or +-i omega, each of these `pairs` times; the rest zero.
void check_spectrum(const std::vector<std::complex<double>>& ev, double omega, int pairs, double tol) {
  int plus = 0, minus = 0, zero = 0;
  for (auto e : ev) {
    INFO("eigenvalue " << e.real() << " + " << e.imag() << "i, expected 0 or +-" << omega << "i");
    if (std::abs(e - std::complex<double>(0.0, omega)) < tol * omega)
      ++plus;
    else if (std::abs(e - std::complex<double>(0.0, -omega)) < tol * omega)
      ++minus;
    else if (std::abs(e) < 1e-5 * omega)  // zeros of Jordan blocks (free coordinates) split by ~sqrt(eps)
      ++zero;
    else
      FAIL("unexpected eigenvalue");
  }
  CHECK(plus == pairs);
  CHECK(minus == pairs);
  CHECK(zero == static_cast<int>(ev.size()) - 2 * pairs);
}

double entry(const mbsc::runtime::LinearModel& lin, const Gen& g, const char* row, const char* col) {
  return lin.A[static_cast<std::size_t>(g.index(row) * lin.n + g.index(col))];
}

}  // namespace

// ---------------------------------------------------------------------------------------
// 1. Finite differences of the generated rhs.
//
// Complement form: the rhs solves A_c(q) q1' = -b(q, q1) and C(q)^T (My q1' - hy) = 0 at
// any state, on the constraint manifold or not. C(q)^T A_c(q)^T = 0 holds identically
// in q, so differentiating C^T (My q1' - hy) = C^T A_c^T lambda gives exactly the
// linear model's projected equations with the d(A_c^T lambda)/dx term, in every
// direction: where the constraints are independent, A equals the full Jacobian, not
// only on the tangent space, and that is asserted (`all_directions`).
// Multipliers form: the Baumgarte terms (2 alpha (A_c q1 + b_v) + beta^2 g) vanish to
// first order along the tangent space only, so only the tangent directions are compared.
// ---------------------------------------------------------------------------------------

TEST_CASE("linear model: A and B equal finite differences of the rhs, complement form", "[numeric][linear_model]") {
  SECTION("spherical pendulum, three forms") {
    check_against_rhs(LIN_GEN(mbsc_gen::sp_cart_lin),
                      {{"bob.x", 0.8, false}, {"bob.y", 0.5, true}, {"bob.z", 0.3, true}, {"bob.v", 0.7, true}, {"bob.w", -0.4, true}},
                      {}, true);
    check_against_rhs(LIN_GEN(mbsc_gen::sp_extra_lin), extra_speed_state(0.5, 0.3, 0.7, -0.4), {}, true);
    check_against_rhs(LIN_GEN(mbsc_gen::sp_angles_lin),
                      {{"theta", 0.9, true}, {"phi", 0.4, true}, {"dtheta", 0.5, true}, {"dphi", -0.8, true}}, {}, true);
  }
  SECTION("ring and disc, invariant level and library joints") {
    check_against_rhs(LIN_GEN(mbsc_gen::ring_disc_lin), {{"theta", 0.9, true}, {"dtheta", 0.6, true}, {"D.w", -1.1, true}}, {}, true);
    check_against_rhs(LIN_GEN(mbsc_gen::ring_disc_joints_lin),
                      {{"R.x", 0.1, true}, {"R.theta", 0.2, true}, {"D.x", 0.3, false}, {"D.theta", 0.5, true},
                       {"R.y", 1.0, false}, {"D.y", 0.4, false}, {"R.w", 0.6, true}, {"D.w", -1.1, true}},
                      {}, true);
  }
  SECTION("planar loops") {
    check_against_rhs(LIN_GEN(mbsc_gen::four_bar_lin),
                      {{"crank.theta", 1.0, true}, {"coupler.theta", 0.3, false}, {"rocker.theta", 1.5, false}, {"crank.w", 3.0, true}},
                      {}, true);
    check_against_rhs(LIN_GEN(mbsc_gen::slider_crank_lin),
                      {{"crank.theta", 0.7, true}, {"rod.theta", -0.3, false}, {"slider.x", 0.4, false}, {"crank.w", 5.0, true}},
                      {0.3, -0.2}, true);
    check_against_rhs(LIN_GEN(mbsc_gen::five_bar_lin),
                      {{"linkage.left.theta", -2.0, true}, {"linkage.right.theta", -1.1, true}, {"linkage.left.phi", -0.9, false},
                       {"linkage.right.phi", -2.2, false}, {"linkage.left.dtheta", 2.0, true}, {"linkage.right.dtheta", -1.0, true},
                       {"motor_left.i", 0.2, true}, {"motor_right.i", -0.1, true}},
                      {1.5, -0.7}, true);
    check_against_rhs(LIN_GEN(mbsc_gen::dp_lin), {{"th1", 0.5, true}, {"th2", -0.3, true}, {"w1", 0.8, true}, {"w2", -1.2, true}}, {},
                      true);
  }
  SECTION("spatial: heavy top, rolling disc, Whipple bicycle") {
    const double n = std::sqrt(0.9 * 0.9 + 0.2 * 0.2 + 0.3 * 0.3 + 0.1 * 0.1);
    check_against_rhs(LIN_GEN(mbsc_gen::heavy_top_lin),
                      {{"top.e0", 0.9 / n, true}, {"top.e1", 0.2 / n, true}, {"top.e2", 0.3 / n, true}, {"top.e3", 0.1 / n, true},
                       {"top.z", 0.1, false}, {"top.wx", 0.4, true}, {"top.wy", -0.3, true}, {"top.wz", 30.0, true}},
                      {}, true);
    const double k = std::sqrt(0.65 * 0.65 + 0.7 * 0.7 + 0.2 * 0.2 + 0.1 * 0.1);
    check_against_rhs(LIN_GEN(mbsc_gen::rolling_disc_lin),
                      {{"disc.e0", 0.65 / k, true}, {"disc.e1", -0.7 / k, true}, {"disc.e2", 0.2 / k, true}, {"disc.e3", 0.1 / k, true},
                       {"disc.z", 0.3, false}, {"disc.wx", 0.3, true}, {"disc.wy", -0.2, true}, {"disc.wz", 5.0, true}},
                      {}, true);
    const double rR = 0.3, rF = 0.35;
    check_against_rhs(LIN_GEN(mbsc_gen::whipple_joints_lin),
                      {{"rear_wheel.x", 0, true},       {"rear_wheel.y", 0, true},      {"rear_wheel.z", -rR, false},
                       {"rear_frame.x", 0.3, false},    {"rear_frame.y", 0, false},     {"rear_frame.z", -0.9, false},
                       {"front_frame.x", 0.9, false},   {"front_frame.y", 0, false},    {"front_frame.z", -0.7, false},
                       {"front_wheel.x", 1.02, false},  {"front_wheel.y", 0, false},    {"front_wheel.z", -rF, false},
                       {"rear_frame.phi", 0.1, true},   {"rear_frame.theta", 0, false}, {"rear_frame.psi", 0.2, true},
                       {"theta_R", 0.3, true},          {"delta", 0.2, true},           {"theta_F", -0.4, true},
                       {"theta_R_dot", -5 / rR, true},  {"rear_frame.wx", 0.5, true},   {"delta_dot", 0.3, true}},
                      {}, true);
  }
}

TEST_CASE("linear model: multipliers form against its rhs on the tangent space, and equal to the complement form's",
          "[numeric][linear_model]") {
  // The linear model is formed from the dependent-coordinate equations, the same in both
  // formulations: at the same reference, A and B must be the same matrices.
  auto same = [](const Checked& a, const Checked& b) {
    REQUIRE(a.lin.A.size() == b.lin.A.size());
    double scale = 1.0, diff = 0.0;
    for (std::size_t i = 0; i < a.lin.A.size(); ++i)
      scale = std::max(scale, std::fabs(a.lin.A[i])), diff = std::max(diff, std::fabs(a.lin.A[i] - b.lin.A[i]));
    for (std::size_t i = 0; i < a.lin.B.size(); ++i) diff = std::max(diff, std::fabs(a.lin.B[i] - b.lin.B[i]));
    CHECK(diff < 1e-10 * scale);
  };
  const std::vector<Value> sp{{"bob.x", 0.8, false}, {"bob.y", 0.5, true}, {"bob.z", 0.3, true}, {"bob.v", 0.7, true}, {"bob.w", -0.4, true}};
  same(check_against_rhs(LIN_GEN(mbsc_gen::sp_cart_lin_mult), sp, {}, false), check_against_rhs(LIN_GEN(mbsc_gen::sp_cart_lin), sp, {}, true));
  const std::vector<Value> rd{{"theta", 0.9, true}, {"dtheta", 0.6, true}, {"D.w", -1.1, true}};
  same(check_against_rhs(LIN_GEN(mbsc_gen::ring_disc_lin_mult), rd, {}, false), check_against_rhs(LIN_GEN(mbsc_gen::ring_disc_lin), rd, {}, true));
  const std::vector<Value> fb{{"crank.theta", 1.0, true}, {"coupler.theta", 0.3, false}, {"rocker.theta", 1.5, false}, {"crank.w", 3.0, true}};
  same(check_against_rhs(LIN_GEN(mbsc_gen::four_bar_lin_mult), fb, {}, false), check_against_rhs(LIN_GEN(mbsc_gen::four_bar_lin), fb, {}, true));
  const std::vector<Value> sc{{"crank.theta", 0.7, true}, {"rod.theta", -0.3, false}, {"slider.x", 0.4, false}, {"crank.w", 5.0, true}};
  same(check_against_rhs(LIN_GEN(mbsc_gen::slider_crank_lin_mult), sc, {0.3, -0.2}, false),
       check_against_rhs(LIN_GEN(mbsc_gen::slider_crank_lin), sc, {0.3, -0.2}, true));
  const double k = std::sqrt(0.65 * 0.65 + 0.7 * 0.7 + 0.2 * 0.2 + 0.1 * 0.1);
  const std::vector<Value> rl{{"disc.e0", 0.65 / k, true}, {"disc.e1", -0.7 / k, true}, {"disc.e2", 0.2 / k, true},
                              {"disc.e3", 0.1 / k, true},  {"disc.z", 0.3, false},      {"disc.wx", 0.3, true},
                              {"disc.wy", -0.2, true},     {"disc.wz", 5.0, true}};
  same(check_against_rhs(LIN_GEN(mbsc_gen::rolling_disc_lin_mult), rl, {}, false),
       check_against_rhs(LIN_GEN(mbsc_gen::rolling_disc_lin), rl, {}, true));
}

TEST_CASE("linear model: the --state minimal rhs agrees with the full-layout model", "[numeric][linear_model]") {
  auto run = [](const Gen& full, const Gen& minimal, const std::vector<Value>& values) {
    const Checked c = check_against_rhs(full, values, {}, true);
    const double err = lin_test::compare_minimal(minimal, c.lin, c.x, c.u, c.p);
    WARN(minimal.name << ": " << minimal.nx << " state components, m = " << c.lin.m << "; FD relative error " << err);
    CHECK(err < kFdTolerance);
  };
  run(LIN_GEN(mbsc_gen::sp_cart_lin), LIN_GEN(mbsc_gen::sp_cart_lin_min),
      {{"bob.x", 0.8, false}, {"bob.y", 0.5, true}, {"bob.z", 0.3, true}, {"bob.v", 0.7, true}, {"bob.w", -0.4, true}});
  run(LIN_GEN(mbsc_gen::four_bar_lin), LIN_GEN(mbsc_gen::four_bar_lin_min),
      {{"crank.theta", 1.0, true}, {"coupler.theta", 0.3, false}, {"rocker.theta", 1.5, false}, {"crank.w", 3.0, true}});
  run(LIN_GEN(mbsc_gen::ring_disc_lin), LIN_GEN(mbsc_gen::ring_disc_lin_min),
      {{"theta", 0.9, true}, {"dtheta", 0.6, true}, {"D.w", -1.1, true}});
}

// ---------------------------------------------------------------------------------------
// 2. Closed forms.
//
// Spherical pendulum (thesis Ex 4.6), gravity g along +x, rod r, at rest at p0: the
// acceleration is a = g x^ + lambda p with lambda fixed by the invariant p.a + v.v = 0.
// At rest lambda0 = -g x0 / r^2 and a0 = g x^ - g x0 p0 / r^2. Linearized: the invariant
// gives dp.a0 + p0.da = 0, the projected dynamics (I - p0 p0^T/r^2)(da - lambda0 dp) = 0,
// so da = lambda0 dp + mu p0 with mu r^2 = -dp.a0 - lambda0 p0.dp. At the bottom
// (p0 = r x^) this is da = -(g/r)(0, dy, dz): two oscillators sqrt(g/r). At
// p0 = (4/5, 3/5, 0) r it is the thesis's matrix (k):
//   du' = g/r (-72/125 dx + 96/125 dy), dv' = g/r (21/125 dx - 28/125 dy), dw' = -4g/(5r) dz,
// and with the extra speed v2 = |v|^2: dv2' = 2 a0.dv = 18g/25 du - 24g/25 dv. On the
// tangent space (4 dx + 3 dy = 0) the eigenvalues are +-i sqrt(4g/(5r)) twice. In the
// angles form (x = r cos theta) the same point is theta0 = acos(4/5), phi = 0, where
// theta'' = -(g/r) sin theta + sin theta cos theta phi'^2 and phi'' = -2 cot theta theta' phi'
// linearize at rest to dtheta'' = -(g/r) cos theta0 dtheta, dphi'' = 0: +-i sqrt(4g/(5r))
// and a double zero. The bottom (theta = 0) is a singular point of the angles.
// ---------------------------------------------------------------------------------------

TEST_CASE("linear model: spherical pendulum closed forms (thesis Ex 4.6)", "[numeric][linear_model]") {
  const Gen cart = LIN_GEN(mbsc_gen::sp_cart_lin), extra = LIN_GEN(mbsc_gen::sp_extra_lin), angles = LIN_GEN(mbsc_gen::sp_angles_lin);
  const std::vector<double> p = defaults(cart), u = inputs(cart);
  const double r = p[static_cast<std::size_t>(mbsc_test::index_of(mbsc_gen::sp_cart_lin::kParamNames, cart.np, "r"))];
  const double g = p[static_cast<std::size_t>(mbsc_test::index_of(mbsc_gen::sp_cart_lin::kParamNames, cart.np, "g"))];
  REQUIRE(r == 1.0);  // extra_speed_state's unit rod
  SECTION("at the bottom at rest: +-i sqrt(g/r) twice (Cartesian forms); the angles are singular there") {
    for (const Gen& G : {cart, extra}) {
      const std::vector<double> x = lin_test::assemble_reference(G, G.nu == 4 ? extra_speed_state(0, 0, 0, 0) : std::vector<Value>{
          {"bob.x", r, true}, {"bob.y", 0, true}, {"bob.z", 0, true}, {"bob.v", 0, true}, {"bob.w", 0, true}}, u, p);
      const auto lin = lin_test::linear(G, x, u, p);
      CHECK(lin.m == 4);
      CHECK(leaves_tangent(lin) < 1e-12);  // an equilibrium: the minimal realization is well defined
      check_spectrum(eigenvalues(lin, {G.index("bob.y"), G.index("bob.z"), G.index("bob.v"), G.index("bob.w")}), std::sqrt(g / r), 2, 1e-9);
    }
    std::vector<double> x = lin_test::assemble_reference(angles, {{"theta", 0, true}, {"phi", 0.3, true}, {"dtheta", 0, true}, {"dphi", 0, true}}, u, p);
    mbsc::runtime::LinearModel lin;
    std::string why;
    CHECK(mbsc::runtime::linear_model(angles.parts, 0.0, x.data(), u.data(), p.data(), lin, why) == 1);
    CHECK(why.find("singular") != std::string::npos);
  }
  SECTION("at (4/5, 3/5, 0) r at rest: the thesis's matrix (k)") {
    const double w2 = 4.0 * g / (5.0 * r);
    for (const Gen& G : {cart, extra}) {
      const std::vector<double> x = lin_test::assemble_reference(G, G.nu == 4 ? extra_speed_state(0.6, 0, 0, 0) : std::vector<Value>{
          {"bob.x", 0.8 * r, true}, {"bob.y", 0.6 * r, true}, {"bob.z", 0, true}, {"bob.v", 0, true}, {"bob.w", 0, true}}, u, p);
      const auto lin = lin_test::linear(G, x, u, p);
      const double tol = 1e-12 * g / r;
      CHECK(std::fabs(entry(lin, G, "bob.u", "bob.x") - (-72.0 / 125.0) * g / r) < tol);
      CHECK(std::fabs(entry(lin, G, "bob.u", "bob.y") - (96.0 / 125.0) * g / r) < tol);
      CHECK(std::fabs(entry(lin, G, "bob.u", "bob.z")) < tol);
      CHECK(std::fabs(entry(lin, G, "bob.v", "bob.x") - (21.0 / 125.0) * g / r) < tol);
      CHECK(std::fabs(entry(lin, G, "bob.v", "bob.y") - (-28.0 / 125.0) * g / r) < tol);
      CHECK(std::fabs(entry(lin, G, "bob.v", "bob.z")) < tol);
      CHECK(std::fabs(entry(lin, G, "bob.w", "bob.z") - (-4.0 / 5.0) * g / r) < tol);
      CHECK(std::fabs(entry(lin, G, "bob.w", "bob.x")) < tol);
      for (const char* row : {"bob.u", "bob.v", "bob.w"})
        for (const char* col : {"bob.u", "bob.v", "bob.w"}) CHECK(std::fabs(entry(lin, G, row, col)) < tol);
      if (G.nu == 4) {
        CHECK(std::fabs(entry(lin, G, "v2", "bob.u") - 18.0 / 25.0 * g) < 1e-12 * g);
        CHECK(std::fabs(entry(lin, G, "v2", "bob.v") - (-24.0 / 25.0) * g) < 1e-12 * g);
        CHECK(std::fabs(entry(lin, G, "v2", "bob.w")) < 1e-12 * g);
      }
      // The thesis's eigenvalues are those of (k), the full-layout A here: +-i sqrt(4g/5r)
      // twice and a double zero (the radial direction). The reference is not an
      // equilibrium (it accelerates along the sphere), A does not keep the tangent space
      // (leaves_tangent > 0), and a 4 x 4 restriction's eigenvalues depend on the
      // components chosen: (y, z, v, w) gives +-i sqrt(0.35 g/r) and +-i sqrt(4g/5r),
      // (x, z, u, w) +-i sqrt(1.6 g/r) and +-i sqrt(4g/5r); neither is the thesis's.
      check_spectrum(full_eigenvalues(lin), std::sqrt(w2), 2, 1e-7);
      CHECK(leaves_tangent(lin) > 1e-3);
    }
    const std::vector<double> x =
        lin_test::assemble_reference(angles, {{"theta", std::acos(0.8), true}, {"phi", 0, true}, {"dtheta", 0, true}, {"dphi", 0, true}}, u, p);
    const auto lin = lin_test::linear(angles, x, u, p);
    // In the angles (the model's own minimal state): d/dt (dtheta, dphi, dtheta', dphi') =
    // [0 0 1 0; 0 0 0 1; -4g/5r 0 0 0; 0 0 0 0] (...).
    std::vector<double> Am, Bm;
    REQUIRE(mbsc::runtime::restrict_to(lin, {angles.index("theta"), angles.index("phi"), angles.index("dtheta"), angles.index("dphi")}, Am, Bm));
    const std::vector<double> closed{0, 0, 1, 0, 0, 0, 0, 1, -w2, 0, 0, 0, 0, 0, 0, 0};
    for (std::size_t i = 0; i < 16; ++i) {
      INFO("entry " << i << ": " << Am[i] << ", closed form " << closed[i]);
      CHECK(std::fabs(Am[i] - closed[i]) < 1e-12 * w2);
    }
    check_spectrum(eigenvalues(lin, {angles.index("theta"), angles.index("phi"), angles.index("dtheta"), angles.index("dphi")}),
                   std::sqrt(w2), 1, 1e-9);
  }
}

// Ring and disc (thesis Ex 4.2 / 4.7). Steady motion: theta = T constant, both bodies
// rolling down the incline (angle X) with the same acceleration; the thesis's relation
// m2/m1 = sin T / (2 sin X cos(T - X) - 3 sin T + sin X) - 1 is solved for T by bisection.
// At theta = T with every speed zero, the linear model's speed rows have non-zero entries
// only in the theta column; the thesis gives the six in closed form (G below, with
// s/c = sin/cos, T = theta_bar, X = xi), and the oscillation about the steady motion has
// omega = sqrt(-G_{dtheta,theta}).
TEST_CASE("linear model: ring and disc closed forms (thesis Ex 4.7)", "[numeric][linear_model]") {
  const Gen rd = LIN_GEN(mbsc_gen::ring_disc_lin);
  namespace RD = mbsc_gen::ring_disc_lin;
  const std::vector<double> p = defaults(rd), u = inputs(rd);
  auto par = [&](const char* n) { return p[static_cast<std::size_t>(mbsc_test::index_of(RD::kParamNames, RD::kNp, n))]; };
  const double m1 = par("m1"), m2 = par("m2"), r1 = par("r1"), r2 = par("r2"), g = par("g"), X = par("xi");
  auto relation = [&](double T) { return std::sin(T) / (2 * std::sin(X) * std::cos(T - X) - 3 * std::sin(T) + std::sin(X)) - 1 - m2 / m1; };
  double lo = 0.5, hi = 0.8;
  REQUIRE(relation(lo) < 0);
  REQUIRE(relation(hi) > 0);
  for (int i = 0; i < 200 && hi - lo > 1e-16; ++i) (relation(0.5 * (lo + hi)) < 0 ? lo : hi) = 0.5 * (lo + hi);
  const double T = 0.5 * (lo + hi);
  CHECK(std::fabs(T - std::asin(0.6)) < 1e-12);  // the thesis's data make theta_bar = asin(3/5)
  const double s = std::sin(T), c = std::cos(T), sX = std::sin(X), cX = std::cos(X);
  auto S = [](double a) { return std::sin(a); };
  const double k = c + 2 * cX, e = 2 * std::cos(T - X) + 1;
  const double D = 2 * s + 3 * S(2 * T - X) - 2 * sX + 2 * S(T - 2 * X) + S(2 * T - 3 * X);
  const double G_u1 = 2 * g * k * (3 * s - sX + S(T - 2 * X)) /
                      (3 * s + 5 * S(2 * T - X) - 2 * sX + 5 * S(T - 2 * X) + 3 * S(3 * T - 2 * X) + 3 * S(2 * T - 3 * X) + S(3 * T - 4 * X));
  const double G_w1 = -G_u1 / r1;
  const double G_u2 = g * k * (3 * s + 5 * (S(2 * T - X) + S(T - 2 * X)) + 3 * S(2 * T - 3 * X)) / (e * e * D);
  const double G_v2 = g * k * sX / (e * (3 * c + 2 * cX + std::cos(T - 2 * X)));
  const double G_w2 = -2 * g * k * (s + 3 * (S(2 * T - X) + S(T - 2 * X)) + S(2 * T - 3 * X)) / (e * e * D * r2);
  const double G_th = 2 * g * k * sX / (e * D * (r1 - r2));
  const double omega = std::sqrt(-G_th);

  const std::vector<double> x = lin_test::assemble_reference(rd, {{"theta", T, true}, {"dtheta", 0, true}, {"D.w", 0, true}}, u, p);
  const auto lin = lin_test::linear(rd, x, u, p);
  const std::vector<std::pair<const char*, double>> expected{{"R.u", G_u1}, {"R.w", G_w1}, {"D.u", G_u2},
                                                             {"D.v", G_v2}, {"D.w", G_w2}, {"dtheta", G_th}};
  for (const auto& [row, value] : expected) {
    INFO(row << ": linear model " << entry(lin, rd, row, "theta") << ", closed form " << value);
    CHECK(std::fabs(entry(lin, rd, row, "theta") - value) < 1e-10 * std::fabs(value));
  }
  // Every other entry of the speed rows vanishes (R.v's row included).
  double others = 0.0;
  for (int i = RD::kNqFull; i < lin.n; ++i)
    for (int j = 0; j < lin.n; ++j)
      if (j != rd.index("theta")) others = std::max(others, std::fabs(lin.A[static_cast<std::size_t>(i * lin.n + j)]));
  CHECK(std::fabs(entry(lin, rd, "R.v", "theta")) < 1e-12 * g);
  CHECK(others < 1e-12 * g);
  // The eigenvalues on the tangent space: +-i omega and zeros.
  check_spectrum(eigenvalues(lin, {rd.index("theta"), rd.index("dtheta")}), omega, 1, 1e-9);

  SECTION("the library-joint model (other coordinates) has the same eigenvalues") {
    const Gen rj = LIN_GEN(mbsc_gen::ring_disc_joints_lin);
    const std::vector<double> pj = defaults(rj);
    // The disc's centre at angle T from the ring's normal (ring_disc_joints.mbs's start, theta = T).
    const std::vector<double> xj = lin_test::assemble_reference(
        rj, {{"R.x", 0, true}, {"R.theta", 0, true}, {"D.x", (r1 - r2) * std::sin(X - T), true}, {"D.theta", 0, false},
             {"R.y", r1, false}, {"D.y", r1 - (r1 - r2) * std::cos(X - T), false}, {"R.w", 0, true}, {"D.w", 0, true}},
        u, pj);
    const auto linj = lin_test::linear(rj, xj, u, pj);
    check_spectrum(eigenvalues(linj, {rj.index("D.x"), rj.index("D.u")}), omega, 1, 1e-9);
  }
}

// ---------------------------------------------------------------------------------------
// 3. Redundant constraints: a parallelogram with a third crank (tests/data/linear/).
// The coupler only translates, so both models are the compound pendulum
//   (m_crank + m_coupler) a^2 phi'' = -(3 m_crank/2 + m_coupler) g a cos(phi)
// (three cranks of inertia m_crank a^2/3 about their pivots, the coupler's mass moving
// with the crank tips): linearized about any (phi, phi'),
//   d(phi)' = d(phi'),  d(phi')' = K sin(phi) d(phi),  K = g (3 m_crank/2 + m_coupler) / ((m_crank + m_coupler) a),
// and about the hanging equilibrium phi = -pi/2, omega^2 = K.
// ---------------------------------------------------------------------------------------

TEST_CASE("linear model: redundant constraints through the least-squares path (parallelogram with a third crank)",
          "[numeric][linear_model]") {
  const Gen red = LIN_GEN(mbsc_gen::parallelogram_redundant_lin), twin = LIN_GEN(mbsc_gen::parallelogram_twin_lin);
  namespace PR = mbsc_gen::parallelogram_redundant_lin;
  REQUIRE(red.nc == 12);
  REQUIRE(twin.nc == 11);
  const std::vector<double> p = defaults(red), u = inputs(red);
  auto par = [&](const char* n) { return p[static_cast<std::size_t>(mbsc_test::index_of(PR::kParamNames, PR::kNp, n))]; };
  const double K = par("g") * (1.5 * par("m_crank") + par("m_coupler")) / ((par("m_crank") + par("m_coupler")) * par("a"));
  auto guesses = [](double phi, double rate) {
    return std::vector<Value>{{"crank1.theta", phi, true},     {"crank2.theta", phi + 0.05, false}, {"crank3.theta", phi - 0.05, false},
                              {"coupler.theta", 0.02, false},   {"coupler.x", 0.6, false},          {"coupler.y", -0.2, false},
                              {"crank1.w", rate, true}};
  };
  for (const auto& [phi, rate] : std::vector<std::pair<double, double>>{{-M_PI / 2, 0.0}, {-1.0, 1.3}, {0.4, -2.0}}) {
    INFO("phi = " << phi << ", phi' = " << rate);
    const std::vector<double> xr = lin_test::assemble_reference(red, guesses(phi, rate), u, p);
    const std::vector<double> xt = lin_test::assemble_reference(twin, guesses(phi, rate), u, p);
    const auto lr = lin_test::linear(red, xr, u, p);
    const auto lt = lin_test::linear(twin, xt, u, p);
    CHECK(lr.constraint_rank == 11);  // one row of twelve is redundant on the manifold
    CHECK(lr.invariant_residual < 1e-10);
    CHECK(lt.constraint_rank == 11);
    CHECK(lr.m == 2);
    CHECK(lt.m == 2);
    std::vector<double> Ar, At, Bm;
    REQUIRE(mbsc::runtime::restrict_to(lr, {red.index("crank1.theta"), red.index("crank1.w")}, Ar, Bm));
    REQUIRE(mbsc::runtime::restrict_to(lt, {twin.index("crank1.theta"), twin.index("crank1.w")}, At, Bm));
    const std::vector<double> closed{0.0, 1.0, K * std::sin(phi), 0.0};
    for (std::size_t i = 0; i < 4; ++i) {
      INFO("entry " << i << ": redundant " << Ar[i] << ", twin " << At[i] << ", closed form " << closed[i]);
      CHECK(std::fabs(Ar[i] - closed[i]) < 1e-10 * K);
      CHECK(std::fabs(At[i] - closed[i]) < 1e-10 * K);
    }
    // The whole motion agrees too: the same full-layout state and the same A on the tangent space.
    for (int j = 0; j < red.nx; ++j) CHECK(std::fabs(xr[static_cast<std::size_t>(j)] - xt[static_cast<std::size_t>(j)]) < 1e-10);
    if (phi == -M_PI / 2) check_spectrum(eigenvalues(lr, {red.index("crank1.theta"), red.index("crank1.w")}), std::sqrt(K), 1, 1e-9);
  }
  // Both rhs against finite differences. The redundant model's rhs solves its dependent
  // speeds in the least-squares sense (mbsc finds the redundancy at the assembled initial
  // state, docs/formulation.md "Redundant constraints"), and gives the twin's xdot.
  // Off the manifold (the full-layout directions) the redundant rows disagree and no
  // least-squares choice is the twin's, so only the tangent space is compared there.
  check_against_rhs(twin, guesses(-1.0, 1.3), {}, true);
  check_against_rhs(red, guesses(-1.0, 1.3), {}, false);
  const std::vector<double> xr = lin_test::assemble_reference(red, guesses(-1.0, 1.3), u, p);
  const std::vector<double> xt = lin_test::assemble_reference(twin, guesses(-1.0, 1.3), u, p);
  std::vector<double> dr(xr.size()), dt(xt.size());
  REQUIRE(red.rhs(0.0, xr.data(), u.data(), p.data(), dr.data()) == 0);
  REQUIRE(twin.rhs(0.0, xt.data(), u.data(), p.data(), dt.data()) == 0);
  for (std::size_t j = 0; j < dr.size(); ++j) CHECK(std::fabs(dr[j] - dt[j]) < 1e-10 * (1.0 + std::fabs(dt[j])));
}
