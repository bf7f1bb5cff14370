// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The batched rhs of a generated model (rhs_at, rhs_batch, the C mbsc_NAME_rhs_batch)
/// against the ordinary rhs, instance by instance: struct-of-arrays columns with padded
/// leading dimensions, shared parameters and times (ld = 0), a NaN instance, and layouts
/// the batch must refuse without writing anything (docs/batched.md). Where an instance
/// fails, the values its rhs did not write read NaN, as in an output filled with NaN first.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

namespace mbsc_test {

/// A batch array: `rows` values for each of n instances, column i of an SoA matrix with
/// leading dimension ld (> n: the padding holds a sentinel that nothing may read or write).
struct SoaMatrix {
  static constexpr double kPad = -7.25e300;
  int rows = 0, ld = 0;
  std::vector<double> data;
  SoaMatrix(int rows_, int ld_) : rows(rows_), ld(ld_), data(static_cast<std::size_t>(rows_ * ld_ + 1), kPad) {}
  double& at(int k, int i) { return data[static_cast<std::size_t>(k * ld + i)]; }
  const double* ptr() const { return rows == 0 ? nullptr : data.data(); }
};

inline bool same_double(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0 || (std::isnan(a) && std::isnan(b)); }

template <class M>
void check_batch(std::mt19937& rng) {
  INFO("batched rhs of " << M::kName);
  const int n = 9, ld = n + 3;
  std::uniform_real_distribution<double> d(-0.8, 0.8);
  SoaMatrix t(1, ld), x(M::kNx, ld), u(M::kNin, ld + 1), p(M::kNp, ld), out(M::kNx, ld + 2);
  for (int i = 0; i < n; ++i) {
    t.at(0, i) = 0.1 * i;
    for (int k = 0; k < M::kNx; ++k) x.at(k, i) = d(rng);
    for (int k = 0; k < M::kNin; ++k) u.at(k, i) = d(rng);
    // Each instance its own parameters: the defaults scaled by 1 +- 10 %.
    for (int k = 0; k < M::kNp; ++k) p.at(k, i) = M::kParamDefaults[k] * (1.0 + 0.1 * d(rng));
  }
  for (int k = 0; k < M::kNx; ++k) x.at(k, n - 1) = std::nan("");  // the last instance reports 2 on its own
  typename M::BatchArrays a;
  a.t = t.ptr();
  a.ldt = t.ld;
  a.x = x.ptr();
  a.ldx = x.ld;
  a.u = u.ptr();
  a.ldu = u.ld;
  a.p = p.ptr();
  a.ldp = p.ld;
  a.out = out.data.data();
  a.ldout = out.ld;
  std::vector<int> status(static_cast<std::size_t>(n), -1);
  const int worst = M::rhs_batch(n, a, status.data());

  // Instance by instance against rhs on the gathered columns: the same bits, the same status.
  int expected_worst = 0;
  for (int i = 0; i < n; ++i) {
    INFO("instance " << i);
    std::vector<double> xi(static_cast<std::size_t>(M::kNx)), ui(static_cast<std::size_t>(M::kNin) + 1),
        pi(static_cast<std::size_t>(M::kNp) + 1), xdot(static_cast<std::size_t>(M::kNx) + 1, std::nan(""));
    for (int k = 0; k < M::kNx; ++k) xi[static_cast<std::size_t>(k)] = x.at(k, i);
    for (int k = 0; k < M::kNin; ++k) ui[static_cast<std::size_t>(k)] = u.at(k, i);
    for (int k = 0; k < M::kNp; ++k) pi[static_cast<std::size_t>(k)] = p.at(k, i);
    const int code = M::rhs(t.at(0, i), xi.data(), ui.data(), pi.data(), xdot.data());
    REQUIRE(status[static_cast<std::size_t>(i)] == code);
    expected_worst = code > expected_worst ? code : expected_worst;
    for (int k = 0; k < M::kNx; ++k) REQUIRE(same_double(out.at(k, i), xdot[static_cast<std::size_t>(k)]));
    // One instance alone (what a GPU thread calls) writes the same column.
    SoaMatrix one(M::kNx, ld + 2);
    typename M::BatchArrays b = a;
    b.out = one.data.data();
    REQUIRE(M::rhs_at(i, b) == code);
    for (int k = 0; k < M::kNx; ++k) REQUIRE(same_double(one.at(k, i), xdot[static_cast<std::size_t>(k)]));
  }
  REQUIRE(worst == expected_worst);
  if (M::kNx > 0) REQUIRE(status[static_cast<std::size_t>(n - 1)] == 2);
  REQUIRE(worst == 2);
  // Padding and the rows beyond kNx were not written.
  for (int k = 0; k < M::kNx; ++k)
    for (int i = n; i < out.ld; ++i) REQUIRE(out.at(k, i) == SoaMatrix::kPad);
  REQUIRE(out.data.back() == SoaMatrix::kPad);

  // Shared time and parameters (ld = 0): every instance gets column 0 of them, as a batch
  // whose columns are copies of it does. The C entry point is the same call.
  SoaMatrix shared_out(M::kNx, n), copied_out(M::kNx, n), copied_p(M::kNp, n), copied_t(1, n);
  for (int i = 0; i < n; ++i) {
    copied_t.at(0, i) = 0.7;
    for (int k = 0; k < M::kNp; ++k) copied_p.at(k, i) = M::kParamDefaults[k];
  }
  const double shared_t = 0.7;
  const int s1 = M::c_rhs_batch(n, &shared_t, 0, x.ptr(), x.ld, u.ptr(), u.ld, M::kNp ? M::kParamDefaults : nullptr, 0,
                                shared_out.data.data(), shared_out.ld, nullptr);
  const int s2 = M::c_rhs_batch(n, copied_t.ptr(), copied_t.ld, x.ptr(), x.ld, u.ptr(), u.ld, copied_p.ptr(), copied_p.ld,
                                copied_out.data.data(), copied_out.ld, nullptr);
  REQUIRE(s1 == s2);
  for (int k = 0; k < M::kNx; ++k)
    for (int i = 0; i < n; ++i) REQUIRE(same_double(shared_out.at(k, i), copied_out.at(k, i)));

  // Layouts that cannot hold n instances: 3, and nothing written.
  SoaMatrix untouched(M::kNx, ld);
  auto refused = [&](typename M::BatchArrays bad, int count) {
    bad.out = untouched.data.data();
    bad.ldout = untouched.ld;
    const int code = M::rhs_batch(count, bad, nullptr);
    for (double v : untouched.data) REQUIRE(v == SoaMatrix::kPad);
    return code;
  };
  REQUIRE(refused(a, -1) == 3);
  if (M::kNx > 0) {
    typename M::BatchArrays bad = a;
    bad.ldx = n - 1;
    REQUIRE(refused(bad, n) == 3);
    bad = a;
    bad.x = nullptr;
    REQUIRE(refused(bad, n) == 3);
    bad = a;
    bad.ldout = n - 1;
    bad.out = untouched.data.data();
    REQUIRE(M::rhs_batch(n, bad, nullptr) == 3);
    for (double v : untouched.data) REQUIRE(v == SoaMatrix::kPad);
  }
  // u or p null: refused where rhs reads them; where it does not, the same values.
  for (int which = 0; which < 2; ++which) {
    if ((which == 0 ? M::kNin : M::kNp) == 0) continue;
    typename M::BatchArrays bad = a;
    (which == 0 ? bad.u : bad.p) = nullptr;
    SoaMatrix o(M::kNx, out.ld);
    bad.out = o.data.data();
    const int code = M::rhs_batch(n, bad, nullptr);
    if (code == 3) {
      for (double v : o.data) REQUIRE(v == SoaMatrix::kPad);
    } else {
      for (int k = 0; k < M::kNx; ++k)
        for (int i = 0; i < n; ++i) REQUIRE(same_double(o.at(k, i), out.at(k, i)));
    }
  }
  // A shared state (ldx = 0): every instance at instance 0's state, with its own t, u, p.
  {
    std::vector<double> x0(static_cast<std::size_t>(M::kNx));
    for (int k = 0; k < M::kNx; ++k) x0[static_cast<std::size_t>(k)] = x.at(k, 0);
    typename M::BatchArrays b = a;
    b.x = x0.data();
    b.ldx = 0;
    SoaMatrix o(M::kNx, out.ld);
    b.out = o.data.data();
    M::rhs_batch(n, b, nullptr);
    for (int i = 0; i < n; ++i) {
      std::vector<double> ui(static_cast<std::size_t>(M::kNin) + 1), pi(static_cast<std::size_t>(M::kNp) + 1),
          xdot(static_cast<std::size_t>(M::kNx) + 1, std::nan(""));
      for (int k = 0; k < M::kNin; ++k) ui[static_cast<std::size_t>(k)] = u.at(k, i);
      for (int k = 0; k < M::kNp; ++k) pi[static_cast<std::size_t>(k)] = p.at(k, i);
      M::rhs(t.at(0, i), x0.data(), ui.data(), pi.data(), xdot.data());
      for (int k = 0; k < M::kNx; ++k) REQUIRE(same_double(o.at(k, i), xdot[static_cast<std::size_t>(k)]));
    }
  }
  REQUIRE(refused(a, 0) == 0);  // an empty batch is valid and evaluates nothing
}

}  // namespace mbsc_test
