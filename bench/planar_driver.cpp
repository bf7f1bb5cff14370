// SPDX-License-Identifier: GPL-2.0-or-later
// Benchmark driver for the planar mechanisms: one model, its complement build (C) and its
// multipliers build (M), compiled together by bench/run_planar.sh:
//   g++ -O2 -DMODEL=four_bar -I GEN bench/planar_driver.cpp GEN/four_bar/four_bar.cpp GEN/four_bar_mult/four_bar_mult.cpp
// It assembles a consistent state from the model's driving coordinate (DRIVER, a state
// name) and prints key=value lines: complement_ns, multipliers_ns (median of 5 loops of
// >= 0.3 s each over 50 states along the motion), max_rel_diff (accelerations of the two
// formulations at those states, relative to the largest).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "mbsc/runtime/assemble.hpp"
#include "mbsc/runtime/rk4.hpp"

#define STR2(x) #x
#define STR(x) STR2(x)
#define HDR(m) STR(m/m.hpp)
#define CAT2(a, b) a##b
#define CAT(a, b) CAT2(a, b)
#include HDR(MODEL)
#include HDR(CAT(MODEL, _mult))

namespace C = mbsc_gen::MODEL;
namespace M = mbsc_gen::CAT(MODEL, _mult);

namespace {

int index_of(const char* name) {
  for (int i = 0; i < C::kNx; ++i)
    if (std::string(name) == C::kStateNames[i]) return i;
  std::fprintf(stderr, "planar_driver: no state %s\n", name);
  std::exit(1);
}

using Fn = int (*)(double, const double*, const double*, const double*, double*);

double time_rhs(Fn f, const std::vector<std::vector<double>>& xs, const double* u, const double* p) {
  std::vector<double> out(C::kNx);
  std::vector<double> reps;
  long calls = 1000;
  double sink = 0.0;
  for (int rep = 0; rep < 6; ++rep) {
    for (;;) {
      const auto t0 = std::chrono::steady_clock::now();
      for (long i = 0; i < calls; ++i) {
        f(0.0, xs[static_cast<std::size_t>(i) % xs.size()].data(), u, p, out.data());
        sink += out[0];
      }
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (s < 0.3) {
        calls *= 2;
        continue;
      }
      if (rep > 0) reps.push_back(s * 1e9 / static_cast<double>(calls));  // the first is warm-up
      break;
    }
  }
  std::sort(reps.begin(), reps.end());
  if (sink == 42.0) std::printf("#\n");
  return reps[reps.size() / 2];
}

}  // namespace

int main() {
  const mbsc::runtime::AssemblyModel model{C::kNq,          C::kNu,          C::kNposc, C::kNc, C::position_constraints,
                                           C::position_jacobian, C::velocity_constraints, C::constraint_jacobian,
                                           C::kPositionConstraintNames, C::kConstraintNames};
  std::vector<double> x(C::kNx, 0.0);
  for (const auto& [name, value] : std::vector<std::pair<const char*, double>>{GUESS}) x[static_cast<std::size_t>(index_of(name))] = value;
  std::vector<bool> gq(C::kNq, false), gu(C::kNu, false);
  for (const char* n : {DRIVERS}) {
    const int i = index_of(n);
    if (i < C::kNq) gq[static_cast<std::size_t>(i)] = true;
    else gu[static_cast<std::size_t>(i - C::kNq)] = true;
  }
  std::vector<double> u(std::max(1, C::kNin), 0.05);
  const auto r = mbsc::runtime::assemble(model, 0.0, x, gq, gu, u.data(), C::kParamDefaults);
  if (!r.ok()) {
    std::fprintf(stderr, "planar_driver: %s\n", r.message.c_str());
    return 1;
  }
  std::vector<double> pm(C::kParamDefaults, C::kParamDefaults + C::kNp);
  pm.push_back(10.0);
  pm.push_back(10.0);
  // 50 states along 0.5 s of motion (complement rhs, RK4).
  std::vector<std::vector<double>> xs;
  auto f = [&](double t, const double* s, double* d) { return C::rhs(t, s, u.data(), C::kParamDefaults, d); };
  double worst = 0.0;
  for (int k = 0; k < 50; ++k) {
    if (mbsc::runtime::rk4_integrate(f, 0.0, 0.01, 20, x, [](double, const std::vector<double>&) {}) != 0) return 1;
    xs.push_back(x);
    std::vector<double> a(C::kNx), b(C::kNx);
    C::rhs(0.0, x.data(), u.data(), C::kParamDefaults, a.data());
    M::rhs(0.0, x.data(), u.data(), pm.data(), b.data());
    double scale = 0.0, diff = 0.0;
    for (int i = C::kNq; i < C::kNx; ++i) {
      scale = std::max(scale, std::fabs(a[static_cast<std::size_t>(i)]));
      diff = std::max(diff, std::fabs(a[static_cast<std::size_t>(i)] - b[static_cast<std::size_t>(i)]));
    }
    worst = std::max(worst, diff / std::max(scale, 1e-300));
  }
  std::printf("complement_ns=%.1f\n", time_rhs(C::rhs, xs, u.data(), C::kParamDefaults));
  std::printf("multipliers_ns=%.1f\n", time_rhs(M::rhs, xs, u.data(), pm.data()));
  std::printf("max_rel_diff=%.3e\n", worst);
  return 0;
}
