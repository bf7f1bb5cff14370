// SPDX-License-Identifier: GPL-2.0-or-later
// The 3-D slider-crank of thesis Ex 4.5 (models/slider_crank_3d.mbs) with its Coulomb
// friction x3* = -mu sign(v3x) |(y3*, z3*)| (thesis eq (b)) closed on the slider's normal
// force: the multipliers of the prismatic joint's rows guide.n1, guide.n2 (their
// gradients are the unit normals z and -y), affine in the friction input Ff, so the law
// is a quadratic in Ff solved exactly at each evaluation. Checked:
//  - 1 degree of freedom with the thesis's independent speed (the crank's rate);
//  - the closed-form kinematics from the thesis's invariants (d),
//    x2^2 = l2^2 - 2 l1^2 (1 - cos chi), satisfy every position and velocity row;
//  - complement and multipliers forms agree (1e-9) at random assembled states with the
//    friction closed, and the closed friction force satisfies the law;
//  - energy balance over a forward run: E(t) - E(0) = integral of (u1 w + Ff v) dt, the
//    friction's share negative (dissipated);
//  - the thesis's inverse dynamics with the prescribed slide (k): over one period of the
//    slide the actuator's work equals the energy friction dissipates, and u1 jumps where
//    the slider reverses (the discontinuity the thesis points out).
// Those close the law here on the reference model with the friction force as an input
// (tests/data/friction/slider_crank_3d_input.mbs). The shipped model's `friction mu` closes
// it in the generated code; checked against the reference:
//  - its rhs (complement, multipliers, --state minimal) equals the outside closure's;
//  - the force read back from its accelerations has |F| = mu |N| with its own N, opposes
//    v, and is 0 at rest; a jamming mu gives status 1, never NaN (but not at rest);
//  - E(t) - E(0) = integral of (u1 w - mu |N| |v|) dt over a run of its rhs alone.
#include <catch2/catch.hpp>
#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "mbsc/runtime/dop853.hpp"
#include "mbsc/runtime/inverse_dynamics.hpp"
#include "mbsc/runtime/model_table.hpp"
#include "slider_crank_3d/slider_crank_3d.hpp"
#include "slider_crank_3d_input/slider_crank_3d_input.hpp"
#include "slider_crank_3d_input_mult/slider_crank_3d_input_mult.hpp"
#include "slider_crank_3d_min/slider_crank_3d_min.hpp"
#include "slider_crank_3d_mult/slider_crank_3d_mult.hpp"
#include "test_support.hpp"

using mbsc_test::index_of;

namespace {

// The shipped model closes the friction itself (C, CM, CS); the reference R, RM takes the
// friction force as the input Ff (tests/data/friction/slider_crank_3d_input.mbs) and the
// law is closed here, outside the generated code.
namespace C = mbsc_gen::slider_crank_3d;
namespace CM = mbsc_gen::slider_crank_3d_mult;
namespace CS = mbsc_gen::slider_crank_3d_min;
namespace R = mbsc_gen::slider_crank_3d_input;
namespace RM = mbsc_gen::slider_crank_3d_input_mult;

double par(const char* n) { return C::kParamDefaults[index_of(C::kParamNames, C::kNp, n)]; }
const double l1 = par("l1"), l2 = par("l2"), g2 = par("gamma2"), mu = par("mu");
std::size_t ix(const char* n) { return static_cast<std::size_t>(index_of(C::kStateNames, C::kNx, n)); }

using V3 = std::array<double, 3>;
V3 cross(const V3& a, const V3& b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }

/// The assembled state at crank angle chi and rate w (rod roll angle theta is free: the
/// thesis's theta does not enter the motion).
std::vector<double> state(double chi, double w, double theta) {
  std::vector<double> x(static_cast<std::size_t>(C::kNx), 0.0);
  const double c = std::cos(chi), s = std::sin(chi);
  const V3 p1{0, -l1 * c, -l1 * s};
  const double x2 = std::sqrt(l2 * l2 - 2 * l1 * l1 * (1 - c));
  const V3 p2{x2, -l1, 0};
  const V3 n{(p2[0] - p1[0]) / l2, (p2[1] - p1[1]) / l2, (p2[2] - p1[2]) / l2};
  const double phi = -std::asin(n[2]), psi = std::atan2(n[1], n[0]);
  // Rates: v_p1 = l1 w (0, s, -c); x2 x2' = -l1^2 s w; the rod turns without spin.
  const V3 v1{0, l1 * w * s, -l1 * w * c};
  const double dx2 = -l1 * l1 * s * w / x2;
  const V3 v2{dx2, 0, 0};
  const V3 dv{(v2[0] - v1[0]) / l2, (v2[1] - v1[1]) / l2, (v2[2] - v1[2]) / l2};
  const V3 om = cross(n, dv);  // omega x n = dv with omega . n = 0
  // Rod body-frame rates: R^T omega, R = Rz(psi) Ry(phi) Rx(theta).
  const double cps = std::cos(psi), sps = std::sin(psi), cph = std::cos(phi), sph = std::sin(phi);
  const double cth = std::cos(theta), sth = std::sin(theta);
  const double R[3][3] = {{cps * cph, cps * sph * sth - cth * sps, cps * cth * sph + sps * sth},
                          {cph * sps, cps * cth + sps * sph * sth, cth * sps * sph - cps * sth},
                          {-sph, cph * sth, cph * cth}};
  V3 wb{};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) wb[static_cast<std::size_t>(i)] += R[k][i] * om[static_cast<std::size_t>(k)];
  x[ix("crank.e0")] = std::cos(chi / 2), x[ix("crank.e1")] = std::sin(chi / 2);
  x[ix("crank.wx")] = w;
  // mbsc names the zyx angles phi, theta, psi (about z, y, x): the thesis's psi, phi, theta.
  x[ix("rod.phi")] = psi, x[ix("rod.theta")] = phi, x[ix("rod.psi")] = theta;
  const char* xyz[3] = {"rod.x", "rod.y", "rod.z"};
  const char* uvw[3] = {"rod.u", "rod.v", "rod.w"};
  const char* om3[3] = {"rod.wx", "rod.wy", "rod.wz"};
  for (std::size_t k = 0; k < 3; ++k) {
    x[ix(xyz[k])] = p1[k] + g2 * (p2[k] - p1[k]);
    x[ix(uvw[k])] = v1[k] + g2 * (v2[k] - v1[k]);
    x[ix(om3[k])] = wb[k];
  }
  x[ix("slider.e0")] = 1;
  x[ix("slider.x")] = x2, x[ix("slider.y")] = -l1;
  x[ix("slider.u")] = dx2;
  return x;
}

/// The slider's normal force (the multipliers of guide.n1, guide.n2) at inputs (u1, Ff).
std::array<double, 2> normal_force(const std::vector<double>& x, double u1, double Ff) {
  std::vector<double> lam(static_cast<std::size_t>(RM::kNc));
  const double u[2] = {u1, Ff};
  REQUIRE(RM::multipliers(0.0, x.data(), u, RM::kParamDefaults, lam.data()) == 0);
  return {lam[static_cast<std::size_t>(index_of(RM::kConstraintNames, RM::kNc, "guide.n1"))],
          lam[static_cast<std::size_t>(index_of(RM::kConstraintNames, RM::kNc, "guide.n2"))]};
}

/// Ff = -mu sigma |N0 + Ff N1|, sigma = sign(v): (1 - mu^2 |N1|^2) F^2 - 2 mu^2 (N0.N1) F -
/// mu^2 |N0|^2 = 0, the root of sign -sigma.
double coulomb(double v, const std::array<double, 2>& N0, const std::array<double, 2>& N1) {
  if (v == 0) return 0;
  const double sigma = v > 0 ? 1 : -1;
  const double a = 1 - mu * mu * (N1[0] * N1[0] + N1[1] * N1[1]);
  const double b = -2 * mu * mu * (N0[0] * N1[0] + N0[1] * N1[1]);
  const double c = -mu * mu * (N0[0] * N0[0] + N0[1] * N0[1]);
  REQUIRE(a > 0);  // no jam: the friction's own effect on the normal force is weaker than 1/mu
  const double d = std::sqrt(b * b - 4 * a * c);
  const double r1 = (-b + d) / (2 * a), r2 = (-b - d) / (2 * a);  // c <= 0: r1 >= 0 >= r2
  return sigma > 0 ? r2 : r1;
}

/// The friction force closed on the state with crank torque u1.
double friction(const std::vector<double>& x, double u1) {
  const auto N0 = normal_force(x, u1, 0), Nf = normal_force(x, u1, 1);
  return coulomb(x[ix("slider.u")], N0, {Nf[0] - N0[0], Nf[1] - N0[1]});
}

}  // namespace

TEST_CASE("slider-crank 3-D: 1 degree of freedom, the crank's rate independent", "[numeric][slider_crank_3d]") {
  CHECK(C::kNdof == 1);
  CHECK(std::string(C::kDofNames[0]) == "crank.wx");
  CHECK(C::kNc == 17);  // revolute 5, spherical 3 + 3, prismatic 5, no spin 1; 18 speeds
  CHECK(C::kNu == 18);
}

TEST_CASE("slider-crank 3-D: the thesis's kinematics satisfy every row", "[numeric][slider_crank_3d]") {
  std::mt19937 rng(45);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 20; ++trial) {
    const auto x = state(3.1 * u(rng), 4 * u(rng), 2 * u(rng));
    std::vector<double> r(static_cast<std::size_t>(C::kNposc)), rv(static_cast<std::size_t>(C::kNc));
    REQUIRE(C::position_constraints(0.0, x.data(), nullptr, C::kParamDefaults, r.data()) == 0);
    REQUIRE(C::velocity_constraints(0.0, x.data(), nullptr, C::kParamDefaults, rv.data()) == 0);
    for (int i = 0; i < C::kNposc; ++i) {
      INFO(C::kPositionConstraintNames[i]);
      CHECK(std::fabs(r[static_cast<std::size_t>(i)]) < 1e-12);
    }
    for (int i = 0; i < C::kNc; ++i) {
      INFO(C::kConstraintNames[i]);
      CHECK(std::fabs(rv[static_cast<std::size_t>(i)]) < 1e-12);
    }
  }
}

TEST_CASE("slider-crank 3-D: both formulations agree with the Coulomb friction closed outside", "[numeric][slider_crank_3d]") {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1, 1);
  int sliding = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const auto x = state(3.1 * u(rng), 4 * u(rng), 2 * u(rng));
    const double u1 = 2 * u(rng);
    const double Ff = friction(x, u1);
    // The law holds with the normal force of the closed input.
    const auto N = normal_force(x, u1, Ff);
    const double v = x[ix("slider.u")];
    CHECK(std::fabs(Ff + mu * (v > 0 ? 1 : -1) * std::hypot(N[0], N[1])) < 1e-10);
    sliding += std::fabs(Ff) > 1e-3;
    const double in[2] = {u1, Ff};
    std::vector<double> a(x.size()), b(x.size());
    REQUIRE(R::rhs(0.0, x.data(), in, R::kParamDefaults, a.data()) == 0);
    REQUIRE(RM::rhs(0.0, x.data(), in, RM::kParamDefaults, b.data()) == 0);
    for (std::size_t i = 0; i < a.size(); ++i) {
      INFO("trial " << trial << " " << C::kStateNames[i]);
      CHECK(std::fabs(a[i] - b[i]) < 1e-9 * (1 + std::fabs(a[i])));
    }
  }
  CHECK(sliding >= 15);  // the friction is really there
}

TEST_CASE("slider-crank 3-D: energy balance with Coulomb friction closed outside over a run", "[numeric][slider_crank_3d]") {
  const double u1 = 0.3;
  // The state, then the works of the torque and of the friction: Wu' = u1 w, Wf' = Ff v.
  const std::size_t iu = static_cast<std::size_t>(C::kNx), iff = iu + 1;
  auto rhs = [&](double t, const double* s, double* sd) {
    const std::vector<double> x(s, s + C::kNx);
    const double Ff = friction(x, u1);
    const double in[2] = {u1, Ff};
    const int st = R::rhs(t, s, in, R::kParamDefaults, sd);
    sd[iu] = u1 * s[ix("crank.wx")];
    sd[iff] = Ff * s[ix("slider.u")];
    return st;
  };
  std::vector<double> y = state(0.4, 6.0, 0.2);
  y.push_back(0.0), y.push_back(0.0);
  std::array<double, 3> e0{}, e{};
  const double in0[2] = {0, 0};
  REQUIRE(C::energy(0.0, y.data(), in0, C::kParamDefaults, e0.data()) == 0);
  mbsc::runtime::StepperOptions o;
  o.rtol = o.atol = 1e-11;
  mbsc::runtime::Dop853 stepper(rhs, C::kNx + 2, o);
  REQUIRE(stepper.reset(0.0, y) == mbsc::runtime::Stepper::Status::Ok);
  double worst = 0;
  int reversals = 0;
  double last_v = y[ix("slider.u")];
  std::vector<double> s(y.size());
  while (stepper.t() < 1.5) {
    REQUIRE(stepper.step(1.5) == mbsc::runtime::Stepper::Status::Ok);
    stepper.interpolate(stepper.t(), s);
    REQUIRE(C::energy(stepper.t(), s.data(), in0, C::kParamDefaults, e.data()) == 0);
    worst = std::max(worst, std::fabs(e[2] - e0[2] - s[iu] - s[iff]));
    const double v = s[ix("slider.u")];
    reversals += (v > 0) != (last_v > 0);
    last_v = v;
  }
  INFO("energy balance error " << worst << ", torque work " << s[iu] << ", friction work " << s[iff] << ", reversals "
                               << reversals);
  CHECK(worst < 1e-8);
  CHECK(s[iff] < -0.05);   // friction dissipated a fair share of the energy
  CHECK(reversals >= 2);   // the slider went back and forth
}

namespace {

/// The thesis's prescribed slide (eq (k)), as the slider's x: l2 + s(t) with
/// s(t) = -(1 - gamma2) l2 (1 + 8 sin^2(2 pi t)) / 10, period 1/2 s; and its two rates.
void thesis_slide(double t, double& q, double& qd, double& qdd) {
  const double pi = std::acos(-1.0), A = (1 - g2) * l2 / 10;
  const double s2 = std::sin(2 * pi * t), c2 = std::cos(2 * pi * t);
  q = l2 - A * (1 + 8 * s2 * s2);
  qd = -A * 32 * pi * s2 * c2;
  qdd = -A * 64 * pi * pi * (c2 * c2 - s2 * s2);
}

struct ThesisSample {
  double u1, Ff, w, v, chi;  // torque, friction force, crank rate, slide rate, crank angle
};

/// The thesis's inverse dynamics at t along the prescribed slide, the crank on the branch
/// chi > 0, closed outside the generated code: the crank's acceleration is affine in
/// (u1, Ff), a0 + au u1 + aF Ff, so u1(Ff) = (dw - a0 - aF Ff) / au, along which the
/// normal force is N0 + Ff N1, and the law's quadratic gives Ff.
ThesisSample thesis_inverse(double t) {
  double x2 = 0, ds = 0, dds = 0;
  thesis_slide(t, x2, ds, dds);
  const double cchi = 1 - (l2 * l2 - x2 * x2) / (2 * l1 * l1), chi = std::acos(cchi), schi = std::sin(chi);
  const double w = -x2 * ds / (l1 * l1 * schi);
  const double dw = -(ds * ds + x2 * dds + l1 * l1 * cchi * w * w) / (l1 * l1 * schi);
  const auto x = state(chi, w, 0.0);
  auto accel = [&](double u1, double Ff) {
    std::vector<double> xd(x.size());
    const double in[2] = {u1, Ff};
    REQUIRE(R::rhs(0.0, x.data(), in, R::kParamDefaults, xd.data()) == 0);
    return xd[ix("crank.wx")];
  };
  const double a0 = accel(0, 0), au = accel(1, 0) - a0, aF = accel(0, 1) - a0;
  const double u10 = (dw - a0) / au, du1 = -aF / au;
  const auto Na = normal_force(x, u10, 0), Nb = normal_force(x, u10 + du1, 1);
  const double Ff = coulomb(ds, Na, {Nb[0] - Na[0], Nb[1] - Na[1]});
  return ThesisSample{u10 + du1 * Ff, Ff, w, ds, chi};
}

}  // namespace

TEST_CASE("slider-crank 3-D: thesis inverse dynamics over one period of the prescribed slide",
          "[numeric][slider_crank_3d]") {
  // Work of u1 and of the friction over a period, by Simpson's rule on each quarter (the
  // integrands are smooth inside and continuous across the reversals at t = 1/4, 1/2).
  double work_u = 0, work_f = 0;
  const int n = 400;
  for (int q = 0; q < 2; ++q) {
    const double a = 0.25 * q + 1e-9, b = 0.25 * (q + 1) - 1e-9, h = (b - a) / n;
    for (int k = 0; k <= n; ++k) {
      const double wgt = (k == 0 || k == n) ? 1 : (k % 2 ? 4 : 2);
      const ThesisSample sm = thesis_inverse(a + k * h);
      work_u += wgt * h / 3 * sm.u1 * sm.w;
      work_f += wgt * h / 3 * sm.Ff * sm.v;
    }
  }
  INFO("torque work " << work_u << ", friction work " << work_f);
  CHECK(work_f < -1e-3);                                 // friction dissipates
  CHECK(std::fabs(work_u + work_f) < 1e-6 * std::fabs(work_f));  // kinetic energy back to its start
  // The jump of u1 where the slider reverses (t = 1/4): the friction force changes sign.
  const ThesisSample before = thesis_inverse(0.25 - 1e-6), after = thesis_inverse(0.25 + 1e-6);
  INFO("u1 at the reversal: " << before.u1 << " -> " << after.u1 << ", Ff " << before.Ff << " -> " << after.Ff);
  CHECK(before.Ff * after.Ff < 0);
  CHECK(std::fabs(before.u1 - after.u1) > 1e-3);
}

TEST_CASE("slider-crank 3-D: the runtime's inverse dynamics solves the torque with the friction law in rhs",
          "[numeric][slider_crank_3d][inverse]") {
  // The shipped model closes the friction in its rhs, which is then not affine in u1:
  // InverseDynamics (prescribed slide, thesis eq (k)) must give the torque the outside
  // closure above gives (thesis_inverse), in both formulations, and drive its rhs to the
  // prescribed motion.
  for (const auto& m : {MBSC_MODEL_TABLE(C), MBSC_MODEL_TABLE_MULTIPLIERS(CM)}) {
    INFO((m.multipliers ? "multipliers" : "complement"));
    const std::vector<double> p(m.param_defaults, m.param_defaults + m.np);  // (with the Baumgarte gains)
    mbsc::runtime::InverseOptions opt;  // the crank's and the slider's quaternions kept unit
    opt.quaternion_indices.assign(C::kQuaternionIndices, C::kQuaternionIndices + 4 * C::kNquaternions);
    mbsc::runtime::InverseDynamics inv(m, {{static_cast<int>(ix("slider.x")), thesis_slide}}, {0}, p, {}, opt);
    REQUIRE(inv.setup_error().empty());
    std::vector<double> x = state(thesis_inverse(0.003).chi, 0.0, 0.0);  // the branch chi > 0
    double worst = 0, largest = 0, friction_share = 0;
    for (int k = 0; k < 40; ++k) {
      const double t = 0.003 + 0.0125 * k;  // never at a reversal (t = 0, 1/4, 1/2)
      mbsc::runtime::InverseSample smp;
      REQUIRE(inv.solve(t, x, smp));
      const double u1 = thesis_inverse(t).u1;
      INFO("t = " << t << ": u1 " << smp.inputs[0] << " against " << u1);
      CHECK(std::fabs(smp.inputs[0] - u1) < 1e-8 * std::max(1.0, std::fabs(u1)));
      CHECK(smp.acceleration_residual < 1e-10);
      worst = std::max(worst, std::fabs(smp.inputs[0] - u1));
      largest = std::max(largest, std::fabs(u1));
      // The friction is not negligible here: its share of the torque.
      std::vector<double> xd(x.size());
      const double no_friction[2] = {smp.inputs[0], 0.0};
      REQUIRE(R::rhs(0.0, smp.x.data(), no_friction, R::kParamDefaults, xd.data()) == 0);
      friction_share = std::max(friction_share, std::fabs(xd[ix("crank.wx")] - smp.xdot[ix("crank.wx")]));
    }
    INFO("largest torque " << largest << ", worst difference " << worst);
    CHECK(friction_share > 1.0);  // rad/s^2 that the friction takes off the crank
  }
}

// ---- The friction closed by the generated code (the joint's `friction mu`) ----

namespace {

/// The normal force the shipped multipliers form reports with its own friction closed.
std::array<double, 2> closed_normal_force(const std::vector<double>& x, double u1) {
  std::vector<double> lam(static_cast<std::size_t>(CM::kNc));
  REQUIRE(CM::multipliers(0.0, x.data(), &u1, CM::kParamDefaults, lam.data()) == 0);
  return {lam[static_cast<std::size_t>(index_of(CM::kConstraintNames, CM::kNc, "guide.n1"))],
          lam[static_cast<std::size_t>(index_of(CM::kConstraintNames, CM::kNc, "guide.n2"))]};
}

/// The minimal state (kept coordinates, the crank's rate) of a full state, by name.
std::vector<double> minimal(const std::vector<double>& x) {
  std::vector<double> z(static_cast<std::size_t>(CS::kNx));
  for (int i = 0; i < CS::kNx; ++i) z[static_cast<std::size_t>(i)] = x[ix(CS::kStateNames[i])];
  return z;
}

}  // namespace

TEST_CASE("slider-crank 3-D friction in the generated code: rhs equals the outside closure",
          "[numeric][slider_crank_3d][friction]") {
  CHECK(C::kNin == 1);  // the friction force is no input
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 20; ++trial) {
    const auto x = state(3.1 * u(rng), 4 * u(rng), 2 * u(rng));
    const double u1 = 2 * u(rng);
    const double in[2] = {u1, friction(x, u1)};
    std::vector<double> ref(x.size()), refm(x.size()), a(x.size()), b(x.size()), s(static_cast<std::size_t>(CS::kNx));
    REQUIRE(R::rhs(0.0, x.data(), in, R::kParamDefaults, ref.data()) == 0);
    REQUIRE(RM::rhs(0.0, x.data(), in, RM::kParamDefaults, refm.data()) == 0);
    REQUIRE(C::rhs(0.0, x.data(), &u1, C::kParamDefaults, a.data()) == 0);
    REQUIRE(CM::rhs(0.0, x.data(), &u1, CM::kParamDefaults, b.data()) == 0);
    const auto z = minimal(x);
    REQUIRE(CS::rhs(0.0, z.data(), &u1, CS::kParamDefaults, s.data()) == 0);
    for (std::size_t i = 0; i < x.size(); ++i) {
      INFO("trial " << trial << " " << C::kStateNames[i]);
      CHECK(std::fabs(a[i] - ref[i]) < 1e-10 * (1 + std::fabs(ref[i])));
      CHECK(std::fabs(b[i] - refm[i]) < 1e-10 * (1 + std::fabs(refm[i])));
      CHECK(std::fabs(a[i] - b[i]) < 1e-9 * (1 + std::fabs(a[i])));  // complement vs multipliers
    }
    for (int i = 0; i < CS::kNx; ++i) {
      INFO("trial " << trial << " minimal " << CS::kStateNames[i]);
      const double full = a[ix(CS::kStateNames[i])];
      CHECK(std::fabs(s[static_cast<std::size_t>(i)] - full) < 1e-9 * (1 + std::fabs(full)));
    }
  }
}

TEST_CASE("slider-crank 3-D friction in the generated code: |F| = mu |N|, F opposite v, 0 at rest",
          "[numeric][slider_crank_3d][friction]") {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  int sliding = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const auto x = state(3.1 * u(rng), 4 * u(rng), 2 * u(rng));
    const double u1 = 2 * u(rng), v = x[ix("slider.u")];
    // F read back from the generated accelerations: they are affine in Ff in the reference.
    std::vector<double> a(x.size()), r0(x.size()), r1(x.size());
    REQUIRE(C::rhs(0.0, x.data(), &u1, C::kParamDefaults, a.data()) == 0);
    const double in0[2] = {u1, 0}, in1[2] = {u1, 1};
    REQUIRE(R::rhs(0.0, x.data(), in0, R::kParamDefaults, r0.data()) == 0);
    REQUIRE(R::rhs(0.0, x.data(), in1, R::kParamDefaults, r1.data()) == 0);
    const std::size_t k = ix("crank.wx");
    const double F = (a[k] - r0[k]) / (r1[k] - r0[k]);
    const auto N = closed_normal_force(x, u1);  // the multipliers form's own reaction
    INFO("trial " << trial << " v " << v << " F " << F << " |N| " << std::hypot(N[0], N[1]));
    CHECK(std::fabs(std::fabs(F) - mu * std::hypot(N[0], N[1])) < 1e-8 * (1 + std::fabs(F)));
    CHECK(F * v <= 0);
    sliding += std::fabs(F) > 1e-3;
  }
  CHECK(sliding >= 15);
  // At rest (v = 0) the law gives 0 (the thesis's sign(0)): the accelerations of Ff = 0.
  const auto x = state(0.7, 0.0, 0.3);
  REQUIRE(x[ix("slider.u")] == 0.0);
  const double u1 = 1.5, in[2] = {u1, 0};
  std::vector<double> a(x.size()), ref(x.size());
  REQUIRE(C::rhs(0.0, x.data(), &u1, C::kParamDefaults, a.data()) == 0);
  REQUIRE(R::rhs(0.0, x.data(), in, R::kParamDefaults, ref.data()) == 0);
  for (std::size_t i = 0; i < x.size(); ++i) CHECK(std::fabs(a[i] - ref[i]) < 1e-12 * (1 + std::fabs(ref[i])));
}

TEST_CASE("slider-crank 3-D friction in the generated code: a jamming coefficient returns status 1, never NaN",
          "[numeric][slider_crank_3d][friction]") {
  // mu so large that 1 - mu^2 |N1|^2 <= 0 (Painleve): no friction force satisfies the law.
  std::vector<double> p(C::kParamDefaults, C::kParamDefaults + C::kNp), pm(CM::kParamDefaults, CM::kParamDefaults + CM::kNp);
  p[static_cast<std::size_t>(index_of(C::kParamNames, C::kNp, "mu"))] = 1e4;
  pm[static_cast<std::size_t>(index_of(CM::kParamNames, CM::kNp, "mu"))] = 1e4;
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(-1, 1);
  int jammed = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const auto x = state(3.1 * u(rng), 4 * u(rng), 2 * u(rng));
    const double u1 = 2 * u(rng);
    std::vector<double> a(x.size()), b(x.size());
    const int st = C::rhs(0.0, x.data(), &u1, p.data(), a.data());
    const int stm = CM::rhs(0.0, x.data(), &u1, pm.data(), b.data());
    CHECK(st == stm);
    jammed += st == 1;
    if (st == 0)
      for (double v : a) CHECK(std::isfinite(v));
  }
  CHECK(jammed >= 18);
  // At rest the law gives F = 0 whatever mu: no jam, the accelerations of Ff = 0.
  const auto x = state(0.7, 0.0, 0.3);
  REQUIRE(x[ix("slider.u")] == 0.0);
  const double u1 = 1.5, in[2] = {u1, 0};
  std::vector<double> a(x.size()), ref(x.size());
  REQUIRE(C::rhs(0.0, x.data(), &u1, p.data(), a.data()) == 0);
  REQUIRE(R::rhs(0.0, x.data(), in, R::kParamDefaults, ref.data()) == 0);
  for (std::size_t i = 0; i < x.size(); ++i) CHECK(std::fabs(a[i] - ref[i]) < 1e-12 * (1 + std::fabs(ref[i])));
}

TEST_CASE("slider-crank 3-D friction in the generated code: E(t) - E(0) = integral of (u1 w - mu |N| |v|)",
          "[numeric][slider_crank_3d][friction]") {
  const double u1 = 0.3;
  const std::size_t iu = static_cast<std::size_t>(C::kNx), iff = iu + 1;
  auto rhs = [&](double t, const double* s, double* sd) {
    const int st = C::rhs(t, s, &u1, C::kParamDefaults, sd);
    const std::vector<double> x(s, s + C::kNx);
    const auto N = closed_normal_force(x, u1);
    sd[iu] = u1 * s[ix("crank.wx")];
    sd[iff] = -mu * std::hypot(N[0], N[1]) * std::fabs(s[ix("slider.u")]);
    return st;
  };
  std::vector<double> y = state(0.4, 6.0, 0.2);
  y.push_back(0.0), y.push_back(0.0);
  std::array<double, 3> e0{}, e{};
  REQUIRE(C::energy(0.0, y.data(), &u1, C::kParamDefaults, e0.data()) == 0);
  mbsc::runtime::StepperOptions o;
  o.rtol = o.atol = 1e-11;
  mbsc::runtime::Dop853 stepper(rhs, C::kNx + 2, o);
  REQUIRE(stepper.reset(0.0, y) == mbsc::runtime::Stepper::Status::Ok);
  double worst = 0;
  std::vector<double> s(y.size());
  while (stepper.t() < 1.5) {
    REQUIRE(stepper.step(1.5) == mbsc::runtime::Stepper::Status::Ok);
    stepper.interpolate(stepper.t(), s);
    REQUIRE(C::energy(stepper.t(), s.data(), &u1, C::kParamDefaults, e.data()) == 0);
    worst = std::max(worst, std::fabs(e[2] - e0[2] - s[iu] - s[iff]));
  }
  INFO("energy balance error " << worst << ", torque work " << s[iu] << ", friction work " << s[iff]);
  CHECK(worst < 1e-8);
  CHECK(s[iff] < -0.05);  // friction dissipated a fair share of the energy
}
