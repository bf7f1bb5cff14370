// SPDX-License-Identifier: GPL-2.0-or-later
// Per-state cost of a generated rhs over many states (bench/run_batch.sh): N random
// states (seeded), the model's default parameters shared by all, evaluated
//   serial   : rhs(t, x_i, u, p, xdot_i) in a loop, states side by side (AoS);
//   batch 1  : NAME_rhs_batch over the struct-of-arrays batch on one thread;
//   batch all: the same split over every core (mbsc::runtime::parallel_chunks).
// Prints one CSV line: model, N, threads, ns per state of each, and the agreement of
// both batched results with the serial ones (largest |difference| and the count of
// values whose bits differ; the batch promises 0 and 0).
//   g++ -O2 -DMODEL_HEADER='"m/m.hpp"' -DMODEL_NS=m batch_driver.cpp m/m.cpp -pthread
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <thread>
#include <vector>

#include MODEL_HEADER
#include "mbsc/runtime/batch.hpp"

namespace m = mbsc_gen::MODEL_NS;

namespace {

// Seconds per repetition of f, repeated until `budget` seconds have passed (at least 3 times).
template <class F>
double seconds_per_run(F&& f, double budget) {
  int runs = 0;
  const auto t0 = std::chrono::steady_clock::now();
  double elapsed = 0.0;
  while (runs < 3 || elapsed < budget) {
    f();
    ++runs;
    elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  return elapsed / runs;
}

// The passes callgrind counts (bench/run_batch.sh toggles collection on these names).
__attribute__((noinline)) void serial_pass(int n, double t, const double* aos, const double* u, const double* p, double* out,
                                           int* status) {
  for (int i = 0; i < n; ++i)
    status[i] = m::rhs(t, aos + static_cast<std::size_t>(i) * m::kNx, u, p, out + static_cast<std::size_t>(i) * m::kNx);
}

__attribute__((noinline)) void batch_pass(int n, const m::BatchArrays& a, int* status) { m::rhs_batch(n, a, status); }

}  // namespace

int main(int argc, char** argv) {
  const int n = argc > 1 ? std::atoi(argv[1]) : 4096;
  const double budget = argc > 2 ? std::atof(argv[2]) : 1.0;
  const int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::mt19937 rng(20261206);
  std::uniform_real_distribution<double> d(-0.8, 0.8);
  std::vector<double> aos(static_cast<std::size_t>(m::kNx) * n), soa(aos.size());
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < m::kNx; ++k) {
      const double v = d(rng);
      aos[static_cast<std::size_t>(i) * m::kNx + k] = v;
      soa[static_cast<std::size_t>(k) * n + i] = v;
    }
  std::vector<double> u(static_cast<std::size_t>(m::kNin) + 1, 0.1);
  const double* p = m::kParamDefaults;
  std::vector<double> serial(aos.size()), one(aos.size()), all(aos.size());
  std::vector<int> serial_status(static_cast<std::size_t>(n));
  const double t = 0.3;

  const double s_serial =
      seconds_per_run([&] { serial_pass(n, t, aos.data(), u.data(), p, serial.data(), serial_status.data()); }, budget);
  m::BatchArrays a;
  a.t = &t;
  a.x = soa.data();
  a.ldx = n;
  a.u = u.data();
  a.ldu = 0;
  a.p = p;
  a.ldp = 0;
  a.ldout = n;
  std::vector<int> status(static_cast<std::size_t>(n));
  const double s_one = seconds_per_run([&] {
    m::BatchArrays b = a;
    b.out = one.data();
    batch_pass(n, b, status.data());
  }, budget);
  const double s_all = seconds_per_run([&] {
    mbsc::runtime::parallel_chunks(n, threads, [&](int begin, int end) {
      m::BatchArrays b = a;
      b.out = all.data();
      b = mbsc::runtime::batch_slice(b, begin);
      m::rhs_batch(end - begin, b, status.data() + begin);
    });
  }, budget);

  double largest = 0.0;
  long differing = 0;
  int failed = 0;
  for (int i = 0; i < n; ++i) {
    failed += serial_status[static_cast<std::size_t>(i)] != 0;
    for (int k = 0; k < m::kNx; ++k) {
      const double s = serial[static_cast<std::size_t>(i) * m::kNx + k];
      for (const auto* b : {&one, &all}) {
        const double v = (*b)[static_cast<std::size_t>(k) * n + i];
        if (std::memcmp(&s, &v, sizeof s) != 0 && !(std::isnan(s) && std::isnan(v))) ++differing;
        if (std::isfinite(s) && std::isfinite(v)) largest = std::max(largest, std::fabs(s - v));
      }
    }
  }
  std::printf("%s,%d,%d,%.2f,%.2f,%.2f,%.3g,%ld,%d\n", MODEL_NAME, n, threads, s_serial / n * 1e9,
              s_one / n * 1e9, s_all / n * 1e9, largest, differing, failed);
  return differing == 0 ? 0 : 1;
}
