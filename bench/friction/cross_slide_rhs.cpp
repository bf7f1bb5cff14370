// SPDX-License-Identifier: GPL-2.0-or-later
// The cost of one rhs call of the cross slide with friction in two joints, solved together
// (docs/benchmarks.md, "Coulomb friction closed in the generated code"): build against the
// generated folder of tests/data/friction/cross_slide.mbs,
//   g++ -O2 -std=c++17 -IDIR bench/friction/cross_slide_rhs.cpp DIR/cross_slide/cross_slide.cpp
// or, with -DFRICTION_AS_INPUTS, of cross_slide_input.mbs (the friction forces as inputs,
// here 0: the cost without the closure). The state is the model's initial one (both
// joints sliding, the carriage not turning), the inputs f1 = 20 N, f2 = -6 N.
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>
#ifdef FRICTION_AS_INPUTS
#include "cross_slide_input/cross_slide_input.hpp"
namespace C = mbsc_gen::cross_slide_input;
#else
#include "cross_slide/cross_slide.hpp"
namespace C = mbsc_gen::cross_slide;
#endif
int main() {
  std::vector<double> x(C::kNx, 0.0), xd(C::kNx);
  auto set = [&](const char* n, double v) {
    for (int i = 0; i < C::kNx; ++i)
      if (std::string(C::kStateNames[i]) == n) x[static_cast<std::size_t>(i)] = v;
  };
  set("table.e0", 1), set("table.u", 1), set("carriage.e0", 1), set("carriage.z", 0.2);
  set("carriage.u", 1), set("carriage.v", -1);
  const double u[4] = {20.0, -6.0, 0.0, 0.0};
  const int n = 200000;
  double acc = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < n; ++k) {
    x[0] += 1e-12;  // keep the call from being hoisted
    C::rhs(0, x.data(), u, C::kParamDefaults, xd.data());
    acc += xd[C::kNq];
  }
  const auto t1 = std::chrono::steady_clock::now();
  const int st = C::rhs(0, x.data(), u, C::kParamDefaults, xd.data());
  std::printf("status %d table.u dot %.6f\n", st, xd[C::kNq]);
  std::printf("%.3f us per rhs (%g)\n", std::chrono::duration<double, std::micro>(t1 - t0).count() / n, acc);
}
