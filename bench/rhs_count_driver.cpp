// SPDX-License-Identifier: GPL-2.0-or-later
// Instruction count of one generated rhs, for bench/count_rhs.sh: calls MODEL's rhs at
// 20 fixed pseudo-random states (entries uniform in [-1, 1], the same for every build
// and every version of mbsc, each unit quaternion of kQuaternionIndices then divided by
// its norm; parameters at their defaults, inputs 0.05) through
// count_calls(), the function callgrind's --toggle-collect measures, and prints
// count_calls=<calls>. The states need not satisfy the constraints: a complement rhs
// solves its systems at any state, and the count is of the code path, not the motion.
//   g++ -O2 -I GEN -DMODEL=four_bar -DHEADER='"four_bar/four_bar.hpp"' bench/rhs_count_driver.cpp GEN/four_bar/four_bar.cpp
#include <cstdio>
#include <random>
#include <vector>

#include "unit_quaternion_states.hpp"
#include HEADER

namespace gen = mbsc_gen::MODEL;

__attribute__((noinline, optimize("no-optimize-sibling-calls"))) int count_calls(const double* x, const double* u,
                                                                                 const double* p, double* out) {
  const int rc = gen::rhs(0.0, x, u, p, out);
  asm volatile("" ::: "memory");
  return rc;
}

int main() {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> dist(-1.0, 1.0);
  std::vector<double> p(gen::kParamDefaults, gen::kParamDefaults + gen::kNp);
  std::vector<double> u(static_cast<std::size_t>(gen::kNin > 0 ? gen::kNin : 1), 0.05);
  std::vector<double> out(static_cast<std::size_t>(gen::kNx));
  constexpr int kStates = 20;
  int calls = 0, failed = 0;
  double sink = 0.0;
  for (int s = 0; s < kStates; ++s) {
    std::vector<double> x(static_cast<std::size_t>(gen::kNx));
    for (double& v : x) v = dist(rng);
    normalize_unit_quaternions(x, gen::kQuaternionIndices, gen::kNquaternions);
    failed += count_calls(x.data(), u.data(), p.data(), out.data()) != 0;
    sink += out[0];
    ++calls;
  }
  std::printf("count_calls=%d\nfailed=%d\nsink=%g\n", calls, failed, sink);
  return 0;
}
