// SPDX-License-Identifier: GPL-2.0-or-later
// The planar library level (points, ground, joints, actuators, springs, dampers):
//  - the slider-crank written with joints equals the same mechanism written by hand at
//    the invariant level (full state derivative at assembled random states, inputs on);
//  - its DOF is Gruebler's count;
//  - a spring pendulum conserves energy without its damper and loses it with it;
//  - a disc rolling on a moving line (a seesaw's plank) equals its hand-written twin.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "mbsc/runtime/assemble.hpp"
#include "mbsc/runtime/rk4.hpp"
#include "planar_rolling_disc/planar_rolling_disc.hpp"
#include "seesaw_disc/seesaw_disc.hpp"
#include "seesaw_disc_invariants/seesaw_disc_invariants.hpp"
#include "slider_crank/slider_crank.hpp"
#include "slider_crank_invariants/slider_crank_invariants.hpp"
#include "slot_gear/slot_gear.hpp"
#include "slot_gear_invariants/slot_gear_invariants.hpp"
#include "spring_pendulum/spring_pendulum.hpp"
#include "spring_pendulum_undamped/spring_pendulum_undamped.hpp"
#include "test_support.hpp"

using mbsc::runtime::AssemblyModel;
using mbsc_test::index_of;

TEST_CASE("planar library: slider-crank with joints equals the hand-written invariants", "[numeric][planar]") {
  namespace L = mbsc_gen::slider_crank;
  namespace H = mbsc_gen::slider_crank_invariants;
  // Gruebler: 3 (4 links - 1) - 2 (4 lower pairs) = 1.
  REQUIRE(L::kNdof == 1);
  REQUIRE(H::kNdof == 1);
  REQUIRE(L::kNx == H::kNx);
  const auto model = MBSC_TEST_ASSEMBLY_MODEL(L);
  auto ix = [](const char* n) { return static_cast<std::size_t>(index_of(L::kStateNames, L::kNx, n)); };
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> angle(0.0, 6.28), rate(-20.0, 20.0), load(-5.0, 5.0);
  for (int k = 0; k < 20; ++k) {
    std::vector<double> x(L::kNx, 0.0);
    const double th = angle(rng);
    x[ix("crank.theta")] = th;
    x[ix("rod.theta")] = -0.2 * std::sin(th);  // the elbow-right branch
    x[ix("slider.x")] = 0.4;
    x[ix("crank.w")] = rate(rng);
    std::vector<bool> gq(L::kNq, false), gu(L::kNu, false);
    gq[ix("crank.theta")] = true;
    gu[ix("crank.w") - L::kNq] = true;
    const double u[2] = {load(rng), load(rng)};
    const auto r = mbsc::runtime::assemble(model, 0.0, x, gq, gu, u, L::kParamDefaults);
    INFO(r.message);
    REQUIRE(r.ok());
    // Same state in the hand-written model's layout (same names).
    std::vector<double> y(H::kNx);
    for (int i = 0; i < H::kNx; ++i) y[static_cast<std::size_t>(i)] = x[ix(H::kStateNames[i])];
    std::vector<double> xd(L::kNx), yd(H::kNx);
    REQUIRE(L::rhs(0.0, x.data(), u, L::kParamDefaults, xd.data()) == 0);
    REQUIRE(H::rhs(0.0, y.data(), u, H::kParamDefaults, yd.data()) == 0);
    double scale = 1.0;
    for (double e : yd) scale = std::max(scale, std::abs(e));
    for (int i = 0; i < H::kNx; ++i) CHECK(std::abs(xd[ix(H::kStateNames[i])] - yd[static_cast<std::size_t>(i)]) < 1e-10 * scale);
    std::vector<double> e1(3), e2(3);
    REQUIRE(L::energy(0.0, x.data(), u, L::kParamDefaults, e1.data()) == 0);
    REQUIRE(H::energy(0.0, y.data(), u, H::kParamDefaults, e2.data()) == 0);
    CHECK(e1[2] == Approx(e2[2]).epsilon(1e-12));
  }
}

namespace {

/// Energy along a 4 s RK4 run of a spring pendulum variant, started at rest off balance.
template <class Fn, class EnergyFn>
std::vector<double> energy_history(Fn rhs, EnergyFn energy, const double* p, int nx, const char* const* names) {
  std::vector<double> x(static_cast<std::size_t>(nx), 0.0), E(3);
  const double th = 0.3, a = 1.0;  // bar angle from the x axis; mass centre at a/2
  x[static_cast<std::size_t>(index_of(names, nx, "bar.theta"))] = th;
  x[static_cast<std::size_t>(index_of(names, nx, "bar.x"))] = a / 2 * std::cos(th);
  x[static_cast<std::size_t>(index_of(names, nx, "bar.y"))] = a / 2 * std::sin(th);
  std::vector<double> history;
  energy(0.0, x.data(), nullptr, p, E.data());
  history.push_back(E[2]);
  auto f = [&](double t, const double* xs, double* xd) { return rhs(t, xs, nullptr, p, xd); };
  REQUIRE(mbsc::runtime::rk4_integrate(f, 0.0, 4.0, 16000, x, [&](double t, const std::vector<double>& xs) {
            energy(t, xs.data(), nullptr, p, E.data());
            history.push_back(E[2]);
          }) == 0);
  return history;
}

}  // namespace

TEST_CASE("planar library: spring conserves energy, damper dissipates it", "[numeric][planar]") {
  namespace U = mbsc_gen::spring_pendulum_undamped;
  namespace D = mbsc_gen::spring_pendulum;
  const auto undamped = energy_history(U::rhs, U::energy, U::kParamDefaults, U::kNx, U::kStateNames);
  double drift = 0.0;
  for (double e : undamped) drift = std::max(drift, std::abs(e - undamped.front()));
  CHECK(drift < 1e-8 * std::abs(undamped.front()));
  const auto damped = energy_history(D::rhs, D::energy, D::kParamDefaults, D::kNx, D::kStateNames);
  for (std::size_t i = 1; i < damped.size(); ++i) CHECK(damped[i] <= damped[i - 1] + 1e-10);
  CHECK(damped.back() < damped.front() - 0.1);  // it really moved and lost energy
}

TEST_CASE("planar library: pin-in-slot, gear, rotational spring and damper equal their hand-written forms",
          "[numeric][planar]") {
  namespace L = mbsc_gen::slot_gear;
  namespace H = mbsc_gen::slot_gear_invariants;
  REQUIRE(L::kNdof == 2);
  REQUIRE(H::kNdof == 2);
  const auto model = MBSC_TEST_ASSEMBLY_MODEL(L);
  auto ix = [](const char* n) { return static_cast<std::size_t>(index_of(L::kStateNames, L::kNx, n)); };
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> angle(-3.0, 3.0), pos(0.2, 1.5), rate(-3.0, 3.0);
  for (int k = 0; k < 20; ++k) {
    std::vector<double> x(L::kNx, 0.0);
    const double th = angle(rng), s = pos(rng);
    x[ix("bar.theta")] = th;
    x[ix("pin.x")] = s * std::cos(th);
    x[ix("pin.y")] = s * std::sin(th) + 0.01;  // a little off the slot: assembly moves it
    x[ix("bar.w")] = rate(rng);
    x[ix("pin.u")] = rate(rng);
    std::vector<bool> gq(L::kNq, false), gu(L::kNu, false);
    gq[ix("bar.theta")] = gq[ix("pin.x")] = true;
    gu[ix("bar.w") - L::kNq] = gu[ix("pin.u") - L::kNq] = true;
    const auto r = mbsc::runtime::assemble(model, 0.0, x, gq, gu, nullptr, L::kParamDefaults);
    INFO(r.message);
    REQUIRE(r.ok());
    // The gear: the wheel turns the other way, twice as fast.
    CHECK(x[ix("wheel.w")] == Approx(-2.0 * x[ix("bar.w")]).margin(1e-12));
    std::vector<double> y(H::kNx);
    for (int i = 0; i < H::kNx; ++i) y[static_cast<std::size_t>(i)] = x[ix(H::kStateNames[i])];
    std::vector<double> xd(L::kNx), yd(H::kNx);
    REQUIRE(L::rhs(0.0, x.data(), nullptr, L::kParamDefaults, xd.data()) == 0);
    REQUIRE(H::rhs(0.0, y.data(), nullptr, H::kParamDefaults, yd.data()) == 0);
    double scale = 1.0;
    for (double e : yd) scale = std::max(scale, std::abs(e));
    for (int i = 0; i < H::kNx; ++i) CHECK(std::abs(xd[ix(H::kStateNames[i])] - yd[static_cast<std::size_t>(i)]) < 1e-10 * scale);
    std::vector<double> e1(3), e2(3);
    REQUIRE(L::energy(0.0, x.data(), nullptr, L::kParamDefaults, e1.data()) == 0);
    REQUIRE(H::energy(0.0, y.data(), nullptr, H::kParamDefaults, e2.data()) == 0);
    CHECK(e1[2] == Approx(e2[2]).epsilon(1e-12));
  }
}

TEST_CASE("planar library: a disc rolling down an incline accelerates at 2/3 g sin(alpha)", "[numeric][planar]") {
  namespace R = mbsc_gen::planar_rolling_disc;
  REQUIRE(R::kNdof == 1);
  auto ix = [](const char* n) { return static_cast<std::size_t>(index_of(R::kStateNames, R::kNx, n)); };
  auto par = [](const char* n) { return R::kParamDefaults[index_of(R::kParamNames, R::kNp, n)]; };
  const double alpha = par("alpha"), r = par("r"), g = par("g");
  const double tx = std::cos(alpha), ty = -std::sin(alpha), nx = -ty, ny = tx;  // tangent, normal
  std::mt19937 rng(43);
  std::uniform_real_distribution<double> s(-2.0, 2.0), v(-3.0, 3.0), th(-3.0, 3.0);
  for (int k = 0; k < 10; ++k) {
    // On the slope at arc length s, rolling at speed v: w = -v / r.
    const double sk = s(rng), vk = v(rng);
    std::vector<double> x(R::kNx, 0.0), xd(R::kNx);
    x[ix("disc.x")] = sk * tx + r * nx;
    x[ix("disc.y")] = sk * ty + r * ny;
    x[ix("disc.theta")] = th(rng);
    x[ix("disc.u")] = vk * tx;
    x[ix("disc.v")] = vk * ty;
    x[ix("disc.w")] = -vk / r;
    REQUIRE(R::rhs(0.0, x.data(), nullptr, R::kParamDefaults, xd.data()) == 0);
    const double a = 2.0 / 3.0 * g * std::sin(alpha);  // down the slope, along +t
    CHECK(xd[ix("disc.u")] == Approx(a * tx).margin(1e-12));
    CHECK(xd[ix("disc.v")] == Approx(a * ty).margin(1e-12));
    CHECK(xd[ix("disc.w")] == Approx(-a / r).margin(1e-11));
  }
}

TEST_CASE("planar library: a disc rolling on a seesaw (a moving body's line) equals its hand-written form",
          "[numeric][planar]") {
  namespace L = mbsc_gen::seesaw_disc;
  namespace H = mbsc_gen::seesaw_disc_invariants;
  REQUIRE(L::kNdof == 2);
  REQUIRE(H::kNdof == 2);
  const auto model = MBSC_TEST_ASSEMBLY_MODEL(L);
  auto ix = [](const char* n) { return static_cast<std::size_t>(index_of(L::kStateNames, L::kNx, n)); };
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> tilt(-0.6, 0.6), along(-0.9, 0.9), rate(-3.0, 3.0);
  for (int k = 0; k < 20; ++k) {
    std::vector<double> x(L::kNx, 0.0);
    const double phi = tilt(rng), s = along(rng);
    x[ix("plank.theta")] = phi;
    x[ix("disc.x")] = s * std::cos(phi);
    x[ix("disc.y")] = s * std::sin(phi) + 0.2;  // near the contact height: assembly puts it there
    x[ix("plank.w")] = rate(rng);
    x[ix("disc.w")] = rate(rng);
    std::vector<bool> gq(L::kNq, false), gu(L::kNu, false);
    gq[ix("plank.theta")] = gq[ix("disc.x")] = true;
    gu[ix("plank.w") - L::kNq] = gu[ix("disc.w") - L::kNq] = true;
    const auto r = mbsc::runtime::assemble(model, 0.0, x, gq, gu, nullptr, L::kParamDefaults);
    INFO(r.message);
    REQUIRE(r.ok());
    std::vector<double> y(H::kNx);
    for (int i = 0; i < H::kNx; ++i) y[static_cast<std::size_t>(i)] = x[ix(H::kStateNames[i])];
    std::vector<double> xd(L::kNx), yd(H::kNx);
    REQUIRE(L::rhs(0.0, x.data(), nullptr, L::kParamDefaults, xd.data()) == 0);
    REQUIRE(H::rhs(0.0, y.data(), nullptr, H::kParamDefaults, yd.data()) == 0);
    double scale = 1.0;
    for (double e : yd) scale = std::max(scale, std::abs(e));
    for (int i = 0; i < H::kNx; ++i) CHECK(std::abs(xd[ix(H::kStateNames[i])] - yd[static_cast<std::size_t>(i)]) < 1e-10 * scale);
  }
}
