// SPDX-License-Identifier: GPL-2.0-or-later
// include/mbsc/runtime/batch.hpp with generated batches: each instance's own time (a
// model whose gravity grows with t), a batch split over threads by batch_slice against
// the batch whole, and rk4_batch_step against rk4_step instance by instance (equal bits)
// with padding, a slice of a wider batch and a failing instance. Also the functions
// batched with `--batch`: one with no outputs, and inverse_dynamics (zdot, unread where
// the model has no inputs), built with -Werror.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <mutex>
#include <vector>

#include "four_bar_batched/four_bar_batched.hpp"
#include "growing_gravity/growing_gravity.hpp"
#include "mbsc/runtime/batch.hpp"
#include "mbsc/runtime/rk4.hpp"

namespace gg = mbsc_gen::growing_gravity;
namespace fb = mbsc_gen::four_bar_batched;

namespace {

bool same(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

TEST_CASE("a batch gives each instance its own time", "[batch]") {
  static_assert(gg::kNx == 4 && gg::kNin == 0);
  const int n = 5;
  std::vector<double> t(n), x(static_cast<std::size_t>(gg::kNx) * n, 0.2), out(x.size());
  for (int i = 0; i < n; ++i) t[static_cast<std::size_t>(i)] = 0.5 * i;
  gg::BatchArrays a;
  a.t = t.data();
  a.ldt = n;
  a.x = x.data();
  a.ldx = n;
  a.p = gg::kParamDefaults;
  a.ldp = 0;
  a.out = out.data();
  a.ldout = n;
  REQUIRE(gg::rhs_batch(n, a, nullptr) == 0);
  const double c = gg::kParamDefaults[0];
  for (int i = 0; i < n; ++i) {
    // x'' = c t (the ball's mass cancels): the rate of u, row 2.
    CHECK(out[static_cast<std::size_t>(2 * n + i)] == Approx(c * t[static_cast<std::size_t>(i)]).margin(1e-15));
    CHECK(out[static_cast<std::size_t>(3 * n + i)] == Approx(-gg::kParamDefaults[1]));
  }
  // t null: t = 0 for all.
  a.t = nullptr;
  REQUIRE(gg::rhs_batch(n, a, nullptr) == 0);
  for (int i = 0; i < n; ++i) CHECK(out[static_cast<std::size_t>(2 * n + i)] == 0.0);
}

TEST_CASE("a batch split over threads by batch_slice equals the batch whole", "[batch]") {
  const int n = 37, ld = 40;
  std::vector<double> x(static_cast<std::size_t>(fb::kNx) * ld), whole(x.size(), 0.0), split(x.size(), 0.0);
  for (std::size_t j = 0; j < x.size(); ++j) x[j] = std::sin(0.37 * static_cast<double>(j));
  fb::BatchArrays a;
  a.x = x.data();
  a.ldx = ld;
  a.p = fb::kParamDefaults;
  a.out = whole.data();
  a.ldout = ld;
  std::vector<int> s1(n, -1), s2(n, -1);
  fb::rhs_batch(n, a, s1.data());
  mbsc::runtime::parallel_chunks(n, 3, [&](int begin, int end) {
    fb::BatchArrays b = a;
    b.out = split.data();
    b = mbsc::runtime::batch_slice(b, begin);
    fb::rhs_batch(end - begin, b, s2.data() + begin);
  });
  CHECK(s1 == s2);
  for (std::size_t j = 0; j < whole.size(); ++j) REQUIRE(same(whole[j], split[j]));
  // More threads than instances, and none.
  int calls = 0;
  std::mutex count;
  mbsc::runtime::parallel_chunks(2, 8, [&](int begin, int end) {
    std::lock_guard<std::mutex> lock(count);
    calls += end - begin;
  });
  CHECK(calls == 2);
  mbsc::runtime::parallel_chunks(0, 4, [&](int, int) { FAIL("no chunk for an empty range"); });
}

TEST_CASE("rk4_batch_step steps each instance as rk4_step does, bit for bit", "[batch]") {
  // Instances 3 .. 9 of a batch of 12 with leading dimension 14: a slice with padding.
  const int wide = 12, ld = 14, first = 3, n = 7, steps = 40;
  const double h = 0.01;
  std::vector<double> x(static_cast<std::size_t>(gg::kNx) * ld, -99.0);
  std::vector<std::vector<double>> alone;
  // The growing-gravity particle: its rhs reads t, so the stage times are checked too.
  for (int i = 0; i < wide; ++i)
    for (int k = 0; k < gg::kNx; ++k) x[static_cast<std::size_t>(k * ld + i)] = 0.1 * std::cos(0.3 * k + 0.7 * i);
  for (int i = first; i < first + n; ++i) {
    std::vector<double> xi(static_cast<std::size_t>(gg::kNx));
    for (int k = 0; k < gg::kNx; ++k) xi[static_cast<std::size_t>(k)] = x[static_cast<std::size_t>(k * ld + i)];
    alone.push_back(xi);
  }
  // The last instance fails: NaN state from the start.
  for (int k = 0; k < gg::kNx; ++k) x[static_cast<std::size_t>(k * ld + first + n - 1)] = std::nan("");
  const std::vector<double> before = x;
  gg::BatchArrays a;
  a.p = gg::kParamDefaults;
  mbsc::runtime::Rk4BatchWork work;
  std::vector<int> status(n, 0);
  int worst = 0;
  for (int s = 0; s < steps; ++s)
    worst = std::max(worst, mbsc::runtime::rk4_batch_step(gg::rhs_batch, a, n, gg::kNx, s * h, h, x.data() + first, ld,
                                                           work, status.data()));
  CHECK(worst == 2);
  for (int i = 0; i + 1 < n; ++i) {
    INFO("instance " << i);
    CHECK(status[static_cast<std::size_t>(i)] == 0);
    auto f = [](double t, const double* s, double* sdot) { return gg::rhs(t, s, nullptr, gg::kParamDefaults, sdot); };
    std::vector<double>& xi = alone[static_cast<std::size_t>(i)];
    for (int s = 0; s < steps; ++s) REQUIRE(mbsc::runtime::rk4_step(f, s * h, h, xi) == 0);
    for (int k = 0; k < gg::kNx; ++k) REQUIRE(same(x[static_cast<std::size_t>(k * ld + first + i)], xi[static_cast<std::size_t>(k)]));
  }
  CHECK(status[static_cast<std::size_t>(n - 1)] == 2);
  // Columns outside the slice and the padding are as they were.
  for (int k = 0; k < gg::kNx; ++k)
    for (int i = 0; i < ld; ++i)
      if (i < first || i >= first + n) REQUIRE(same(x[static_cast<std::size_t>(k * ld + i)], before[static_cast<std::size_t>(k * ld + i)]));
  // An invalid layout steps nothing.
  CHECK(mbsc::runtime::rk4_batch_step(gg::rhs_batch, a, n, gg::kNx, 0.0, h, x.data(), n - 1, work) == 3);
}

TEST_CASE("--batch: a function with no outputs and inverse_dynamics batch too", "[batch]") {
  // The four-bar has no inputs: inverse_dynamics writes nothing and reads no zdot.
  static_assert(fb::kNin == 0);
  const int n = 3;
  std::vector<double> x(static_cast<std::size_t>(fb::kNx) * n, 0.1), e(3 * n, 0.0);
  fb::BatchArrays a;
  a.x = x.data();
  a.ldx = n;
  a.p = fb::kParamDefaults;
  CHECK(fb::inverse_dynamics_batch(n, a, nullptr) == 0);  // zdot null: unread
  a.out = e.data();
  a.ldout = n;
  REQUIRE(fb::energy_batch(n, a, nullptr) == 0);
  // Every instance is at the state with all values 0.1.
  double E[3];
  std::vector<double> x0(static_cast<std::size_t>(fb::kNx), 0.1);
  REQUIRE(fb::energy(0.0, x0.data(), nullptr, fb::kParamDefaults, E) == 0);
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) CHECK(same(e[static_cast<std::size_t>(k * n + i)], E[k]));
}
