// SPDX-License-Identifier: GPL-2.0-or-later
// Thesis Ex 4.1: the spherical pendulum in spherical coordinates, in Cartesian
// coordinates, and in Cartesian coordinates with the extra quasi-velocity v = |r'|^2
// are three different ODEs for one motion: the bob trajectories must agree.
#include <catch2/catch.hpp>
#include <cmath>

#include "mbsc/runtime/rk4.hpp"
#include "spherical_pendulum_angles/spherical_pendulum_angles.hpp"
#include "spherical_pendulum_cartesian/spherical_pendulum_cartesian.hpp"
#include "spherical_pendulum_extra_speed/spherical_pendulum_extra_speed.hpp"
#include "test_support.hpp"

namespace A = mbsc_gen::spherical_pendulum_angles;
namespace C = mbsc_gen::spherical_pendulum_cartesian;
namespace E = mbsc_gen::spherical_pendulum_extra_speed;
using mbsc_test::index_of;

namespace {

using RhsFn = int (*)(double, const double*, const double*, const double*, double*);

struct Form {
  RhsFn rhs, outputs, energy;
  const char* const* names;
  int nx;
  const double* params;
  std::vector<double> x;
  void set(const std::string& name, double v) { x[index_of(names, nx, name)] = v; }
};

// Initial motion: zenith angle 1.0 rad from the downward x axis, azimuth 0.3 rad,
// with rates that keep sin(theta) well away from zero (angular momentum about x).
constexpr double kTh = 1.0, kPh = 0.3, kThd = 0.4, kPhd = 0.9, kR = 1.0;

void set_cartesian(Form& f) {
  const double st = std::sin(kTh), ct = std::cos(kTh), sp = std::sin(kPh), cp = std::cos(kPh);
  f.set("bob.x", kR * ct);
  f.set("bob.y", kR * cp * st);
  f.set("bob.z", kR * sp * st);
  f.set("bob.u", -kR * st * kThd);
  f.set("bob.v", kR * (-sp * kPhd * st + cp * ct * kThd));
  f.set("bob.w", kR * (cp * kPhd * st + sp * ct * kThd));
}

}  // namespace

TEST_CASE("Ex 4.1: three forms of the spherical pendulum give one bob trajectory", "[numeric][pendulum]") {
  Form angles{A::rhs, A::outputs, A::energy, A::kStateNames, A::kNx, A::kParamDefaults, std::vector<double>(A::kNx, 0.0)};
  Form cart{C::rhs, C::outputs, C::energy, C::kStateNames, C::kNx, C::kParamDefaults, std::vector<double>(C::kNx, 0.0)};
  Form extra{E::rhs, E::outputs, E::energy, E::kStateNames, E::kNx, E::kParamDefaults, std::vector<double>(E::kNx, 0.0)};
  REQUIRE(A::kNdof == 2);
  REQUIRE(C::kNdof == 2);
  REQUIRE(E::kNdof == 2);
  set_cartesian(angles);
  angles.set("theta", kTh);
  angles.set("phi", kPh);
  angles.set("dtheta", kThd);
  angles.set("dphi", kPhd);
  set_cartesian(cart);
  set_cartesian(extra);
  const double* xe = extra.x.data();
  const int u = index_of(E::kStateNames, E::kNx, "bob.u");
  extra.set("v2", xe[u] * xe[u] + xe[u + 1] * xe[u + 1] + xe[u + 2] * xe[u + 2]);

  const double h = 2.5e-4;
  const int steps_per_check = 2000;  // every 0.5 s, 5 s in all
  double max_diff = 0.0, max_radius_error = 0.0;
  std::vector<Form*> forms = {&angles, &cart, &extra};
  double e0[3][3];
  for (int k = 0; k < 3; ++k) REQUIRE(forms[k]->energy(0.0, forms[k]->x.data(), nullptr, forms[k]->params, e0[k]) == 0);
  for (int check = 1; check <= 10; ++check) {
    double bob[3][3];
    for (int k = 0; k < 3; ++k) {
      Form& f = *forms[k];
      auto rhs = [&f](double t, const double* x, double* xd) { return f.rhs(t, x, nullptr, f.params, xd); };
      for (int s = 0; s < steps_per_check; ++s) {
        const double t = ((check - 1) * steps_per_check + s) * h;
        REQUIRE(mbsc::runtime::rk4_step(rhs, t, h, f.x) == 0);
      }
      REQUIRE(f.outputs(check * 0.5, f.x.data(), nullptr, f.params, bob[k]) == 0);
      const double radius = std::sqrt(bob[k][0] * bob[k][0] + bob[k][1] * bob[k][1] + bob[k][2] * bob[k][2]);
      max_radius_error = std::max(max_radius_error, std::abs(radius - kR));
    }
    for (int k = 1; k < 3; ++k)
      for (int i = 0; i < 3; ++i) max_diff = std::max(max_diff, std::abs(bob[k][i] - bob[0][i]));
  }
  INFO("max bob position difference between the forms over 5 s: " << max_diff);
  CHECK(max_diff < 1e-8);
  CHECK(max_radius_error < 1e-9);
  // Energy is conserved by each form (an independent check of the dynamics).
  for (int k = 0; k < 3; ++k) {
    double e[3];
    REQUIRE(forms[k]->energy(5.0, forms[k]->x.data(), nullptr, forms[k]->params, e) == 0);
    CHECK(std::abs(e[2] - e0[k][2]) < 1e-9 * std::max(1.0, std::abs(e0[k][2])));
  }
}

TEST_CASE("Ex 4.1: the extra-speed form keeps v = |r'|^2 and gives v' = 2 g x'", "[numeric][pendulum]") {
  std::vector<double> x(E::kNx, 0.0), xd(E::kNx);
  Form f{E::rhs, E::outputs, E::energy, E::kStateNames, E::kNx, E::kParamDefaults, x};
  set_cartesian(f);
  const int u = index_of(E::kStateNames, E::kNx, "bob.u");
  const double v2 = f.x[u] * f.x[u] + f.x[u + 1] * f.x[u + 1] + f.x[u + 2] * f.x[u + 2];
  f.set("v2", v2);
  REQUIRE(E::rhs(0.0, f.x.data(), nullptr, E::kParamDefaults, xd.data()) == 0);
  const double g = E::kParamDefaults[index_of(E::kParamNames, E::kNp, "g")];
  // Thesis (o): v' = 2 g x' on the constraint manifold (energy conservation).
  CHECK(xd[index_of(E::kStateNames, E::kNx, "v2")] == Approx(2.0 * g * f.x[u]).margin(1e-12));
}
