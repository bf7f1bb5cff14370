// SPDX-License-Identifier: GPL-2.0-or-later
// Agreement of two generated rhs of the same model (bench/run_spatial_chain.sh): MODEL_A
// and MODEL_B (e.g. the tree recursion and the dense Cholesky of one spatial chain) at 100
// pseudo-random states, entries uniform in [-1.5, 1.5] (each unit quaternion of the state,
// kQuaternionIndices, then divided by its norm), parameters at their defaults. Prints max |a - b| / max(1, |a|_inf) over the states, and failed=<calls with status != 0>.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "unit_quaternion_states.hpp"
#include HEADER_A
#include HEADER_B

namespace a = mbsc_gen::MODEL_A;
namespace b = mbsc_gen::MODEL_B;

int main() {
  static_assert(a::kNx == b::kNx, "the two builds must have the same state");
  std::mt19937 rng(20261205);
  std::uniform_real_distribution<double> dist(-1.5, 1.5);
  std::vector<double> p(a::kParamDefaults, a::kParamDefaults + a::kNp);
  std::vector<double> x(a::kNx), xa(a::kNx), xb(a::kNx);
  double worst = 0.0;
  int failed = 0;
  for (int s = 0; s < 100; ++s) {
    for (double& v : x) v = dist(rng);
    normalize_unit_quaternions(x, a::kQuaternionIndices, a::kNquaternions);
    failed += a::rhs(0.0, x.data(), nullptr, p.data(), xa.data()) != 0;
    failed += b::rhs(0.0, x.data(), nullptr, p.data(), xb.data()) != 0;
    double scale = 1.0, diff = 0.0;
    for (int i = 0; i < a::kNx; ++i) {
      scale = std::max(scale, std::fabs(xa[static_cast<std::size_t>(i)]));
      diff = std::max(diff, std::fabs(xa[static_cast<std::size_t>(i)] - xb[static_cast<std::size_t>(i)]));
    }
    worst = std::max(worst, diff / scale);
  }
  std::printf("agreement=%.3g\nfailed=%d\n", worst, failed);
  return failed != 0;
}
