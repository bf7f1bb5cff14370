// SPDX-License-Identifier: GPL-2.0-or-later WITH mbsc-runtime-exception
// (see LICENSE: this header may be included in applications under any terms)
#pragma once
/// Many instances of one generated model at once, on the CPU (docs/batched.md): the
/// generated NAME_batch entry points work on a struct-of-arrays batch (BatchArrays,
/// value k of instance i at a[k * ld + i]); this header splits a batch over threads and
/// steps all of its instances with RK4 in lockstep. Header-only, standard library only.
#include <algorithm>
#include <cstddef>
#include <exception>
#include <system_error>
#include <thread>
#include <vector>

namespace mbsc::runtime {

/// Instances begin, begin + 1, ... of a batch as a batch of their own: every array with a
/// leading dimension moves to column `begin`; shared arrays (ld = 0) stay. `Arrays` is a
/// generated model's BatchArrays.
template <class Arrays>
Arrays batch_slice(Arrays a, int begin) {
  if (a.t != nullptr && a.ldt > 0) a.t += begin;
  if (a.x != nullptr && a.ldx > 0) a.x += begin;
  if (a.u != nullptr && a.ldu > 0) a.u += begin;
  if (a.p != nullptr && a.ldp > 0) a.p += begin;
  if (a.out != nullptr) a.out += begin;
  return a;
}

/// Calls work(begin, end) on contiguous chunks that cover [0, n), one per thread, and
/// returns when all are done; `threads` <= 0 takes the hardware's count. An exception
/// thrown by a chunk is rethrown here (the first one) after every thread has finished.
template <class Work>
void parallel_chunks(int n, int threads, Work work) {
  if (threads <= 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  threads = std::max(1, std::min(threads, n));
  if (threads == 1) {
    if (n > 0) work(0, n);
    return;
  }
  std::vector<std::thread> pool;
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(threads));
  auto chunk = [&work, &errors, n, threads](int k) {
    const int begin = static_cast<int>(static_cast<long long>(n) * k / threads);
    const int end = static_cast<int>(static_cast<long long>(n) * (k + 1) / threads);
    try {
      work(begin, end);
    } catch (...) {
      errors[static_cast<std::size_t>(k)] = std::current_exception();
    }
  };
  // Chunks 1 .. threads-1 on new threads, chunk 0 on this one; a thread that cannot be
  // started leaves its chunk to this one (the threads already started are joined).
  int started = 1;
  try {
    for (; started < threads; ++started) pool.emplace_back(chunk, started);
  } catch (const std::system_error&) {
  }
  for (int k = started; k < threads; ++k) chunk(k);
  chunk(0);
  for (auto& t : pool) t.join();
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
}

/// Scratch arrays of rk4_batch_step: four stage derivatives and a stage state, each
/// rows x n (leading dimension n).
struct Rk4BatchWork {
  std::vector<double> k1, k2, k3, k4, stage;
  std::vector<int> codes;  // the status of each instance in one stage
};

/// One classical RK4 step of n instances in lockstep, all at time t with step h: x holds
/// `rows` values per instance (exactly the model's kNx), leading dimension ld >= n
/// (columns n and beyond are not touched, so x may be a slice of a larger batch). `a`
/// gives the inputs and parameters (its t, x and out are set here); `rhs_batch` is the
/// generated NAME_batch (or anything with its signature). Each instance sees the
/// arithmetic of rk4_step (rk4.hpp), so while its rhs returns 0 its state is, bit for
/// bit, what rk4_step gives it alone. `status[i]` (n entries, may be null; the caller
/// zeroes them once) keeps the largest code instance i's rhs returned: where rk4_step
/// would stop, a failing instance here goes on as NaN while the others step. Returns the
/// largest code of the step, or 3, stepping nothing, when the layout is invalid.
template <class Arrays, class RhsBatch>
int rk4_batch_step(RhsBatch&& rhs_batch, Arrays a, int n, int rows, double t, double h, double* x, int ld,
                   Rk4BatchWork& w, int* status = nullptr) {
  if (n < 0 || ld < n || rows < 0) return 3;
  const std::size_t size = static_cast<std::size_t>(rows) * static_cast<std::size_t>(n);
  for (auto* v : {&w.k1, &w.k2, &w.k3, &w.k4, &w.stage})
    if (v->size() < size) v->resize(size);
  std::vector<int>& codes = w.codes;
  codes.assign(static_cast<std::size_t>(n), 0);
  int worst = 0;
  double stage_time = t;
  a.t = &stage_time;
  a.ldt = 0;
  a.ldout = n;
  auto stage = [&](const double* state, int state_ld, double* k) {
    a.x = state;
    a.ldx = state_ld;
    a.out = k;
    const int code = rhs_batch(n, a, codes.data());
    if (code == 3) return false;
    worst = std::max(worst, code);
    if (status != nullptr)
      for (int i = 0; i < n; ++i) status[i] = std::max(status[i], codes[static_cast<std::size_t>(i)]);
    return true;
  };
  // x + c h k into the stage state, row by row: each inner loop runs over contiguous
  // columns, which the compiler vectorizes.
  double* s = w.stage.data();
  auto combine = [&](double c, const std::vector<double>& k) {
    for (int r = 0; r < rows; ++r) {
      const double* xr = x + static_cast<std::ptrdiff_t>(r) * ld;
      const double* kr = k.data() + static_cast<std::ptrdiff_t>(r) * n;
      double* sr = s + static_cast<std::ptrdiff_t>(r) * n;
      for (int i = 0; i < n; ++i) sr[i] = xr[i] + c * h * kr[i];
    }
  };
  if (!stage(x, ld, w.k1.data())) return 3;
  combine(0.5, w.k1);
  stage_time = t + 0.5 * h;
  if (!stage(s, n, w.k2.data())) return 3;
  combine(0.5, w.k2);
  if (!stage(s, n, w.k3.data())) return 3;
  combine(1.0, w.k3);
  stage_time = t + h;
  if (!stage(s, n, w.k4.data())) return 3;
  for (int r = 0; r < rows; ++r) {
    double* xr = x + static_cast<std::ptrdiff_t>(r) * ld;
    const std::size_t o = static_cast<std::size_t>(r) * static_cast<std::size_t>(n);
    for (int i = 0; i < n; ++i)
      xr[i] += h / 6.0 * (w.k1[o + i] + 2.0 * w.k2[o + i] + 2.0 * w.k3[o + i] + w.k4[o + i]);
  }
  return worst;
}

}  // namespace mbsc::runtime
