// SPDX-License-Identifier: GPL-2.0-or-later
// Benchmark driver for the planar N-link pendulum chain: mbsc's generated rhs against
// sympy's generated mass matrix and forcing (KanesMethod) + the Cholesky solve and the
// finiteness status check mbsc emits.
//
// Built per N by bench/run_chain.sh:
//   g++ -std=c++17 -O2 -march=x86-64 -DCHAIN_N=8 -DMBSC_HEADER='"chain8.hpp"' -I GEN/chain8
//       bench/chain_driver.cpp chain8.o sympy_chain8.o
//   (add -DNO_SYMPY without sympy's code)
//
// `driver` prints key=value lines:
//   states, max_rel_diff       agreement of the angle accelerations at 100 random consistent
//                              states: per state max_k |a_k - b_k| / max_k |b_k| (a = mbsc,
//                              b = sympy), the largest over the states
//   mbsc_ref_diff,             the same with a = the tool's accelerations and b = the
//   sympy_ref_diff             closed-form reference below (Lagrange's equations of the
//                              chain, solved in long double)
//   mbsc_ns, sympy_ns          ns per rhs call, median of 5 repeats of a loop that takes
//                              >= 0.5 s (the tools' repeats alternate); also
//                              *_ns_min, *_ns_max, *_calls
// `driver count TOOL` (TOOL = mbsc or sympy) calls that tool's rhs once at each
// state (warm-up: lazy symbol binding, first-call set-up), then once more at each state
// through count_calls(), the function bench/run_chain.sh gives to callgrind's
// --toggle-collect: instructions per rhs call = callgrind's total / the printed calls.
// All rhs are called through the same kind of function pointer, cycling over the same
// 100 states (in each tool's layout), from object files compiled with the same flags.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include MBSC_HEADER

#ifndef CHAIN_N
#error "define CHAIN_N"
#endif

#define CAT2(a, b) a##b
#define CAT(a, b) CAT2(a, b)
#define MBSC_NS CAT(chain, CHAIN_N)
#define SYMPY_MASS_FORCING CAT(CAT(sympy_chain, CHAIN_N), _mass_forcing)

namespace gen = mbsc_gen::MBSC_NS;
constexpr int N = CHAIN_N;
// Generated with --state minimal: x = (angles, rates), like sympy's; else all 6N entries.
constexpr bool kMinimal = gen::kNx == 2 * N;

#ifndef NO_SYMPY
extern "C" void SYMPY_MASS_FORCING(const double* q, const double* u, const double* p, double* M, double* F);
#endif

namespace {

[[noreturn]] void die(const std::string& msg) {
  std::fprintf(stderr, "chain_driver: %s\n", msg.c_str());
  std::exit(1);
}

int state_index(const std::string& name) {
  for (int i = 0; i < gen::kNx; ++i)
    if (name == gen::kStateNames[i]) return i;
  die("state " + name + " not in kStateNames");
}

int param_index(const std::string& name) {
  for (int i = 0; i < gen::kNp; ++i)
    if (name == gen::kParamNames[i]) return i;
  die("parameter " + name + " not in kParamNames");
}

// Indices of the named states in mbsc's x.
struct Layout {
  int th[N], w[N], bx[N], by[N], bu[N], bv[N];
};

Layout layout() {
  Layout L{};
  for (int k = 0; k < N; ++k) {
    const std::string b = "b" + std::to_string(k + 1);
    L.th[k] = state_index("th" + std::to_string(k + 1));
    L.w[k] = state_index("w" + std::to_string(k + 1));
    if (!kMinimal) {
      L.bx[k] = state_index(b + ".x");
      L.by[k] = state_index(b + ".y");
      L.bu[k] = state_index(b + ".u");
      L.bv[k] = state_index(b + ".v");
    }
  }
  return L;
}

// Parameters: mbsc's defaults in kParamNames order, and sympy's {m, l, g} from them.
double g_pm[gen::kNp > 0 ? gen::kNp : 1];
double g_ps[3];

// mbsc state consistent with the angles th and rates w (bobs from the constraints).
void mbsc_state(const Layout& L, const double* th, const double* w, double* x) {
  const double l = g_ps[1];
  for (int i = 0; i < gen::kNx; ++i) x[i] = 0.0;
  double px = 0, py = 0, vx = 0, vy = 0;
  for (int k = 0; k < N; ++k) {
    px += l * std::sin(th[k]);
    py -= l * std::cos(th[k]);
    vx += l * std::cos(th[k]) * w[k];
    vy += l * std::sin(th[k]) * w[k];
    x[L.th[k]] = th[k];
    x[L.w[k]] = w[k];
    if (kMinimal) continue;  // the bobs are rebuilt inside rhs
    x[L.bx[k]] = px;
    x[L.by[k]] = py;
    x[L.bu[k]] = vx;
    x[L.bv[k]] = vy;
  }
}

int rhs_mbsc(const double* x, double* xdot) { return gen::rhs(0.0, x, nullptr, g_pm, xdot); }

#ifndef NO_SYMPY
// The status check mbsc's generated functions end with (status 2 instead of a silent
// inf or NaN), copied so that every rhs meets the same contract.
bool all_finite(const double* v, int n) {
  bool special = false;
  for (int i = 0; i < n; ++i) {
    std::uint64_t bits;
    std::memcpy(&bits, v + i, sizeof bits);
    special |= (~bits & 0x7ff0000000000000u) == 0;
  }
  return !special;
}
#endif

#ifndef NO_SYMPY
// Solve A x = b in place for the symmetric positive definite mass matrix: the same
// Cholesky algorithm mbsc emits for its reduced mass matrix (so both tools pay for the
// same solver). Returns 1 when A is not positive definite.
int chol_solve(double* A, double* b) {
  double dmax = 0.0;  // the largest |diagonal entry|, inline as mbsc's (no std::fmax call)
  for (int i = 0; i < N; ++i) {
    const double v = std::fabs(A[i * N + i]);
    if (v > dmax) dmax = v;
  }
  const double tiny = 1e-13 * dmax;
  for (int j = 0; j < N; ++j) {
    double d = A[j * N + j];
    for (int m = 0; m < j; ++m) d -= A[j * N + m] * A[j * N + m];
    if (!(d > tiny)) return 1;
    const double ljj = std::sqrt(d);
    A[j * N + j] = ljj;
    for (int i = j + 1; i < N; ++i) {
      double s = A[i * N + j];
      for (int m = 0; m < j; ++m) s -= A[i * N + m] * A[j * N + m];
      A[i * N + j] = s / ljj;
    }
  }
  for (int i = 0; i < N; ++i) {
    double s = b[i];
    for (int m = 0; m < i; ++m) s -= A[i * N + m] * b[m];
    b[i] = s / A[i * N + i];
  }
  for (int i = N - 1; i >= 0; --i) {
    double s = b[i];
    for (int m = i + 1; m < N; ++m) s -= A[m * N + i] * b[m];
    b[i] = s / A[i * N + i];
  }
  return 0;
}

// sympy's rhs: x = (q, u), xdot = (u, M^-1 F), with mbsc's solver and status check.
int rhs_sympy(const double* x, double* xdot) {
  double M[N * N];
  double* F = xdot + N;
  SYMPY_MASS_FORCING(x, x + N, g_ps, M, F);
  for (int k = 0; k < N; ++k) xdot[k] = x[N + k];
  if (chol_solve(M, F) != 0) return 1;
  return all_finite(xdot, 2 * N) ? 0 : 2;
}
#endif

// The reference: the chain's equations of motion in closed form (Lagrange, absolute
// angles th, rates w, 0-based k; c_ij = N - max(i, j) bobs hang below both rods i, j):
//   sum_j c_ij cos(th_i - th_j) th_j'' = -sum_j c_ij sin(th_i - th_j) w_j^2 - (g/l) c_ii sin th_i
// (m l^2 divided out), solved by Gaussian elimination with partial pivoting, all in
// long double: a formulation independent of the tools.
void reference_accel(const double* th, const double* w, double* thdd) {
  const long double gl = static_cast<long double>(g_ps[2]) / static_cast<long double>(g_ps[1]);
  std::vector<long double> A(static_cast<std::size_t>(N * N)), b(N);
  for (int i = 0; i < N; ++i) {
    long double r = -gl * static_cast<long double>(N - i) * std::sin(static_cast<long double>(th[i]));
    for (int j = 0; j < N; ++j) {
      const long double c = static_cast<long double>(N - std::max(i, j));
      const long double d = static_cast<long double>(th[i]) - static_cast<long double>(th[j]);
      A[static_cast<std::size_t>(i * N + j)] = c * std::cos(d);
      r -= c * std::sin(d) * static_cast<long double>(w[j]) * static_cast<long double>(w[j]);
    }
    b[static_cast<std::size_t>(i)] = r;
  }
  auto a = [&](int i, int j) -> long double& { return A[static_cast<std::size_t>(i * N + j)]; };
  for (int k = 0; k < N; ++k) {
    int piv = k;
    for (int i = k + 1; i < N; ++i)
      if (std::fabs(a(i, k)) > std::fabs(a(piv, k))) piv = i;
    if (piv != k) {
      for (int j = 0; j < N; ++j) std::swap(a(k, j), a(piv, j));
      std::swap(b[static_cast<std::size_t>(k)], b[static_cast<std::size_t>(piv)]);
    }
    for (int i = k + 1; i < N; ++i) {
      const long double f = a(i, k) / a(k, k);
      for (int j = k; j < N; ++j) a(i, j) -= f * a(k, j);
      b[static_cast<std::size_t>(i)] -= f * b[static_cast<std::size_t>(k)];
    }
  }
  for (int i = N - 1; i >= 0; --i) {
    long double r = b[static_cast<std::size_t>(i)];
    for (int j = i + 1; j < N; ++j) r -= a(i, j) * static_cast<long double>(thdd[j]);
    thdd[i] = static_cast<double>(r / a(i, i));
  }
}

// max_k |a_k - b_k| / max_k |b_k|
double rel_diff(const double* a, const double* b) {
  double num = 0.0, den = 0.0;
  for (int k = 0; k < N; ++k) {
    num = std::max(num, std::fabs(a[k] - b[k]));
    den = std::max(den, std::fabs(b[k]));
  }
  return num / den;
}

using Rhs = int (*)(const double*, double*);

// The one function callgrind counts (--toggle-collect): a real call, not a tail jump.
__attribute__((noinline, optimize("no-optimize-sibling-calls"))) int count_calls(Rhs f, const double* x, double* out) {
  const int rc = f(x, out);
  asm volatile("" ::: "memory");
  return rc;
}

// ns per call over `calls` calls cycling through the states; the checksum keeps the
// calls alive.
double time_loop(Rhs f, const std::vector<std::vector<double>>& xs, int nout, long calls, double& sink) {
  std::vector<double> out(static_cast<std::size_t>(nout));
  const std::size_t ns = xs.size();
  double acc = 0.0;
  const auto t0 = std::chrono::steady_clock::now();
  for (long i = 0; i < calls; ++i) {
    if (f(xs[static_cast<std::size_t>(i) % ns].data(), out.data()) != 0) die("rhs failed in the timing loop");
    acc += out[static_cast<std::size_t>(nout) - 1];
  }
  const auto t1 = std::chrono::steady_clock::now();
  sink += acc;
  return std::chrono::duration<double, std::nano>(t1 - t0).count() / static_cast<double>(calls);
}

struct Timed {
  const char* tag;
  Rhs f;
  const std::vector<std::vector<double>>* xs;
  int nout;
  long calls = 1;
  std::vector<double> reps;
};

// Calibrate: double the count until one loop takes >= 0.25 s, then aim at 0.6 s a loop.
void calibrate(Timed& b, double& sink) {
  double ns = 0;
  for (;;) {
    ns = time_loop(b.f, *b.xs, b.nout, b.calls, sink);
    if (ns * static_cast<double>(b.calls) >= 0.25e9) break;
    b.calls *= 2;
  }
  b.calls = std::max(b.calls, static_cast<long>(std::ceil(0.6e9 / ns)));
}

// One repeat; it must last >= 0.5 s, else it is redone with more calls.
void repeat(Timed& b, double& sink) {
  double t = time_loop(b.f, *b.xs, b.nout, b.calls, sink);
  while (t * static_cast<double>(b.calls) < 0.5e9) {
    b.calls = static_cast<long>(std::ceil(0.6e9 / t));
    t = time_loop(b.f, *b.xs, b.nout, b.calls, sink);
  }
  b.reps.push_back(t);
}

void report(Timed& b) {
  std::sort(b.reps.begin(), b.reps.end());
  const std::size_t n = b.reps.size();
  std::printf("%s_ns=%.6g\n%s_ns_min=%.6g\n%s_ns_max=%.6g\n%s_calls=%ld\n", b.tag, b.reps[n / 2], b.tag, b.reps[0],
              b.tag, b.reps[n - 1], b.tag, b.calls);
}

}  // namespace

int main(int argc, char** argv) {
  const Layout L = layout();
  for (int i = 0; i < gen::kNp; ++i) g_pm[i] = gen::kParamDefaults[i];
  g_ps[0] = g_pm[param_index("m")];
  g_ps[1] = g_pm[param_index("l")];
  g_ps[2] = g_pm[param_index("g")];
  if (gen::kNdof != N) die("kNdof != N");

  std::mt19937_64 rng(20240607u + N);
  std::uniform_real_distribution<double> ang(-M_PI, M_PI), rate(-2.0, 2.0);
  constexpr int kStates = 100;
  std::vector<std::vector<double>> xm, xsym, ths, ws;
  for (int s = 0; s < kStates; ++s) {
    double th[N], w[N];
    for (int k = 0; k < N; ++k) th[k] = ang(rng);
    for (int k = 0; k < N; ++k) w[k] = rate(rng);
    ths.emplace_back(th, th + N);
    ws.emplace_back(w, w + N);
    std::vector<double> x(static_cast<std::size_t>(gen::kNx));
    mbsc_state(L, th, w, x.data());
    xm.push_back(x);
    std::vector<double> y(2 * N);
    for (int k = 0; k < N; ++k) {
      y[static_cast<std::size_t>(k)] = th[k];
      y[static_cast<std::size_t>(N + k)] = w[k];
    }
    xsym.push_back(y);
  }

  if (argc == 3 && std::string(argv[1]) == "count") {
    const std::string tool = argv[2];
    Rhs f = nullptr;
    const std::vector<std::vector<double>>* xs = nullptr;
    int nout = 0;
    if (tool == "mbsc") f = rhs_mbsc, xs = &xm, nout = gen::kNx;
#ifndef NO_SYMPY
    if (tool == "sympy") f = rhs_sympy, xs = &xsym, nout = 2 * N;
#endif
    if (f == nullptr) die("count: no tool " + tool + " in this build");
    std::vector<double> out(static_cast<std::size_t>(nout));
    for (const auto& x : *xs)
      if (f(x.data(), out.data()) != 0) die("count: " + tool + " rhs failed (warm-up)");
    for (const auto& x : *xs)
      if (count_calls(f, x.data(), out.data()) != 0) die("count: " + tool + " rhs failed");
    std::printf("count_tool=%s\ncount_calls=%zu\n", tool.c_str(), xs->size());
    return 0;
  }
  if (argc != 1) die("usage: driver [count mbsc|sympy]");

  std::printf("n=%d\nstates=%d\n", N, kStates);
  double sink = 0.0;
  // Absolute angle accelerations of each tool at each state, then the comparisons.
  std::vector<std::vector<double>> ref(kStates, std::vector<double>(N)), am = ref, as = ref;
  for (int s = 0; s < kStates; ++s) {
    const auto si = static_cast<std::size_t>(s);
    reference_accel(ths[si].data(), ws[si].data(), ref[si].data());
    std::vector<double> a(static_cast<std::size_t>(gen::kNx)), b(2 * N);
    if (rhs_mbsc(xm[si].data(), a.data()) != 0) die("mbsc rhs failed");
    for (int k = 0; k < N; ++k) {
      am[si][static_cast<std::size_t>(k)] = a[static_cast<std::size_t>(L.w[k])];
      if (a[static_cast<std::size_t>(L.th[k])] != ws[si][static_cast<std::size_t>(k)]) die("mbsc angle rates differ");
    }
#ifndef NO_SYMPY
    if (rhs_sympy(xsym[si].data(), b.data()) != 0) die("sympy rhs failed");
    for (int k = 0; k < N; ++k) {
      as[si][static_cast<std::size_t>(k)] = b[static_cast<std::size_t>(N + k)];
      if (b[static_cast<std::size_t>(k)] != ws[si][static_cast<std::size_t>(k)]) die("sympy angle rates differ");
    }
#endif
  }
  auto worst = [&](const std::vector<std::vector<double>>& a, const std::vector<std::vector<double>>& b) {
    double w = 0.0;
    for (int s = 0; s < kStates; ++s)
      w = std::max(w, rel_diff(a[static_cast<std::size_t>(s)].data(), b[static_cast<std::size_t>(s)].data()));
    return w;
  };
  std::printf("mbsc_ref_diff=%.3e\n", worst(am, ref));
#ifndef NO_SYMPY
  std::printf("max_rel_diff=%.3e\n", worst(am, as));
  std::printf("sympy_ref_diff=%.3e\n", worst(as, ref));
#endif
  std::fflush(stdout);
  // The tools' repeats alternate (mbsc, sympy, mbsc, ...) so that a load change on the
  // machine hits both alike.
  std::vector<Timed> runs;
  runs.push_back(Timed{"mbsc", rhs_mbsc, &xm, gen::kNx, 1, {}});
#ifndef NO_SYMPY
  runs.push_back(Timed{"sympy", rhs_sympy, &xsym, 2 * N, 1, {}});
#endif
  for (Timed& b : runs) calibrate(b, sink);
  for (int r = 0; r < 5; ++r)
    for (Timed& b : runs) repeat(b, sink);
  for (Timed& b : runs) report(b);
  std::printf("checksum=%.6g\n", sink);
  return 0;
}
