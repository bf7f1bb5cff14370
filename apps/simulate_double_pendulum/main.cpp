// SPDX-License-Identifier: GPL-2.0-or-later
// Simulates the shipped double pendulum with the code mbsc generated at build time:
// starts at rest from th1 = 2.0, th2 = 2.5 rad, integrates 10 s with RK4 and prints the
// angles, the tip position and the energy drift.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "double_pendulum/double_pendulum.hpp"
#include "mbsc/runtime/rk4.hpp"

namespace dp = mbsc_gen::double_pendulum;

namespace {
int find(const char* const* names, int n, const char* name) {
  for (int i = 0; i < n; ++i)
    if (std::strcmp(names[i], name) == 0) return i;
  std::fprintf(stderr, "no variable named %s\n", name);
  std::exit(1);
}
int index_of(const char* name) { return find(dp::kStateNames, dp::kNx, name); }
}  // namespace

int main() {
  std::vector<double> p(dp::kParamDefaults, dp::kParamDefaults + dp::kNp);
  const double l1 = p[find(dp::kParamNames, dp::kNp, "l1")], l2 = p[find(dp::kParamNames, dp::kNp, "l2")];
  const double th1 = 2.0, th2 = 2.5;
  // A consistent initial state: angles given, bob positions from the constraints, at rest.
  std::vector<double> x(dp::kNx, 0.0);
  x[index_of("th1")] = th1;
  x[index_of("th2")] = th2;
  x[index_of("b1.x")] = l1 * std::sin(th1);
  x[index_of("b1.y")] = -l1 * std::cos(th1);
  x[index_of("b2.x")] = l1 * std::sin(th1) + l2 * std::sin(th2);
  x[index_of("b2.y")] = -l1 * std::cos(th1) - l2 * std::cos(th2);
  auto rhs = [&](double t, const double* s, double* sdot) { return dp::rhs(t, s, nullptr, p.data(), sdot); };
  double e0[3];
  dp::energy(0.0, x.data(), nullptr, p.data(), e0);
  std::printf("double pendulum, %d dof, state size %d; t, th1, th2, tip x, tip y, relative energy drift\n", dp::kNdof, dp::kNx);
  int step = 0;
  int status = mbsc::runtime::rk4_integrate(rhs, 0.0, 10.0, 40000, x, [&](double t, const std::vector<double>& s) {
    if (++step % 8000 != 0) return;
    double e[3], y[dp::kNy];
    dp::energy(t, s.data(), nullptr, p.data(), e);
    dp::outputs(t, s.data(), nullptr, p.data(), y);
    std::printf("%5.2f %10.6f %10.6f %10.6f %10.6f %10.3e\n", t, s[index_of("th1")], s[index_of("th2")], y[0], y[1],
                (e[2] - e0[2]) / std::abs(e0[2] == 0 ? 1.0 : e0[2]));
  });
  if (status != 0) {
    std::fprintf(stderr, "rhs failed with status %d\n", status);
    return 1;
  }
  return 0;
}
