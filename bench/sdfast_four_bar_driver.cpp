// SPDX-License-Identifier: GPL-2.0-or-later
// Benchmark driver for the four-bar linkage (models/four_bar.mbs): mbsc's complement rhs
// (full state and --state minimal) against SD/FAST's generated code for the same
// mechanism (bench/sdfast_four_bar.py: a tree of three pins plus a loop pin joint), in
// its Order(N) formulation (prefix sdn) and its Kane formulation (prefix sdk).
//
// Built by bench/run_sdfast_planar.sh:
//   g++ -std=c++17 -O2 -march=x86-64 -I GEN bench/sdfast_four_bar_driver.cpp
//       four_bar.o four_bar_min.o sdn_four_bar_dyn.o sdnlib.o sdk_four_bar_dyn.o sdklib.o
//
// `driver` prints key=value lines:
//   states                     100 random assembled states (crank angle uniform in
//                              [-pi, pi], crank rate in [-3, 3]; coupler and rocker on
//                              the branch of models/four_bar.mbs's initial guess, the
//                              rocker up), built in closed form from the loop geometry
//   sdn_rel_diff, sdk_rel_diff the angular accelerations of crank, coupler and rocker
//                              against the complement's (full state): max over the states
//                              of max_i |a_i - b_i| / max_i |b_i|
//   minimal_rel_diff           the same for the crank's, --state minimal against full
//   <tool>_ns                  ns per rhs call, median of 5 loops of >= 0.3 s (alternating)
// `driver count TOOL` (complement, minimal, sdn, sdk): 100 warm-up calls, then 100 calls
// through count_calls(), the function callgrind's --toggle-collect counts.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "four_bar/four_bar.hpp"
#include "four_bar_min/four_bar_min.hpp"

namespace C = mbsc_gen::four_bar;
namespace Mn = mbsc_gen::four_bar_min;

// SD/FAST's generated C, once per formulation (the prefix is the only difference).
#define SD_DECLARE(P)                                  \
  extern "C" {                                         \
  void P##mass(int body, double massin);               \
  void P##iner(int body, double inerin[3][3]);         \
  void P##btj(int joint, double btjin[3]);             \
  void P##itj(int joint, double itjin[3]);             \
  void P##grav(double gravin[3]);                      \
  void P##init(void);                                  \
  void P##state(double timein, double qin[], double uin[]); \
  void P##hinget(int joint, int axis, double torque);  \
  void P##deriv(double oqdot[], double oudot[]);       \
  void P##error(int* routine, int* errnum);            \
  }
SD_DECLARE(sdn)
SD_DECLARE(sdk)

namespace {

[[noreturn]] void die(const std::string& msg) {
  std::fprintf(stderr, "sdfast_four_bar_driver: %s\n", msg.c_str());
  std::exit(1);
}

template <std::size_t K>
int index_of(const char* const (&names)[K], int n, const std::string& name) {
  for (int i = 0; i < n; ++i)
    if (name == names[i]) return i;
  die(name + " not found");
}

double g_p[C::kNp];
double a, b, c, d, g, m1, m2, m3, tau0;

// The status check mbsc's generated functions end with, so that every rhs meets the
// same contract (status 2 instead of a silent inf or NaN).
bool all_finite(const double* v, int n) {
  bool special = false;
  for (int i = 0; i < n; ++i) {
    std::uint64_t bits;
    std::memcpy(&bits, v + i, sizeof bits);
    special |= (~bits & 0x7ff0000000000000u) == 0;
  }
  return !special;
}

int rhs_complement(const double* x, double* xdot) { return C::rhs(0.0, x, nullptr, g_p, xdot); }
int rhs_minimal(const double* x, double* xdot) { return Mn::rhs(0.0, x, nullptr, g_p, xdot); }

// SD/FAST's rhs on its state (q0..q2, u0..u2): the crank torque tau0 applied after
// sdstate, as its manual prescribes; status 1 when SD/FAST flagged an error.
#define SD_RHS(P)                                                              \
  int rhs_##P(const double* x, double* xdot) {                                 \
    P##state(0.0, const_cast<double*>(x), const_cast<double*>(x + 3));         \
    P##hinget(0, 0, tau0);                                                     \
    P##deriv(xdot, xdot + 3);                                                  \
    int routine = 0, err = 0;                                                  \
    P##error(&routine, &err);                                                  \
    if (err != 0) return 1;                                                    \
    return all_finite(xdot, 6) ? 0 : 2;                                        \
  }                                                                            \
  void setup_##P() {                                                           \
    const double ms[3] = {m1, m2, m3}, ls[3] = {a, b, c};                      \
    for (int k = 0; k < 3; ++k) {                                              \
      P##mass(k, ms[k]);                                                       \
      double I[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, ms[k] * ls[k] * ls[k] / 12}}; \
      P##iner(k, I);                                                           \
      double btj[3] = {-ls[k] / 2, 0, 0};                                      \
      P##btj(k, btj);                                                          \
    }                                                                          \
    double btj3[3] = {c / 2, 0, 0}, itj1[3] = {a / 2, 0, 0}, itj2[3] = {d, 0, 0}, itj3[3] = {b / 2, 0, 0}; \
    P##btj(3, btj3);                                                           \
    P##itj(1, itj1);                                                           \
    P##itj(2, itj2);                                                           \
    P##itj(3, itj3);                                                           \
    double grav[3] = {0, -g, 0};                                               \
    P##grav(grav);                                                             \
    P##init();                                                                 \
    int routine = 0, err = 0;                                                  \
    P##error(&routine, &err);                                                  \
    if (err != 0) die(#P " set-up: routine " + std::to_string(routine) + ", error " + std::to_string(err)); \
  }
SD_RHS(sdn)
SD_RHS(sdk)

// An assembled state from the crank angle t1 and rate w1: B from the two circles about A
// (radius b) and Q (radius c), on the left of A -> Q; rates from the loop's velocity
// equation a w1 e1' + b w2 e2' = c w3 e3' (e' = (-sin, cos)).
struct Angles {
  double t[3], w[3];
};

Angles assemble(double t1, double w1) {
  const double ax = a * std::cos(t1), ay = a * std::sin(t1);
  const double dx = d - ax, dy = -ay, D = std::hypot(dx, dy);
  const double along = (b * b - c * c + D * D) / (2 * D), h = std::sqrt(b * b - along * along);
  const double bx = ax + along * dx / D - h * dy / D, by = ay + along * dy / D + h * dx / D;
  Angles s{};
  s.t[0] = t1;
  s.t[1] = std::atan2(by - ay, bx - ax);
  s.t[2] = std::atan2(by, bx - d);
  const double s1 = std::sin(t1), c1 = std::cos(t1), s2 = std::sin(s.t[1]), c2 = std::cos(s.t[1]);
  const double s3 = std::sin(s.t[2]), c3 = std::cos(s.t[2]);
  // [-b s2, c s3; b c2, -c c3] [w2; w3] = [a w1 s1; -a w1 c1]
  const double det = (-b * s2) * (-c * c3) - (c * s3) * (b * c2);
  const double r1 = a * w1 * s1, r2 = -a * w1 * c1;
  s.w[0] = w1;
  s.w[1] = (r1 * (-c * c3) - (c * s3) * r2) / det;
  s.w[2] = ((-b * s2) * r2 - (b * c2) * r1) / det;
  return s;
}

// mbsc's full state: mass centres and their velocities from the angles.
std::vector<double> full_state(const Angles& s) {
  const double c1 = std::cos(s.t[0]), s1 = std::sin(s.t[0]), c2 = std::cos(s.t[1]), s2 = std::sin(s.t[1]);
  const double c3 = std::cos(s.t[2]), s3 = std::sin(s.t[2]);
  const double w1 = s.w[0], w2 = s.w[1], w3 = s.w[2];
  struct Named {
    const char* name;
    double v;
  } vals[] = {
      {"crank.x", a / 2 * c1},           {"crank.y", a / 2 * s1},           {"crank.theta", s.t[0]},
      {"coupler.x", a * c1 + b / 2 * c2}, {"coupler.y", a * s1 + b / 2 * s2}, {"coupler.theta", s.t[1]},
      {"rocker.x", d + c / 2 * c3},       {"rocker.y", c / 2 * s3},          {"rocker.theta", s.t[2]},
      {"crank.u", -a / 2 * s1 * w1},      {"crank.v", a / 2 * c1 * w1},      {"crank.w", w1},
      {"coupler.u", -a * s1 * w1 - b / 2 * s2 * w2}, {"coupler.v", a * c1 * w1 + b / 2 * c2 * w2},
      {"coupler.w", w2},                  {"rocker.u", -c / 2 * s3 * w3},    {"rocker.v", c / 2 * c3 * w3},
      {"rocker.w", w3},
  };
  std::vector<double> x(C::kNx);
  for (const Named& v : vals) x[static_cast<std::size_t>(index_of(C::kStateNames, C::kNx, v.name))] = v.v;
  return x;
}

std::vector<double> minimal_state(const Angles& s) {
  std::vector<double> x(Mn::kNx);
  const char* names[] = {"crank.theta", "coupler.theta", "rocker.theta", "crank.w"};
  const double vals[] = {s.t[0], s.t[1], s.t[2], s.w[0]};
  if (Mn::kNx != 4) die("--state minimal: expected 4 states");
  for (int i = 0; i < 4; ++i) x[static_cast<std::size_t>(index_of(Mn::kStateNames, Mn::kNx, names[i]))] = vals[i];
  return x;
}

// SD/FAST's tree coordinates: crank, coupler relative to crank, rocker.
std::vector<double> sdfast_state(const Angles& s) {
  return {s.t[0], s.t[1] - s.t[0], s.t[2], s.w[0], s.w[1] - s.w[0], s.w[2]};
}

using Rhs = int (*)(const double*, double*);

__attribute__((noinline, optimize("no-optimize-sibling-calls"))) int count_calls(Rhs f, const double* x, double* out) {
  const int rc = f(x, out);
  asm volatile("" ::: "memory");
  return rc;
}

struct Tool {
  const char* tag;
  Rhs f;
  std::vector<std::vector<double>> xs;
  int nout;
  long calls = 1000;
  std::vector<double> reps;
};

double time_loop(Tool& t, double& sink) {
  std::vector<double> out(static_cast<std::size_t>(t.nout));
  const std::size_t n = t.xs.size();
  double acc = 0.0;
  const auto t0 = std::chrono::steady_clock::now();
  for (long i = 0; i < t.calls; ++i) {
    if (t.f(t.xs[static_cast<std::size_t>(i) % n].data(), out.data()) != 0) die(std::string(t.tag) + " rhs failed");
    acc += out[static_cast<std::size_t>(t.nout) - 1];
  }
  const auto t1 = std::chrono::steady_clock::now();
  sink += acc;
  return std::chrono::duration<double, std::nano>(t1 - t0).count() / static_cast<double>(t.calls);
}

double rel_diff(const double* x, const double* y, int n) {
  double num = 0.0, den = 0.0;
  for (int i = 0; i < n; ++i) {
    num = std::max(num, std::fabs(x[i] - y[i]));
    den = std::max(den, std::fabs(y[i]));
  }
  return num / den;
}

}  // namespace

int main(int argc, char** argv) {
  for (int i = 0; i < C::kNp; ++i) g_p[i] = C::kParamDefaults[i];
  if (Mn::kNp != C::kNp) die("the two builds' parameters differ");
  auto par = [](const char* n) { return g_p[index_of(C::kParamNames, C::kNp, n)]; };
  a = par("a"), b = par("b"), c = par("c"), d = par("d"), g = par("g");
  m1 = par("m1"), m2 = par("m2"), m3 = par("m3"), tau0 = par("tau0");
  setup_sdn();
  setup_sdk();

  std::mt19937_64 rng(20261202u);
  std::uniform_real_distribution<double> ang(-M_PI, M_PI), rate(-3.0, 3.0);
  std::vector<Tool> tools = {{"complement", rhs_complement, {}, C::kNx, 1000, {}},
                             {"minimal", rhs_minimal, {}, Mn::kNx, 1000, {}},
                             {"sdn", rhs_sdn, {}, 6, 1000, {}},
                             {"sdk", rhs_sdk, {}, 6, 1000, {}}};
  constexpr int kStates = 100;
  for (int s = 0; s < kStates; ++s) {
    const double t1 = ang(rng), w1 = rate(rng);
    const Angles st = assemble(t1, w1);
    tools[0].xs.push_back(full_state(st));
    tools[1].xs.push_back(minimal_state(st));
    tools[2].xs.push_back(sdfast_state(st));
    tools[3].xs.push_back(sdfast_state(st));
  }
  // the assembled states satisfy mbsc's position constraints
  double worst_pos = 0.0;
  for (const auto& x : tools[0].xs) {
    double r[C::kNposc];
    if (C::position_constraints(0.0, x.data(), nullptr, g_p, r) != 0) die("position_constraints failed");
    for (double v : r) worst_pos = std::max(worst_pos, std::fabs(v));
  }

  if (argc == 3 && std::string(argv[1]) == "count") {
    for (Tool& t : tools) {
      if (t.tag != std::string(argv[2])) continue;
      std::vector<double> out(static_cast<std::size_t>(t.nout));
      for (const auto& x : t.xs)
        if (t.f(x.data(), out.data()) != 0) die("count: warm-up failed");
      for (const auto& x : t.xs)
        if (count_calls(t.f, x.data(), out.data()) != 0) die("count: rhs failed");
      std::printf("count_tool=%s\ncount_calls=%zu\n", t.tag, t.xs.size());
      return 0;
    }
    die(std::string("count: no tool ") + argv[2]);
  }
  if (argc != 1) die("usage: driver [count complement|minimal|sdn|sdk]");

  std::printf("states=%d\nassembly_residual=%.3e\n", kStates, worst_pos);
  const int iw[3] = {index_of(C::kStateNames, C::kNx, "crank.w"), index_of(C::kStateNames, C::kNx, "coupler.w"),
                     index_of(C::kStateNames, C::kNx, "rocker.w")};
  const int iwm = index_of(Mn::kStateNames, Mn::kNx, "crank.w");
  double worst_n = 0.0, worst_k = 0.0, worst_m = 0.0;
  for (int s = 0; s < kStates; ++s) {
    const auto si = static_cast<std::size_t>(s);
    std::vector<double> xc(C::kNx), xm(Mn::kNx), yn(6), yk(6);
    if (rhs_complement(tools[0].xs[si].data(), xc.data()) != 0) die("complement rhs failed");
    if (rhs_minimal(tools[1].xs[si].data(), xm.data()) != 0) die("minimal rhs failed");
    if (rhs_sdn(tools[2].xs[si].data(), yn.data()) != 0) die("SD/FAST Order(N) rhs failed");
    if (rhs_sdk(tools[3].xs[si].data(), yk.data()) != 0) die("SD/FAST Kane rhs failed");
    const double ref[3] = {xc[static_cast<std::size_t>(iw[0])], xc[static_cast<std::size_t>(iw[1])],
                           xc[static_cast<std::size_t>(iw[2])]};
    const double an[3] = {yn[3], yn[3] + yn[4], yn[5]}, ak[3] = {yk[3], yk[3] + yk[4], yk[5]};
    worst_n = std::max(worst_n, rel_diff(an, ref, 3));
    worst_k = std::max(worst_k, rel_diff(ak, ref, 3));
    worst_m = std::max(worst_m, rel_diff(&xm[static_cast<std::size_t>(iwm)], ref, 1));
  }
  std::printf("sdn_rel_diff=%.3e\nsdk_rel_diff=%.3e\nminimal_rel_diff=%.3e\n", worst_n, worst_k, worst_m);
  std::fflush(stdout);

  double sink = 0.0;
  for (Tool& t : tools)  // calibrate to >= 0.3 s a loop
    for (;;) {
      const double ns = time_loop(t, sink);
      if (ns * static_cast<double>(t.calls) >= 0.3e9) break;
      t.calls = static_cast<long>(std::ceil(0.35e9 / ns));
    }
  for (int r = 0; r < 5; ++r)
    for (Tool& t : tools) t.reps.push_back(time_loop(t, sink));
  for (Tool& t : tools) {
    std::sort(t.reps.begin(), t.reps.end());
    std::printf("%s_ns=%.6g\n", t.tag, t.reps[2]);
  }
  std::printf("checksum=%.6g\n", sink);
  return 0;
}
