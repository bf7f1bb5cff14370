// SPDX-License-Identifier: GPL-2.0-or-later
// Coulomb friction in two joints of one model, solved together in the generated code
// (docs/formulation.md, "Coulomb friction on a reaction", several joints): the cross slide
// of tests/data/friction/cross_slide.mbs, a table on a prismatic joint (friction mu1) and
// a carriage on a cylindrical joint on the table (friction mu2). The reference
// cross_slide_input.mbs takes the two friction forces as inputs F1, F2; this test closes
// the coupled law outside with that model's multipliers by a different method than the
// generated sweeps: the table's law in closed form for a given F2, and bisection on F2 for
// the carriage's. Checked:
//  - the generated rhs (complement, multipliers, --state minimal) equals the outside
//    closure's at random assembled states;
//  - the forces read back from the generated accelerations satisfy |F_i| = mu_i |N_i| with
//    the multipliers form's own normal forces, and F_i v_i <= 0; a joint at rest has none;
//  - a jamming pair of coefficients returns status 1 (never a NaN) while both slide, and
//    not when one joint is at rest;
//  - E(t) - E(0) = integral of (f1 v1 + f2 v2 - mu1 |N1| |v1| - mu2 |N2| |v2|) dt over a run
//    of the generated rhs alone.
// With a third joint (cross_slide3.mbs, a lifter sliding along the table's z axis): the
// three friction forces read from the generated accelerations by each slide's own
// momentum balance (a prismatic or cylindrical joint's reaction has no part along its
// slide) satisfy |F_i| = mu_i |N_i| with the multipliers form's normal forces and oppose
// the slides; the three forms agree.
#include <catch2/catch.hpp>
#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "cross_slide/cross_slide.hpp"
#include "cross_slide3/cross_slide3.hpp"
#include "cross_slide3_min/cross_slide3_min.hpp"
#include "cross_slide3_mult/cross_slide3_mult.hpp"
#include "cross_slide_input/cross_slide_input.hpp"
#include "cross_slide_input_mult/cross_slide_input_mult.hpp"
#include "cross_slide_min/cross_slide_min.hpp"
#include "cross_slide_mult/cross_slide_mult.hpp"
#include "mbsc/runtime/dop853.hpp"
#include "test_support.hpp"

using mbsc_test::index_of;

namespace {

namespace C = mbsc_gen::cross_slide;
namespace CM = mbsc_gen::cross_slide_mult;
namespace CS = mbsc_gen::cross_slide_min;
namespace R = mbsc_gen::cross_slide_input;
namespace RM = mbsc_gen::cross_slide_input_mult;

double par(const char* n) { return C::kParamDefaults[index_of(C::kParamNames, C::kNp, n)]; }
const double h = par("h");
std::size_t ix(const char* n) { return static_cast<std::size_t>(index_of(C::kStateNames, C::kNx, n)); }

using V2 = std::array<double, 2>;
double norm(const V2& a) { return std::hypot(a[0], a[1]); }
V2 axpy(double s, const V2& a, const V2& b) { return {b[0] + s * a[0], b[1] + s * a[1]}; }
double sgn(double v) { return v > 0 ? 1.0 : v < 0 ? -1.0 : 0.0; }

/// The assembled state: the table at x = s1 moving at v1, the carriage s2 along the table's
/// y axis moving at v2 relative to it, turned by theta about that axis at rate w.
std::vector<double> state(double s1, double v1, double s2, double v2, double theta, double w) {
  std::vector<double> x(static_cast<std::size_t>(C::kNx), 0.0);
  x[ix("table.e0")] = 1;
  x[ix("table.x")] = s1, x[ix("table.u")] = v1;
  x[ix("carriage.e0")] = std::cos(theta / 2), x[ix("carriage.e2")] = std::sin(theta / 2);
  x[ix("carriage.x")] = s1, x[ix("carriage.y")] = s2, x[ix("carriage.z")] = h;
  x[ix("carriage.u")] = v1, x[ix("carriage.v")] = v2;
  x[ix("carriage.wy")] = w;  // the body's y axis is the space's (turned about y)
  return x;
}
double slide_rate(const std::vector<double>& x) { return x[ix("table.u")]; }
double cross_rate(const std::vector<double>& x) { return x[ix("carriage.v")]; }  // the table does not turn

/// The normal forces (the multipliers of each joint's rows n1, n2) of the reference at
/// inputs (f1, f2) and friction forces (F1, F2); the rows' gradients are unit vectors.
std::array<V2, 2> normal_forces(const std::vector<double>& x, const V2& f, double F1, double F2) {
  std::vector<double> lam(static_cast<std::size_t>(RM::kNc));
  const double u[4] = {f[0], f[1], F1, F2};
  REQUIRE(RM::multipliers(0.0, x.data(), u, RM::kParamDefaults, lam.data()) == 0);
  auto at = [&](const char* n) { return lam[static_cast<std::size_t>(index_of(RM::kConstraintNames, RM::kNc, n))]; };
  return {V2{at("slide.n1"), at("slide.n2")}, V2{at("cross.n1"), at("cross.n2")}};
}

/// F = -mu sigma |c + F n|, one joint's law with the others' share c: the root of sign
/// -sigma of (1 - mu^2 |n|^2) F^2 - 2 mu^2 (c.n) F - mu^2 |c|^2 = 0.
double coulomb(double sigma, double mu, const V2& c, const V2& n) {
  if (sigma == 0) return 0;
  const double a = 1 - mu * mu * (n[0] * n[0] + n[1] * n[1]);
  const double b = -2 * mu * mu * (c[0] * n[0] + c[1] * n[1]), cc = -mu * mu * (c[0] * c[0] + c[1] * c[1]);
  REQUIRE(a > 0);
  const double d = std::sqrt(b * b - 4 * a * cc);
  return sigma > 0 ? (-b - d) / (2 * a) : (-b + d) / (2 * a);
}

/// The coupled law closed outside: N_i = N0_i + F1 D1_i + F2 D2_i from three evaluations
/// of the reference's multipliers; F1 = phi(F2) by the table's closed form, and F2 the
/// root of g(F2) = F2 + sigma2 mu2 |N_2(phi(F2), F2)|, increasing while the law is a
/// contraction, by bisection on a bracket grown from 0 towards -sigma2.
V2 friction(const std::vector<double>& x, const V2& f, double mu1, double mu2) {
  const auto N0 = normal_forces(x, f, 0, 0), A = normal_forces(x, f, 1, 0), B = normal_forces(x, f, 0, 1);
  std::array<V2, 2> D1, D2;
  for (std::size_t i = 0; i < 2; ++i) {
    D1[i] = {A[i][0] - N0[i][0], A[i][1] - N0[i][1]};
    D2[i] = {B[i][0] - N0[i][0], B[i][1] - N0[i][1]};
  }
  const double s1 = sgn(slide_rate(x)), s2 = sgn(cross_rate(x));
  auto phi = [&](double F2) { return coulomb(s1, mu1, axpy(F2, D2[0], N0[0]), D1[0]); };
  auto g = [&](double F2) { return F2 + s2 * mu2 * norm(axpy(F2, D2[1], axpy(phi(F2), D1[1], N0[1]))); };
  double F2 = 0;
  if (s2 != 0) {
    double lo = 0, hi = -s2;  // g(lo) has the sign of s2 (or is 0), g(hi) is sought of the other
    while (g(hi) * s2 > 0) hi *= 2;
    for (int it = 0; it < 200 && lo != hi; ++it) {
      const double mid = (lo + hi) / 2;
      if (mid == lo || mid == hi) break;
      (g(mid) * s2 > 0 ? lo : hi) = mid;
    }
    F2 = (lo + hi) / 2;
  }
  return {phi(F2), F2};
}

/// The minimal state (kept coordinates and independent speeds) of a full state, by name.
std::vector<double> minimal(const std::vector<double>& x) {
  std::vector<double> z(static_cast<std::size_t>(CS::kNx));
  for (int i = 0; i < CS::kNx; ++i) z[static_cast<std::size_t>(i)] = x[ix(CS::kStateNames[i])];
  return z;
}

/// A random assembled state with both joints sliding (or, with `rest`, the second at rest).
std::vector<double> random_state(std::mt19937& rng, bool rest = false) {
  std::uniform_real_distribution<double> u(-1, 1);
  return state(u(rng), 2 * u(rng), 0.5 * u(rng), rest ? 0.0 : 2 * u(rng), 3 * u(rng), 4 * u(rng));
}

/// The normal forces the multipliers form reports with its own friction closed.
std::array<V2, 2> closed_normal_forces(const std::vector<double>& x, const V2& f, const double* p = CM::kParamDefaults) {
  std::vector<double> lam(static_cast<std::size_t>(CM::kNc));
  REQUIRE(CM::multipliers(0.0, x.data(), f.data(), p, lam.data()) == 0);
  auto at = [&](const char* n) { return lam[static_cast<std::size_t>(index_of(CM::kConstraintNames, CM::kNc, n))]; };
  return {V2{at("slide.n1"), at("slide.n2")}, V2{at("cross.n1"), at("cross.n2")}};
}

}  // namespace

TEST_CASE("friction in two joints: the generated rhs equals the coupled law closed outside, in every form",
          "[numeric][friction][friction_coupled]") {
  CHECK(C::kNin == 2);  // the friction forces are no inputs
  CHECK(C::kNdof == 3);
  const double mu1 = par("mu1"), mu2 = par("mu2");
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(-1, 1);
  int coupled = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const auto x = random_state(rng, trial % 5 == 4);  // every fifth with the carriage at rest
    const V2 f{10 * u(rng), 5 * u(rng)};
    const V2 F = friction(x, f, mu1, mu2);
    const double in[4] = {f[0], f[1], F[0], F[1]};
    // The outside closure satisfies both laws with the reference's own normal forces.
    const auto N = normal_forces(x, f, F[0], F[1]);
    CHECK(std::fabs(F[0] + sgn(slide_rate(x)) * mu1 * norm(N[0])) < 1e-10 * (1 + std::fabs(F[0])));
    CHECK(std::fabs(F[1] + sgn(cross_rate(x)) * mu2 * norm(N[1])) < 1e-10 * (1 + std::fabs(F[1])));
    coupled += std::fabs(F[0]) > 1e-3 && std::fabs(F[1]) > 1e-3;
    std::vector<double> ref(x.size()), refm(x.size()), a(x.size()), b(x.size()), s(static_cast<std::size_t>(CS::kNx));
    REQUIRE(R::rhs(0.0, x.data(), in, R::kParamDefaults, ref.data()) == 0);
    REQUIRE(RM::rhs(0.0, x.data(), in, RM::kParamDefaults, refm.data()) == 0);
    REQUIRE(C::rhs(0.0, x.data(), f.data(), C::kParamDefaults, a.data()) == 0);
    REQUIRE(CM::rhs(0.0, x.data(), f.data(), CM::kParamDefaults, b.data()) == 0);
    const auto z = minimal(x);
    REQUIRE(CS::rhs(0.0, z.data(), f.data(), CS::kParamDefaults, s.data()) == 0);
    for (std::size_t i = 0; i < x.size(); ++i) {
      INFO("trial " << trial << " " << C::kStateNames[i] << " F " << F[0] << ", " << F[1]);
      CHECK(std::fabs(a[i] - ref[i]) < 1e-10 * (1 + std::fabs(ref[i])));
      CHECK(std::fabs(b[i] - refm[i]) < 1e-10 * (1 + std::fabs(refm[i])));
    }
    for (int i = 0; i < CS::kNx; ++i) {
      INFO("trial " << trial << " minimal " << CS::kStateNames[i]);
      const double full = a[ix(CS::kStateNames[i])];
      CHECK(std::fabs(s[static_cast<std::size_t>(i)] - full) < 1e-10 * (1 + std::fabs(full)));
    }
  }
  CHECK(coupled >= 12);  // both frictions really there in most trials
}

TEST_CASE("friction in two joints: |F_i| = mu_i |N_i| with the generated normal forces, F_i v_i <= 0",
          "[numeric][friction][friction_coupled]") {
  const double mu1 = par("mu1"), mu2 = par("mu2");
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 20; ++trial) {
    const bool rest = trial % 5 == 4;
    const auto x = random_state(rng, rest);
    const V2 f{10 * u(rng), 5 * u(rng)};
    // F read back from the generated accelerations (table.u', carriage.v'), which the
    // reference has affine in (F1, F2).
    std::vector<double> a(x.size()), r0(x.size()), r1(x.size()), r2(x.size());
    REQUIRE(C::rhs(0.0, x.data(), f.data(), C::kParamDefaults, a.data()) == 0);
    const double i0[4] = {f[0], f[1], 0, 0}, i1[4] = {f[0], f[1], 1, 0}, i2[4] = {f[0], f[1], 0, 1};
    REQUIRE(R::rhs(0.0, x.data(), i0, R::kParamDefaults, r0.data()) == 0);
    REQUIRE(R::rhs(0.0, x.data(), i1, R::kParamDefaults, r1.data()) == 0);
    REQUIRE(R::rhs(0.0, x.data(), i2, R::kParamDefaults, r2.data()) == 0);
    const std::size_t p = ix("table.u"), q = ix("carriage.v");
    const double m11 = r1[p] - r0[p], m12 = r2[p] - r0[p], m21 = r1[q] - r0[q], m22 = r2[q] - r0[q];
    const double e1 = a[p] - r0[p], e2 = a[q] - r0[q], det = m11 * m22 - m12 * m21;
    REQUIRE(std::fabs(det) > 1e-6);
    const double F1 = (e1 * m22 - m12 * e2) / det, F2 = (m11 * e2 - m21 * e1) / det;
    const auto N = closed_normal_forces(x, f);
    INFO("trial " << trial << " F " << F1 << ", " << F2 << " |N| " << norm(N[0]) << ", " << norm(N[1]));
    CHECK(std::fabs(std::fabs(F1) - mu1 * norm(N[0])) < 1e-8 * (1 + std::fabs(F1)));
    CHECK(F1 * slide_rate(x) <= 0);
    CHECK(F2 * cross_rate(x) <= 0);
    if (rest) CHECK(std::fabs(F2) < 1e-9);
    else CHECK(std::fabs(std::fabs(F2) - mu2 * norm(N[1])) < 1e-8 * (1 + std::fabs(F2)));
  }
}

TEST_CASE("friction in two joints: coefficients that may jam return status 1, never NaN, unless a joint rests",
          "[numeric][friction][friction_coupled]") {
  // mu1 = mu2 = 3: the carriage's friction loads the table's normal force with weight 1,
  // the table's loads the carriage's with m2 / (m1 + m2) = 1/3, so 1 - C12 C21 = -2 < 0.
  auto params = [](const double* defaults, const char* const* names, int n) {
    std::vector<double> p(defaults, defaults + n);
    p[static_cast<std::size_t>(index_of(names, n, "mu1"))] = 3;
    p[static_cast<std::size_t>(index_of(names, n, "mu2"))] = 3;
    return p;
  };
  const auto p = params(C::kParamDefaults, C::kParamNames, C::kNp);
  const auto pm = params(CM::kParamDefaults, CM::kParamNames, CM::kNp);
  const auto ps = params(CS::kParamDefaults, CS::kParamNames, CS::kNp);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  int jammed = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const auto x = random_state(rng);
    const V2 f{10 * u(rng), 5 * u(rng)};
    std::vector<double> a(x.size()), b(x.size()), s(static_cast<std::size_t>(CS::kNx));
    const int st = C::rhs(0.0, x.data(), f.data(), p.data(), a.data());
    const int stm = CM::rhs(0.0, x.data(), f.data(), pm.data(), b.data());
    const auto z = minimal(x);
    const int sts = CS::rhs(0.0, z.data(), f.data(), ps.data(), s.data());
    CHECK(st == stm);
    CHECK(st == sts);
    CHECK((st == 0 || st == 1));
    jammed += st == 1;
    if (st == 0)
      for (double v : a) CHECK(std::isfinite(v));
  }
  CHECK(jammed == 20);
  // The carriage at rest: its force is 0, the table's law alone (a = 1 there) has a
  // solution, the outside closure's.
  for (int trial = 0; trial < 5; ++trial) {
    const auto x = random_state(rng, true);
    const V2 f{10 * u(rng), 5 * u(rng)};
    std::vector<double> a(x.size()), ref(x.size());
    REQUIRE(C::rhs(0.0, x.data(), f.data(), p.data(), a.data()) == 0);
    const V2 F = friction(x, f, 3, 3);
    CHECK(F[1] == 0.0);
    std::vector<double> pr(R::kParamDefaults, R::kParamDefaults + R::kNp);
    const double in[4] = {f[0], f[1], F[0], F[1]};
    REQUIRE(R::rhs(0.0, x.data(), in, pr.data(), ref.data()) == 0);
    for (std::size_t i = 0; i < x.size(); ++i) CHECK(std::fabs(a[i] - ref[i]) < 1e-10 * (1 + std::fabs(ref[i])));
  }
}

TEST_CASE("friction in two joints: E(t) - E(0) = integral of the inputs' power less mu_i |N_i| |v_i|",
          "[numeric][friction][friction_coupled]") {
  const double mu1 = par("mu1"), mu2 = par("mu2");
  // Forces that keep both joints sliding one way (f1 beats mu1 (m1 + m2) g, f2 pulls the
  // carriage on the way it goes), the carriage spinning freely.
  const V2 f{20.0, -6.0};
  const std::size_t iw = static_cast<std::size_t>(C::kNx), idiss = iw + 1;
  auto rhs = [&](double t, const double* s, double* sd) {
    const int st = C::rhs(t, s, f.data(), C::kParamDefaults, sd);
    const std::vector<double> x(s, s + C::kNx);
    const auto N = closed_normal_forces(x, f);
    sd[iw] = f[0] * slide_rate(x) + f[1] * cross_rate(x);
    sd[idiss] = -mu1 * norm(N[0]) * std::fabs(slide_rate(x)) - mu2 * norm(N[1]) * std::fabs(cross_rate(x));
    return st;
  };
  std::vector<double> y = state(0.0, 1.0, 0.0, -1.0, 0.3, 2.0);
  y.push_back(0.0), y.push_back(0.0);
  std::array<double, 3> e0{}, e{};
  REQUIRE(C::energy(0.0, y.data(), f.data(), C::kParamDefaults, e0.data()) == 0);
  mbsc::runtime::StepperOptions o;
  o.rtol = o.atol = 1e-11;
  mbsc::runtime::Dop853 stepper(rhs, C::kNx + 2, o);
  REQUIRE(stepper.reset(0.0, y) == mbsc::runtime::Stepper::Status::Ok);
  double worst = 0;
  std::vector<double> s(y.size());
  while (stepper.t() < 1.0) {
    REQUIRE(stepper.step(1.0) == mbsc::runtime::Stepper::Status::Ok);
    stepper.interpolate(stepper.t(), s);
    REQUIRE(C::energy(stepper.t(), s.data(), f.data(), C::kParamDefaults, e.data()) == 0);
    worst = std::max(worst, std::fabs(e[2] - e0[2] - s[iw] - s[idiss]));
  }
  INFO("energy balance error " << worst << ", inputs' work " << s[iw] << ", dissipated " << s[idiss]);
  CHECK(worst < 1e-8);
  CHECK(s[idiss] < -1.0);  // both frictions dissipate a fair share
  CHECK(slide_rate(s) > 0);
  CHECK(cross_rate(s) < 0);  // still sliding the same ways
}

namespace {

namespace T = mbsc_gen::cross_slide3;
namespace TM = mbsc_gen::cross_slide3_mult;
namespace TS = mbsc_gen::cross_slide3_min;

double par3(const char* n) { return T::kParamDefaults[index_of(T::kParamNames, T::kNp, n)]; }
std::size_t ix3(const char* n) { return static_cast<std::size_t>(index_of(T::kStateNames, T::kNx, n)); }

/// The cross slide's state with the lifter at height s3 on the table's mast, sliding at v3.
std::vector<double> state3(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  const double s1 = u(rng), v1 = 2 * u(rng), s2 = 0.5 * u(rng), v2 = 2 * u(rng), th = 3 * u(rng), w = 4 * u(rng);
  const double s3 = 0.5 * u(rng), v3 = 2 * u(rng);
  std::vector<double> x(static_cast<std::size_t>(T::kNx), 0.0);
  x[ix3("table.e0")] = 1;
  x[ix3("table.x")] = s1, x[ix3("table.u")] = v1;
  x[ix3("carriage.e0")] = std::cos(th / 2), x[ix3("carriage.e2")] = std::sin(th / 2);
  x[ix3("carriage.x")] = s1, x[ix3("carriage.y")] = s2, x[ix3("carriage.z")] = par3("h");
  x[ix3("carriage.u")] = v1, x[ix3("carriage.v")] = v2, x[ix3("carriage.wy")] = w;
  x[ix3("lifter.e0")] = 1;
  x[ix3("lifter.x")] = s1 + par3("ahead"), x[ix3("lifter.z")] = s3;
  x[ix3("lifter.u")] = v1, x[ix3("lifter.w")] = v3;
  return x;
}

}  // namespace

TEST_CASE("friction in three joints: each law holds with the generated forces and normal forces, in every form",
          "[numeric][friction][friction_coupled]") {
  const double m1 = par3("m1"), m2 = par3("m2"), m3 = par3("m3"), g = par3("g");
  const double mu[3] = {par3("mu1"), par3("mu2"), par3("mu3")};
  std::mt19937 rng(33);
  std::uniform_real_distribution<double> u(-1, 1);
  int coupled = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const auto x = state3(rng);
    const V2 f{10 * u(rng), 5 * u(rng)};
    std::vector<double> a(x.size()), b(x.size()), s(static_cast<std::size_t>(TS::kNx));
    REQUIRE(T::rhs(0.0, x.data(), f.data(), T::kParamDefaults, a.data()) == 0);
    REQUIRE(TM::rhs(0.0, x.data(), f.data(), TM::kParamDefaults, b.data()) == 0);
    std::vector<double> z(static_cast<std::size_t>(TS::kNx));
    for (int i = 0; i < TS::kNx; ++i) z[static_cast<std::size_t>(i)] = x[ix3(TS::kStateNames[i])];
    REQUIRE(TS::rhs(0.0, z.data(), f.data(), TS::kParamDefaults, s.data()) == 0);
    for (std::size_t i = 0; i < x.size(); ++i) {
      INFO("trial " << trial << " " << T::kStateNames[i]);
      CHECK(std::fabs(a[i] - b[i]) < 1e-9 * (1 + std::fabs(a[i])));
    }
    for (int i = 0; i < TS::kNx; ++i) {
      INFO("trial " << trial << " minimal " << TS::kStateNames[i]);
      const double full = a[ix3(TS::kStateNames[i])];
      CHECK(std::fabs(s[static_cast<std::size_t>(i)] - full) < 1e-9 * (1 + std::fabs(full)));
    }
    // Along each slide only the friction and the actuator act: the whole mechanism along
    // x, the carriage along y, the lifter along z (with its weight).
    const double F[3] = {(m1 + m2 + m3) * a[ix3("table.u")] - f[0], m2 * a[ix3("carriage.v")] - f[1],
                         m3 * (a[ix3("lifter.w")] + g)};
    const double v[3] = {x[ix3("table.u")], x[ix3("carriage.v")], x[ix3("lifter.w")]};
    std::vector<double> lam(static_cast<std::size_t>(TM::kNc));
    REQUIRE(TM::multipliers(0.0, x.data(), f.data(), TM::kParamDefaults, lam.data()) == 0);
    const char* joints[3] = {"slide", "cross", "lift"};
    bool all = true;
    for (int j = 0; j < 3; ++j) {
      auto at = [&](const std::string& n) {
        return lam[static_cast<std::size_t>(index_of(TM::kConstraintNames, TM::kNc, joints[j] + n))];
      };
      const double N = std::hypot(at(".n1"), at(".n2"));
      INFO("trial " << trial << " joint " << joints[j] << " F " << F[j] << " |N| " << N << " v " << v[j]);
      CHECK(std::fabs(std::fabs(F[j]) - mu[j] * N) < 1e-8 * (1 + std::fabs(F[j])));
      CHECK(F[j] * v[j] <= 0);
      all = all && std::fabs(F[j]) > 1e-3;
    }
    coupled += all;
  }
  CHECK(coupled >= 15);
}
