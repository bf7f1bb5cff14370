// SPDX-License-Identifier: GPL-2.0-or-later WITH mbsc-runtime-exception
// (see LICENSE: this file may be copied into applications under any terms)
//
// The ensemble of main.cpp on a GPU: one CUDA thread integrates one double pendulum with
// RK4, calling the generated rhs as device code. The generated source is included here,
// after MBSC_HOST_DEVICE is defined, so that its functions compile for host and device
// in this one translation unit. Checks three trajectories against the ordinary rhs on
// the CPU and the energy drift, and prints the throughput. Exits 77 (skipped) where
// there is no CUDA device.
//
//   nvcc -std=c++17 -O3 -fmad=false -I<mbsc include> -I<generated folder> main.cu
//   batch_trajectories_cuda [N] [steps]          (defaults 4000, 2000)
#define MBSC_HOST_DEVICE __host__ __device__
#include "dp/dp.cpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include <cuda_runtime.h>

#include "ensemble.hpp"
#include "mbsc/runtime/rk4.hpp"

namespace dp = mbsc_gen::dp;

namespace {

// Trajectory i (column i of x and p) over `steps` RK4 steps, the arithmetic of rk4_step.
__global__ void integrate(int n, int steps, double h, double* x, const double* p, int* status) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  constexpr int nx = dp::kNx;
  double xi[nx], pi[dp::kNp], k1[nx], k2[nx], k3[nx], k4[nx], s[nx];
  for (int k = 0; k < nx; ++k) xi[k] = x[static_cast<long long>(k) * n + i];
  for (int k = 0; k < dp::kNp; ++k) pi[k] = p[static_cast<long long>(k) * n + i];
  int code = 0;
  for (int step = 0; step < steps && code == 0; ++step) {
    const double t = step * h;
    code = dp::rhs(t, xi, nullptr, pi, k1);
    for (int k = 0; k < nx; ++k) s[k] = xi[k] + 0.5 * h * k1[k];
    code = code ? code : dp::rhs(t + 0.5 * h, s, nullptr, pi, k2);
    for (int k = 0; k < nx; ++k) s[k] = xi[k] + 0.5 * h * k2[k];
    code = code ? code : dp::rhs(t + 0.5 * h, s, nullptr, pi, k3);
    for (int k = 0; k < nx; ++k) s[k] = xi[k] + h * k3[k];
    code = code ? code : dp::rhs(t + h, s, nullptr, pi, k4);
    if (code == 0)
      for (int k = 0; k < nx; ++k) xi[k] += h / 6.0 * (k1[k] + 2.0 * k2[k] + 2.0 * k3[k] + k4[k]);
  }
  for (int k = 0; k < nx; ++k) x[static_cast<long long>(k) * n + i] = xi[k];
  status[i] = code;
}

// The derivatives of every pendulum at once through the batched entry point, one thread each.
__global__ void derivatives(int n, dp::BatchArrays a, int* status) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) status[i] = dp::rhs_at(i, a);
}

int count_argument(int argc, char** argv, int i, int fallback) {
  if (argc <= i) return fallback;
  char* end = nullptr;
  const long v = std::strtol(argv[i], &end, 10);
  if (*end != '\0' || v < 1 || v > 100000000) {
    std::fprintf(stderr, "batch_trajectories_cuda: argument %d: expected a count from 1 to 1e8, got '%s'\n", i, argv[i]);
    std::exit(2);
  }
  return static_cast<int>(v);
}

bool cuda_ok(cudaError_t e, const char* what) {
  if (e == cudaSuccess) return true;
  std::fprintf(stderr, "batch_trajectories_cuda: %s: %s\n", what, cudaGetErrorString(e));
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  const int n = count_argument(argc, argv, 1, 4000);
  const int steps = count_argument(argc, argv, 2, 2000);
  int devices = 0;
  if (cudaGetDeviceCount(&devices) != cudaSuccess || devices == 0) {
    std::printf("no CUDA device here: skipped\n");
    return 77;
  }
  const double h = ensemble::kTEnd / steps;
  ensemble::Ensemble e = ensemble::make(n);
  const std::vector<double> e0 = ensemble::energies(e);
  const ensemble::Ensemble start = e;
  double *x = nullptr, *p = nullptr;
  int* status = nullptr;
  const std::size_t xb = e.x.size() * sizeof(double), pb = e.p.size() * sizeof(double);
  if (!cuda_ok(cudaMalloc(&x, xb), "cudaMalloc") || !cuda_ok(cudaMalloc(&p, pb), "cudaMalloc") ||
      !cuda_ok(cudaMalloc(&status, n * sizeof(int)), "cudaMalloc") ||
      !cuda_ok(cudaMemcpy(x, e.x.data(), xb, cudaMemcpyHostToDevice), "cudaMemcpy") ||
      !cuda_ok(cudaMemcpy(p, e.p.data(), pb, cudaMemcpyHostToDevice), "cudaMemcpy"))
    return 1;
  // First the batched rhs at the start, on the device and on the host.
  double* xdot = nullptr;
  if (!cuda_ok(cudaMalloc(&xdot, xb), "cudaMalloc")) return 1;
  dp::BatchArrays a;
  a.x = x;
  a.ldx = n;
  a.p = p;
  a.ldp = n;
  a.out = xdot;
  a.ldout = n;
  derivatives<<<(n + 127) / 128, 128>>>(n, a, status);
  std::vector<double> device_xdot(e.x.size()), host_xdot(e.x.size());
  if (!cuda_ok(cudaGetLastError(), "launch") || !cuda_ok(cudaDeviceSynchronize(), "kernel") ||
      !cuda_ok(cudaMemcpy(device_xdot.data(), xdot, xb, cudaMemcpyDeviceToHost), "cudaMemcpy"))
    return 1;
  cudaFree(xdot);
  dp::BatchArrays h_a;
  h_a.x = e.x.data();
  h_a.ldx = n;
  h_a.p = e.p.data();
  h_a.ldp = n;
  h_a.out = host_xdot.data();
  h_a.ldout = n;
  dp::rhs_batch(n, h_a, nullptr);
  double rhs_difference = 0.0;
  for (std::size_t j = 0; j < host_xdot.size(); ++j)
    rhs_difference = std::max(rhs_difference, std::abs(device_xdot[j] - host_xdot[j]) / std::max(1.0, std::abs(host_xdot[j])));

  const auto t0 = std::chrono::steady_clock::now();
  integrate<<<(n + 127) / 128, 128>>>(n, steps, h, x, p, status);
  if (!cuda_ok(cudaGetLastError(), "launch") || !cuda_ok(cudaDeviceSynchronize(), "kernel")) return 1;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::vector<int> codes(static_cast<std::size_t>(n));
  if (!cuda_ok(cudaMemcpy(e.x.data(), x, xb, cudaMemcpyDeviceToHost), "cudaMemcpy") ||
      !cuda_ok(cudaMemcpy(codes.data(), status, n * sizeof(int), cudaMemcpyDeviceToHost), "cudaMemcpy"))
    return 1;
  cudaFree(x);
  cudaFree(p);
  cudaFree(status);
  int failed = 0;
  for (int c : codes) failed += c != 0;
  // Three trajectories on the CPU with the ordinary rhs.
  double largest_difference = 0.0;
  for (int i : {0, n / 2, n - 1}) {
    std::vector<double> xs = ensemble::column(start.x, dp::kNx, n, i);
    const std::vector<double> ps = ensemble::column(start.p, dp::kNp, n, i);
    auto f = [&](double t, const double* s, double* sdot) { return dp::rhs(t, s, nullptr, ps.data(), sdot); };
    for (int s = 0; s < steps; ++s) mbsc::runtime::rk4_step(f, s * h, h, xs);
    const std::vector<double> gpu = ensemble::column(e.x, dp::kNx, n, i);
    for (int k = 0; k < dp::kNx; ++k)
      largest_difference = std::max(largest_difference, std::abs(gpu[static_cast<std::size_t>(k)] - xs[static_cast<std::size_t>(k)]));
  }
  const double drift = ensemble::energy_drift(e, e0);
  std::printf("%d double pendulums, %d RK4 steps of %g s on the GPU: %.3f s, %.3g steps/s, %.3g ns per rhs\n", n, steps,
              h, seconds, n * static_cast<double>(steps) / seconds, seconds / (4.0 * n * steps) * 1e9);
  std::printf("rhs_at on the device against rhs_batch on the host: largest relative difference %.3g\n", rhs_difference);
  std::printf("failed trajectories %d; largest |GPU - CPU| over 3 trajectories %.3g; largest relative energy drift %.3g\n",
              failed, largest_difference, drift);
  // The device's sin, cos and sqrt round differently from the host's: agreement to
  // rounding in one evaluation, and after 2 s of these chaotic swings a difference that
  // rounding has grown (bounds not yet measured on a device: loose).
  return failed == 0 && rhs_difference < 1e-13 && largest_difference < 1e-6 && drift < 1e-4 ? 0 : 1;
}
