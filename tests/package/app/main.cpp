// SPDX-License-Identifier: GPL-2.0-or-later
// The app of the package test: calls the code mbsc_add_model generated from the
// installed mbsc, and the installed runtime, and checks them against physics:
//   * double pendulum: the generated rates against the textbook equations (Lagrange,
//     point masses) at random states, and the energy drift of an RK4 run;
//   * swing (a simple pendulum): w' = -(g/l) sin(th), with l from the included file.
// Prints one "NAME: ok ..." line per model and exits 0, or says what failed and exits 1.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

#include "double_pendulum/double_pendulum.hpp"
#include "mbsc/runtime/rk4.hpp"
#include "swing/swing.hpp"

namespace dp = mbsc_gen::double_pendulum;
namespace sw = mbsc_gen::swing;

namespace {

int failures = 0;

void expect(bool ok, const char* what, double got, double want) {
  if (ok) return;
  std::printf("FAILED: %s: got %.17g, expected %.17g\n", what, got, want);
  ++failures;
}

int index_of(const char* const* names, int n, const char* name) {
  for (int i = 0; i < n; ++i)
    if (std::strcmp(names[i], name) == 0) return i;
  std::printf("FAILED: no variable named %s\n", name);
  ++failures;
  return 0;
}

/// A consistent double-pendulum state from the angles and their rates.
std::vector<double> dp_state(double l1, double l2, double th1, double th2, double w1, double w2) {
  std::vector<double> x(dp::kNx, 0.0);
  auto set = [&](const char* name, double v) { x[index_of(dp::kStateNames, dp::kNx, name)] = v; };
  set("th1", th1);
  set("th2", th2);
  set("w1", w1);
  set("w2", w2);
  set("b1.x", l1 * std::sin(th1));
  set("b1.y", -l1 * std::cos(th1));
  set("b2.x", l1 * std::sin(th1) + l2 * std::sin(th2));
  set("b2.y", -l1 * std::cos(th1) - l2 * std::cos(th2));
  set("b1.u", l1 * std::cos(th1) * w1);
  set("b1.v", l1 * std::sin(th1) * w1);
  set("b2.u", l1 * std::cos(th1) * w1 + l2 * std::cos(th2) * w2);
  set("b2.v", l1 * std::sin(th1) * w1 + l2 * std::sin(th2) * w2);
  return x;
}

void check_double_pendulum() {
  std::vector<double> p(dp::kParamDefaults, dp::kParamDefaults + dp::kNp);
  auto param = [&](const char* name) { return p[index_of(dp::kParamNames, dp::kNp, name)]; };
  const double m1 = param("m1"), m2 = param("m2"), l1 = param("l1"), l2 = param("l2"), g = param("g");
  const int iw1 = index_of(dp::kStateNames, dp::kNx, "w1"), iw2 = index_of(dp::kStateNames, dp::kNx, "w2");

  // Lagrange's equations of two point masses on rods, d = th1 - th2:
  //   [(m1 + m2) l1^2      m2 l1 l2 cos d] [w1']   [-m2 l1 l2 sin(d) w2^2 - (m1 + m2) g l1 sin th1]
  //   [m2 l1 l2 cos d      m2 l2^2       ] [w2'] = [ m2 l1 l2 sin(d) w1^2 - m2 g l2 sin th2        ]
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(-3.0, 3.0), rate(-2.0, 2.0);
  for (int k = 0; k < 20; ++k) {
    const double th1 = angle(rng), th2 = angle(rng), w1 = rate(rng), w2 = rate(rng);
    const double d = th1 - th2;
    const double a = (m1 + m2) * l1 * l1, b = m2 * l1 * l2 * std::cos(d), c = m2 * l2 * l2;
    const double f1 = -m2 * l1 * l2 * std::sin(d) * w2 * w2 - (m1 + m2) * g * l1 * std::sin(th1);
    const double f2 = m2 * l1 * l2 * std::sin(d) * w1 * w1 - m2 * g * l2 * std::sin(th2);
    const double det = a * c - b * b;
    const double want1 = (c * f1 - b * f2) / det, want2 = (a * f2 - b * f1) / det;
    const std::vector<double> x = dp_state(l1, l2, th1, th2, w1, w2);
    std::vector<double> xdot(dp::kNx);
    expect(dp::rhs(0.0, x.data(), nullptr, p.data(), xdot.data()) == 0, "double_pendulum rhs status", 1, 0);
    const double tol = 1e-11 * (1 + std::abs(want1) + std::abs(want2));
    expect(std::abs(xdot[iw1] - want1) <= tol, "double_pendulum w1'", xdot[iw1], want1);
    expect(std::abs(xdot[iw2] - want2) <= tol, "double_pendulum w2'", xdot[iw2], want2);
  }

  // 5 s of chaotic motion from rest at large angles with RK4 (h = 1 ms): the total
  // energy T + V stays put to the method's error.
  std::vector<double> x = dp_state(l1, l2, 2.0, 2.5, 0.0, 0.0);
  double e0[3], e1[3];
  dp::energy(0.0, x.data(), nullptr, p.data(), e0);
  auto f = [&](double t, const double* s, double* sdot) { return dp::rhs(t, s, nullptr, p.data(), sdot); };
  const int status = mbsc::runtime::rk4_integrate(f, 0.0, 5.0, 5000, x, [](double, const std::vector<double>&) {});
  expect(status == 0, "double_pendulum RK4 status", status, 0);
  dp::energy(5.0, x.data(), nullptr, p.data(), e1);
  const double drift = std::abs(e1[2] - e0[2]) / std::abs(e0[2]);
  expect(drift < 1e-6, "double_pendulum relative energy drift", drift, 1e-6);
  std::printf("double_pendulum: ok, energy drift %.1e over 5 s\n", drift);
}

void check_swing() {
  std::vector<double> p(sw::kParamDefaults, sw::kParamDefaults + sw::kNp);
  const double l = p[index_of(sw::kParamNames, sw::kNp, "l")], g = p[index_of(sw::kParamNames, sw::kNp, "g")];
  auto at = [&](const char* name) { return index_of(sw::kStateNames, sw::kNx, name); };
  for (double th : {-2.5, -0.3, 0.0, 0.7, 1.9}) {
    const double w = 0.4 - th;
    std::vector<double> x(sw::kNx, 0.0), xdot(sw::kNx);
    x[at("th")] = th;
    x[at("w")] = w;
    x[at("bob.x")] = l * std::sin(th);
    x[at("bob.y")] = -l * std::cos(th);
    x[at("bob.u")] = l * std::cos(th) * w;
    x[at("bob.v")] = l * std::sin(th) * w;
    expect(sw::rhs(0.0, x.data(), nullptr, p.data(), xdot.data()) == 0, "swing rhs status", 1, 0);
    const double want = -g / l * std::sin(th);
    expect(std::abs(xdot[at("w")] - want) <= 1e-12 * (1 + std::abs(want)), "swing w'", xdot[at("w")], want);
  }
  std::printf("swing: ok, l = %g\n", l);
}

}  // namespace

int main() {
  check_double_pendulum();
  check_swing();
  return failures == 0 ? 0 : 1;
}
