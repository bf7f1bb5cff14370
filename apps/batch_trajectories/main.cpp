// SPDX-License-Identifier: GPL-2.0-or-later WITH mbsc-runtime-exception
// (see LICENSE: this file may be copied into applications under any terms)
//
// Integrates an ensemble of N double pendulums (ensemble.hpp) with RK4 on every core:
// the ensemble is split into one chunk per thread, and each thread steps its chunk in
// lockstep through the generated batched rhs (dp::rhs_batch, struct-of-arrays). Checks
// a few trajectories against the ordinary rhs integrated alone (they must agree bit for
// bit) and the energy drift, and prints the throughput.
//
//   batch_trajectories [N] [steps] [threads]     (defaults 4000, 2000, all cores)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "ensemble.hpp"
#include "mbsc/runtime/batch.hpp"
#include "mbsc/runtime/rk4.hpp"

namespace dp = mbsc_gen::dp;

namespace {

int arg(int argc, char** argv, int i, int fallback) {
  if (argc <= i) return fallback;
  char* end = nullptr;
  const long v = std::strtol(argv[i], &end, 10);
  if (*end != '\0' || v < 0 || v > 100000000) {
    std::fprintf(stderr, "batch_trajectories: argument %d: expected a count, got '%s'\n", i, argv[i]);
    std::exit(2);
  }
  return static_cast<int>(v);
}

}  // namespace

int main(int argc, char** argv) {
  const int n = std::max(1, arg(argc, argv, 1, 4000));
  const int steps = std::max(1, arg(argc, argv, 2, 2000));
  const int threads = arg(argc, argv, 3, 0);
  const double h = ensemble::kTEnd / steps;
  ensemble::Ensemble e = ensemble::make(n);
  const std::vector<double> e0 = ensemble::energies(e);
  const ensemble::Ensemble start = e;

  std::vector<int> status(static_cast<std::size_t>(n), 0);
  const auto t0 = std::chrono::steady_clock::now();
  mbsc::runtime::parallel_chunks(n, threads, [&](int begin, int end) {
    dp::BatchArrays a;
    a.p = e.p.data() + begin;  // the chunk's columns of the parameters
    a.ldp = n;
    mbsc::runtime::Rk4BatchWork work;
    for (int s = 0; s < steps; ++s)
      mbsc::runtime::rk4_batch_step(dp::rhs_batch, a, end - begin, dp::kNx, s * h, h, e.x.data() + begin, n, work,
                                    status.data() + begin);
  });
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  int failed = 0;
  for (int s : status) failed += s != 0;

  // Three trajectories again, alone, with the ordinary rhs: the same bits.
  double largest_difference = 0.0;
  for (int i : {0, n / 2, n - 1}) {
    std::vector<double> x = ensemble::column(start.x, dp::kNx, n, i);
    const std::vector<double> p = ensemble::column(start.p, dp::kNp, n, i);
    auto f = [&](double t, const double* s, double* sdot) { return dp::rhs(t, s, nullptr, p.data(), sdot); };
    for (int s = 0; s < steps; ++s) mbsc::runtime::rk4_step(f, s * h, h, x);
    const std::vector<double> batched = ensemble::column(e.x, dp::kNx, n, i);
    for (int k = 0; k < dp::kNx; ++k)
      largest_difference = std::max(largest_difference, std::abs(batched[static_cast<std::size_t>(k)] - x[static_cast<std::size_t>(k)]));
  }
  const double drift = ensemble::energy_drift(e, e0);
  const double rhs_calls = 4.0 * n * steps;
  const int used = std::min(n, threads > 0 ? threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
  std::printf("%d double pendulums, %d RK4 steps of %g s, %d thread(s): %.3f s, %.3g steps/s, %.3g ns per rhs\n", n,
              steps, h, used, seconds,
              n * static_cast<double>(steps) / seconds, seconds / rhs_calls * 1e9);
  std::printf("failed trajectories %d; largest |batched - alone| over 3 trajectories %.3g; largest relative energy drift %.3g\n",
              failed, largest_difference, drift);
  // RK4 at h = 1 ms keeps the energy of these swings to about 1e-6.
  return failed == 0 && largest_difference == 0.0 && drift < 1e-4 ? 0 : 1;
}
