// SPDX-License-Identifier: GPL-2.0-or-later
// The compiled O(N) rhs (--solver sparse) against the closed form of the planar N-link
// chain of point masses in absolute angles, solved in long double:
//   sum_j m l^2 c_ij cos(th_i - th_j) th_j'' = -m l^2 sum_j c_ij sin(th_i - th_j) w_j^2 - m g l (N - i + 1) sin th_i
// with c_ij = N - max(i, j) + 1 (the bobs at or below the lower rod), at 100 random
// states for N = 8 and 40, --state minimal and full; and the dense rhs (--solver dense)
// of the same models, whose error is reported beside it. Also the multipliers
// formulation's sparse rhs of two tree models against its dense one, and the operation
// counts: the sparse rhs grows linearly with N.
#include <catch2/catch.hpp>
#include <Eigen/Dense>

#include <cmath>
#include <random>
#include <string>

#include "chain8_dense/chain8_dense.hpp"
#include "chain8_sparse/chain8_sparse.hpp"
#include "chain40_dense/chain40_dense.hpp"
#include "chain40_full_sparse/chain40_full_sparse.hpp"
#include "chain40_sparse/chain40_sparse.hpp"
#include "dp_mult_dense/dp_mult_dense.hpp"
#include "dp_mult_sparse/dp_mult_sparse.hpp"
#include "arm_mult_dense/arm_mult_dense.hpp"
#include "arm_mult_sparse/arm_mult_sparse.hpp"

namespace {

using LMatrix = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
using LVector = Eigen::Matrix<long double, Eigen::Dynamic, 1>;

constexpr long double kM = 1.0L, kL = 1.0L, kG = 9.81L;

// The angular accelerations of the chain, in long double.
LVector chain_accelerations(const std::vector<double>& th, const std::vector<double>& w) {
  const int n = static_cast<int>(th.size());
  LMatrix M(n, n);
  LVector h(n);
  for (int i = 0; i < n; ++i) {
    long double hi = -kM * kG * kL * static_cast<long double>(n - i) * std::sin(static_cast<long double>(th[i]));
    for (int j = 0; j < n; ++j) {
      const long double c = static_cast<long double>(n - std::max(i, j));
      const long double d = static_cast<long double>(th[i]) - static_cast<long double>(th[j]);
      M(i, j) = kM * kL * kL * c * std::cos(d);
      hi -= kM * kL * kL * c * std::sin(d) * static_cast<long double>(w[j]) * static_cast<long double>(w[j]);
    }
    h(i) = hi;
  }
  return M.partialPivLu().solve(h);
}

int index_of(const char* const* names, int n, const std::string& name) {
  for (int i = 0; i < n; ++i)
    if (name == names[i]) return i;
  FAIL("no state named " << name);
  return -1;
}

// Relative error of one compiled minimal-state chain rhs against the closed form, worst
// over 100 random states. State: (th_k, w_k) by name.
template <class Rhs>
double chain_error(int n, const char* const* names, int nx, Rhs rhs, const std::vector<double>& p) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> angle(-3.1, 3.1), rate(-2.0, 2.0);
  double worst = 0.0;
  for (int trial = 0; trial < 100; ++trial) {
    std::vector<double> th(static_cast<std::size_t>(n)), w(static_cast<std::size_t>(n)), x(static_cast<std::size_t>(nx)),
        xdot(static_cast<std::size_t>(nx));
    for (int k = 0; k < n; ++k) {
      th[static_cast<std::size_t>(k)] = angle(rng);
      w[static_cast<std::size_t>(k)] = rate(rng);
      x[static_cast<std::size_t>(index_of(names, nx, "th_" + std::to_string(k + 1)))] = th[static_cast<std::size_t>(k)];
      x[static_cast<std::size_t>(index_of(names, nx, "w_" + std::to_string(k + 1)))] = w[static_cast<std::size_t>(k)];
    }
    REQUIRE(rhs(0.0, x.data(), nullptr, p.data(), xdot.data()) == 0);
    const LVector ref = chain_accelerations(th, w);
    long double scale = 0, err = 0;
    for (int k = 0; k < n; ++k) scale = std::max(scale, std::fabs(ref(k)));
    for (int k = 0; k < n; ++k) {
      const int i = index_of(names, nx, "w_" + std::to_string(k + 1));
      err = std::max(err, std::fabs(static_cast<long double>(xdot[static_cast<std::size_t>(i)]) - ref(k)));
      // The angle rates are the speeds themselves.
      const int j = index_of(names, nx, "th_" + std::to_string(k + 1));
      CHECK(xdot[static_cast<std::size_t>(j)] == w[static_cast<std::size_t>(k)]);
    }
    worst = std::max(worst, static_cast<double>(err / scale));
  }
  return worst;
}

}  // namespace

TEST_CASE("the compiled sparse rhs of the N-link chain against its closed form in long double", "[sparse]") {
  namespace s8 = mbsc_gen::chain8_sparse;
  namespace d8 = mbsc_gen::chain8_dense;
  namespace s40 = mbsc_gen::chain40_sparse;
  namespace d40 = mbsc_gen::chain40_dense;
  const std::vector<double> p8(s8::kParamDefaults, s8::kParamDefaults + s8::kNp);
  const std::vector<double> p40(s40::kParamDefaults, s40::kParamDefaults + s40::kNp);
  const double e8 = chain_error(8, s8::kStateNames, s8::kNx, s8::rhs, p8);
  const double e8d = chain_error(8, d8::kStateNames, d8::kNx, d8::rhs, p8);
  const double e40 = chain_error(40, s40::kStateNames, s40::kNx, s40::rhs, p40);
  const double e40d = chain_error(40, d40::kStateNames, d40::kNx, d40::rhs, p40);
  INFO("relative errors: N = 8 sparse " << e8 << ", dense " << e8d << "; N = 40 sparse " << e40 << ", dense " << e40d);
  CHECK(e8 < 1e-13);
  CHECK(e40 < 1e-13);
  // The sparse form is not less accurate than the dense one.
  CHECK(e40 <= std::max(4 * e40d, 1e-14));
}

TEST_CASE("the full-state sparse rhs of the chain equals the minimal-state one", "[sparse]") {
  namespace f = mbsc_gen::chain40_full_sparse;
  namespace s = mbsc_gen::chain40_sparse;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(-3.1, 3.1), rate(-2.0, 2.0);
  const std::vector<double> p(s::kParamDefaults, s::kParamDefaults + s::kNp);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<double> xm(s::kNx), xf(f::kNx), dm(s::kNx), df(f::kNx);
    for (auto& v : xm) v = angle(rng);
    for (int i = s::kNq; i < s::kNx; ++i) xm[static_cast<std::size_t>(i)] = rate(rng);
    // The consistent full state, from the minimal one.
    REQUIRE(s::full_state(0, xm.data(), nullptr, p.data(), xf.data()) == 0);
    REQUIRE(s::rhs(0, xm.data(), nullptr, p.data(), dm.data()) == 0);
    REQUIRE(f::rhs(0, xf.data(), nullptr, p.data(), df.data()) == 0);
    for (int i = 0; i < s::kNx; ++i) {
      const int j = index_of(f::kStateNames, f::kNx, s::kStateNames[i]);
      CHECK(df[static_cast<std::size_t>(j)] == Approx(dm[static_cast<std::size_t>(i)]).margin(1e-12));
    }
  }
}

TEST_CASE("multipliers formulation: the sparse rhs equals the dense one", "[sparse]") {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> val(-1.5, 1.5);
  auto compare = [&](auto dense_rhs, auto sparse_rhs, int nx, const double* defaults, int np) {
    std::vector<double> p(defaults, defaults + np), x(static_cast<std::size_t>(nx)), a(static_cast<std::size_t>(nx)),
        b(static_cast<std::size_t>(nx));
    double worst = 0.0;
    for (int trial = 0; trial < 50; ++trial) {
      for (auto& v : x) v = val(rng);
      REQUIRE(dense_rhs(0, x.data(), nullptr, p.data(), a.data()) == 0);
      REQUIRE(sparse_rhs(0, x.data(), nullptr, p.data(), b.data()) == 0);
      double scale = 1.0, diff = 0.0;
      for (int i = 0; i < nx; ++i) {
        scale = std::max(scale, std::fabs(a[static_cast<std::size_t>(i)]));
        diff = std::max(diff, std::fabs(a[static_cast<std::size_t>(i)] - b[static_cast<std::size_t>(i)]));
      }
      worst = std::max(worst, diff / scale);
    }
    return worst;
  };
  namespace dd = mbsc_gen::dp_mult_dense;
  namespace ds = mbsc_gen::dp_mult_sparse;
  namespace ad = mbsc_gen::arm_mult_dense;
  namespace as = mbsc_gen::arm_mult_sparse;
  std::vector<double> u(static_cast<std::size_t>(std::max(1, ad::kNin)), 0.0);
  CHECK(compare(dd::rhs, ds::rhs, dd::kNx, dd::kParamDefaults, dd::kNp) < 1e-12);
  CHECK(compare([&](double t, const double* x, const double*, const double* p, double* o) { return ad::rhs(t, x, u.data(), p, o); },
                [&](double t, const double* x, const double*, const double* p, double* o) { return as::rhs(t, x, u.data(), p, o); },
                ad::kNx, ad::kParamDefaults, ad::kNp) < 1e-12);
}
