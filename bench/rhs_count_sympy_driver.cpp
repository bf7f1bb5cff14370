// SPDX-License-Identifier: GPL-2.0-or-later
// Instruction count of sympy's rhs of a planar mechanism, for bench/count_rhs.sh SYMPY=1:
// the same 20 pseudo-random states as bench/rhs_count_driver.cpp (entries uniform in
// [-1, 1], sympy's own state q, u), parameters at mbsc's defaults (mapped by name through
// the complement's header), inputs 0.05. sympy's rhs is what bench/planar_driver.cpp times:
// its generated mass_forcing (M, F), q' = u, then u' = M^-1 F by a dense LU with partial
// pivoting of the o x o matrix, then the finiteness check every mbsc rhs ends with.
//   g++ -O2 -I GEN -DMODEL=four_bar -DHEADER='"four_bar/four_bar.hpp"' -DSYMPY_NQ=3
//       bench/rhs_count_sympy_driver.cpp -x c++ sympy_four_bar.c      (one command line)
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include HEADER

namespace gen = mbsc_gen::MODEL;

#define CAT_(a, b) a##b
#define CAT(a, b) CAT_(a, b)
#define SYM(s) CAT(CAT(sympy_, MODEL), s)
extern "C" {
extern const int SYM(_nq), SYM(_np), SYM(_nin);
extern const char* const SYM(_pnames)[];
extern const char* const SYM(_inames)[];
void SYM(_mass_forcing)(const double* q, const double* u, const double* p, const double* in, double* M, double* F);
}

namespace {

constexpr int kS = SYMPY_NQ;
std::vector<double> g_p, g_in;

// A x = b in place (A row-major kS x kS), LU with partial pivoting: KanesMethod's matrix
// holds the velocity-constraint rows, so it is not symmetric.
int lu_solve(double* A, double* b) {
  for (int k = 0; k < kS; ++k) {
    int piv = k;
    for (int i = k + 1; i < kS; ++i)
      if (std::fabs(A[i * kS + k]) > std::fabs(A[piv * kS + k])) piv = i;
    if (A[piv * kS + k] == 0.0) return 1;
    if (piv != k) {
      for (int j = 0; j < kS; ++j) std::swap(A[k * kS + j], A[piv * kS + j]);
      std::swap(b[k], b[piv]);
    }
    const double inv = 1.0 / A[k * kS + k];
    for (int i = k + 1; i < kS; ++i) {
      const double f = A[i * kS + k] * inv;
      for (int j = k + 1; j < kS; ++j) A[i * kS + j] -= f * A[k * kS + j];
      b[i] -= f * b[k];
    }
  }
  for (int i = kS - 1; i >= 0; --i) {
    double s = b[i];
    for (int j = i + 1; j < kS; ++j) s -= A[i * kS + j] * b[j];
    b[i] = s / A[i * kS + i];
  }
  return 0;
}

bool all_finite(const double* v, int n) {
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

// A sympy parameter or input by name: mbsc's input value (0.05) or parameter default.
double value_of(const char* name) {
  for (int i = 0; i < gen::kNin; ++i)
    if (std::string(name) == gen::kInputNames[i]) return 0.05;
  for (int i = 0; i < gen::kNp; ++i)
    if (std::string(name) == gen::kParamNames[i]) return gen::kParamDefaults[i];
  std::fprintf(stderr, "no input or parameter %s in the mbsc model\n", name);
  std::exit(1);
}

}  // namespace

__attribute__((noinline, optimize("no-optimize-sibling-calls"))) int count_calls(const double* x, double* xdot) {
  double A[kS * kS];
  double* F = xdot + kS;
  SYM(_mass_forcing)(x, x + kS, g_p.data(), g_in.data(), A, F);
  for (int k = 0; k < kS; ++k) xdot[k] = x[kS + k];
  int rc = lu_solve(A, F) != 0 ? 1 : (all_finite(xdot, 2 * kS) ? 0 : 2);
  asm volatile("" ::: "memory");
  return rc;
}

int main() {
  if (SYM(_nq) != kS) {
    std::fprintf(stderr, "SYMPY_NQ differs from the generated code\n");
    return 1;
  }
  for (int i = 0; i < SYM(_np); ++i) g_p.push_back(value_of(SYM(_pnames)[i]));
  for (int i = 0; i < SYM(_nin); ++i) g_in.push_back(value_of(SYM(_inames)[i]));
  if (g_in.empty()) g_in.push_back(0.0);
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> dist(-1.0, 1.0);
  constexpr int kStates = 20;
  int calls = 0, failed = 0;
  double sink = 0.0;
  for (int s = 0; s < kStates; ++s) {
    std::vector<double> x(2 * kS), xdot(2 * kS);
    for (double& v : x) v = dist(rng);
    failed += count_calls(x.data(), xdot.data()) != 0;
    sink += xdot[kS];
    ++calls;
  }
  std::printf("count_calls=%d\nfailed=%d\nsink=%g\n", calls, failed, sink);
  return 0;
}
