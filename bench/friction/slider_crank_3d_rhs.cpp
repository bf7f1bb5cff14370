// SPDX-License-Identifier: GPL-2.0-or-later
// The cost of one rhs call of the 3-D slider-crank (docs/benchmarks.md, "Coulomb friction
// closed in the generated code"): build against one generated/slider_crank_3d folder,
//   g++ -O2 -std=c++17 -IDIR bench/friction/slider_crank_3d_rhs.cpp DIR/slider_crank_3d/slider_crank_3d.cpp
// The state is the model's reference configuration with the crank at 2 rad/s; the model
// with its friction as an input (before issue 12) takes two inputs, the second ignored
// there after.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>
#include <string>
#include "slider_crank_3d/slider_crank_3d.hpp"
namespace C = mbsc_gen::slider_crank_3d;
int main() {
  // the model's initial state (reference configuration, crank at 2 rad/s)
  std::vector<double> x(C::kNx, 0.0), xd(C::kNx);
  auto set = [&](const char* n, double v) { for (int i = 0; i < C::kNx; ++i) if (std::string(C::kStateNames[i]) == n) x[i] = v; };
  const double l1 = 0.5, l2 = std::sqrt(2.0), g2 = std::sqrt(2.0) / 2;
  set("crank.e0", 1); set("crank.wx", 2); set("rod.x", g2 * l2); set("rod.y", -l1); set("slider.e0", 1);
  set("slider.x", l2); set("slider.y", -l1); set("rod.w", -l1 * 2 * (1 - g2)); set("rod.wy", 2 * l1 / l2);
  double u[2] = {0.3, 0.0};
  const int n = 200000;
  double acc = 0;
  auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < n; ++k) { x[0] += 1e-12;  // keep the call from being hoisted
    C::rhs(0, x.data(), u, C::kParamDefaults, xd.data()); acc += xd[C::kNq]; }
  int st = C::rhs(0, x.data(), u, C::kParamDefaults, xd.data()); double wd = 0; for (int i = 0; i < C::kNx; ++i) if (std::string(C::kStateNames[i]) == "crank.wx") wd = xd[i];
  std::printf("status %d crank.wx dot %g\n", st, wd);
  auto t1 = std::chrono::steady_clock::now();
  std::printf("%.3f us per rhs (%g)\n", std::chrono::duration<double, std::micro>(t1 - t0).count() / n, acc);
}
