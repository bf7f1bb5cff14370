// SPDX-License-Identifier: GPL-2.0-or-later
// Benchmark driver for the planar mechanisms: one model, its complement build (C) and its
// multipliers build (M), and optionally its peers, compiled together by bench/run_planar.sh:
//   g++ -O2 -DMODEL=four_bar -DGUESS=... -DDRIVERS=... -I GEN bench/planar_driver.cpp
//       GEN/four_bar/four_bar.cpp GEN/four_bar_mult/four_bar_mult.cpp
//   [-DWITH_MINIMAL GEN/four_bar_min/four_bar_min.cpp]   the complement with --state minimal
//   [-DWITH_SYMPY -DSYMPY_NQ=3 sympy_four_bar.o]        sympy.physics.mechanics' M u' = F
//   [-DSYMPY_NAME=four_bar_abs]                         another sympy variant of the model
//   [-DWITH_MUJOCO -DMJ_XML='"bench/mujoco/four_bar.xml"' -DMJ_MAP=... -DMJ_INPUTS=... -lmujoco]
// It assembles a consistent state from the model's driving coordinate (DRIVERS, state
// names), integrates 0.5 s with RK4 (complement rhs) collecting 50 states, and prints
// key=value lines:
//   complement_ns, multipliers_ns, minimal_ns, sympy_ns, mujoco_ns   ns per call at those 50 states,
//       median of 5 loops of >= 0.3 s each (the tools' loops alternate, after a warm-up);
//       mujoco: copy qpos/qvel in, mj_forward, copy qacc out;
//   max_rel_diff     speed rates, multipliers vs complement, max over the states of
//                    max_i |a_i - b_i| / max_i |a_i|;
//   minimal_rel_diff the same, the --state minimal build's independent speed rates;
//   sympy_rel_diff   the same, sympy's u' vs the complement's rates of the same speeds;
//   sympy_rel_diff_start  the same at the assembled start state (before the RK4 run);
//   mujoco_rel_diff  the same, MuJoCo's qacc vs the complement's rates mapped to its joints
//                    (relative angles for child hinges);
//   mujoco_hard_rel_diff(_rest)  the same with near-hard constraints (checks the mapping);
//   mujoco_eq_start, mujoco_eq_states   max |efc_pos| of the equality rows at the assembled
//                    state and at the 50 states (checks the state mapping: ~0);
//   mujoco_eq_1s, mujoco_eq_end  max |efc_pos| of the equality rows (m) over 1 s of
//                    mj_step from the assembled state (MuJoCo's defaults: Euler, 2 ms,
//                    Newton solver, soft constraints), and at the end of it.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "mbsc/runtime/assemble.hpp"
#include "mbsc/runtime/rk4.hpp"

#ifdef WITH_MUJOCO
#include <mujoco/mujoco.h>
#endif

#define STR2(x) #x
#define STR(x) STR2(x)
#define HDR(m) STR(m/m.hpp)
#define CAT2(a, b) a##b
#define CAT(a, b) CAT2(a, b)
#include HDR(MODEL)
#include HDR(CAT(MODEL, _mult))

namespace C = mbsc_gen::MODEL;
namespace M = mbsc_gen::CAT(MODEL, _mult);

#ifdef WITH_MINIMAL
#include HDR(CAT(MODEL, _min))
namespace Mn = mbsc_gen::CAT(MODEL, _min);
#endif

#ifdef WITH_SYMPY
#ifndef SYMPY_NAME  // the sympy variant: sympy_SYMPY_NAME_* (default: the model's name)
#define SYMPY_NAME MODEL
#endif
#define SYM(s) CAT(CAT(sympy_, SYMPY_NAME), s)
extern "C" {
extern const int SYM(_nq), SYM(_np), SYM(_nin);
extern const char* const SYM(_qnames)[];
extern const char* const SYM(_unames)[];
extern const char* const SYM(_pnames)[];
extern const char* const SYM(_inames)[];
void SYM(_mass_forcing)(const double* q, const double* u, const double* p, const double* in, double* M, double* F);
}
#endif

namespace {

[[noreturn]] void die(const std::string& msg) {
  std::fprintf(stderr, "planar_driver: %s\n", msg.c_str());
  std::exit(1);
}

int index_of(const std::string& name) {
  for (int i = 0; i < C::kNx; ++i)
    if (name == C::kStateNames[i]) return i;
  die("no state " + name);
}

int param_or_input(const std::string& name, bool& is_input) {
  for (int i = 0; i < C::kNin; ++i)
    if (name == C::kInputNames[i]) return is_input = true, i;
  for (int i = 0; i < C::kNp; ++i)
    if (name == C::kParamNames[i]) return is_input = false, i;
  die("no input or parameter " + name);
}

// The speed of a coordinate: x -> u, y -> v, theta -> w (mbsc's planar leaves).
std::string speed_of(const std::string& coord) {
  const auto dot = coord.rfind('.');
  const std::string leaf = coord.substr(dot + 1), stem = coord.substr(0, dot + 1);
  if (leaf == "x") return stem + "u";
  if (leaf == "y") return stem + "v";
  if (leaf == "theta") return stem + "w";
  die("no speed for " + coord);
}

std::vector<double> g_u;   // inputs (all 0.05)
std::vector<double> g_pm;  // multipliers build: defaults + Baumgarte alpha, beta

int rhs_c(const double* x, double* xdot) { return C::rhs(0.0, x, g_u.data(), C::kParamDefaults, xdot); }
int rhs_m(const double* x, double* xdot) { return M::rhs(0.0, x, g_u.data(), g_pm.data(), xdot); }

#ifdef WITH_MINIMAL
// The complement build with --state minimal: its x holds a subset of the full state.
int rhs_min(const double* x, double* xdot) { return Mn::rhs(0.0, x, g_u.data(), Mn::kParamDefaults, xdot); }
std::vector<int> g_min;  // minimal state entry -> full state index

std::vector<double> minimal_state(const std::vector<double>& x) {
  if (g_min.empty())
    for (int i = 0; i < Mn::kNx; ++i) g_min.push_back(index_of(Mn::kStateNames[i]));
  std::vector<double> y;
  for (int i : g_min) y.push_back(x[static_cast<std::size_t>(i)]);
  return y;
}
#endif

// Largest |a_i - b_i| over the largest |a_i|, i over the listed pairs (a = reference).
double rel_diff(const std::vector<std::pair<double, double>>& ab) {
  double scale = 0.0, diff = 0.0;
  for (const auto& [a, b] : ab) {
    scale = std::max(scale, std::fabs(a));
    diff = std::max(diff, std::fabs(a - b));
  }
  return diff / std::max(scale, 1e-300);
}

// The finiteness status check that ends every mbsc function (status 2), so that the
// peers' rhs meet the same contract.
bool all_finite(const double* v, int n) {
  bool special = false;
  for (int i = 0; i < n; ++i) {
    std::uint64_t bits;
    std::memcpy(&bits, v + i, sizeof bits);
    special |= (~bits & 0x7ff0000000000000u) == 0;
  }
  return !special;
}

#ifdef WITH_SYMPY
constexpr int kS = SYMPY_NQ;
std::vector<double> g_ps, g_in;

// Dense LU with partial pivoting, solving A x = b in place (A n x n row-major, not
// symmetric: KanesMethod's matrix holds the velocity-constraint rows).
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

// sympy's rhs on its own state (q, u): (u, M^-1 F).
int rhs_s(const double* x, double* xdot) {
  double A[kS * kS];
  double* F = xdot + kS;
  SYM(_mass_forcing)(x, x + kS, g_ps.data(), g_in.data(), A, F);
  for (int k = 0; k < kS; ++k) xdot[k] = x[kS + k];
  if (lu_solve(A, F) != 0) return 1;
  return all_finite(xdot, 2 * kS) ? 0 : 2;
}

std::vector<int> g_sq, g_su;  // sympy's q_k / u_k -> mbsc state index

void sympy_setup() {
  if (SYM(_nq) != kS) die("SYMPY_NQ differs from the generated code");
  for (int k = 0; k < kS; ++k) {
    g_sq.push_back(index_of(SYM(_qnames)[k]));
    g_su.push_back(index_of(SYM(_unames)[k]));
  }
  for (int i = 0; i < SYM(_np); ++i) {
    bool in = false;
    const int j = param_or_input(SYM(_pnames)[i], in);
    g_ps.push_back(in ? g_u[static_cast<std::size_t>(j)] : C::kParamDefaults[j]);
  }
  for (int i = 0; i < SYM(_nin); ++i) {
    bool in = false;
    const int j = param_or_input(SYM(_inames)[i], in);
    g_in.push_back(in ? g_u[static_cast<std::size_t>(j)] : C::kParamDefaults[j]);
  }
  if (g_in.empty()) g_in.push_back(0.0);
}

std::vector<double> sympy_state(const std::vector<double>& x) {
  std::vector<double> y(2 * kS);
  for (int k = 0; k < kS; ++k) {
    y[static_cast<std::size_t>(k)] = x[static_cast<std::size_t>(g_sq[static_cast<std::size_t>(k)])];
    y[static_cast<std::size_t>(kS + k)] = x[static_cast<std::size_t>(g_su[static_cast<std::size_t>(k)])];
  }
  return y;
}
#endif

#ifdef WITH_MUJOCO
mjModel* g_mj = nullptr;
mjData* g_md = nullptr;

// A MuJoCo joint's value from mbsc's coordinates: plus - minus (minus "" for a root
// joint); the speed likewise from the coordinates' speeds. The one exception is the
// Whitworth's slot joint (plus "@slot"): the crank pin's position along the rocker's slot
// follows from the crank and rocker angles.
struct JointMap {
  const char* joint;
  const char* plus;
  const char* minus;
};
struct JointIdx {
  int qadr, vadr;
  int pq = -1, mq = -1, pu = -1, mu = -1;
  bool slot = false;
};
std::vector<JointIdx> g_joints;
std::vector<std::pair<int, double>> g_qfrc;  // dof address, generalized force

void mujoco_setup() {
  char err[1000] = "";
  g_mj = mj_loadXML(MJ_XML, nullptr, err, sizeof err);
  if (!g_mj) die(std::string("mj_loadXML: ") + err);
  g_md = mj_makeData(g_mj);
  for (const JointMap& j : std::vector<JointMap>{MJ_MAP}) {
    const int id = mj_name2id(g_mj, mjOBJ_JOINT, j.joint);
    if (id < 0) die(std::string("no MuJoCo joint ") + j.joint);
    JointIdx ji{g_mj->jnt_qposadr[id], g_mj->jnt_dofadr[id]};
    if (std::string(j.plus) == "@slot") {
      ji.slot = true;
    } else {
      ji.pq = index_of(j.plus);
      ji.pu = index_of(speed_of(j.plus));
      if (*j.minus) {
        ji.mq = index_of(j.minus);
        ji.mu = index_of(speed_of(j.minus));
      }
    }
    g_joints.push_back(ji);
  }
  if (static_cast<int>(g_joints.size()) != g_mj->njnt) die("MJ_MAP does not list every MuJoCo joint");
  for (const auto& [joint, name] : std::vector<std::pair<const char*, const char*>>{MJ_INPUTS}) {
    const int id = mj_name2id(g_mj, mjOBJ_JOINT, joint);
    if (id < 0) die(std::string("no MuJoCo joint ") + joint);
    bool in = false;
    const int j = param_or_input(name, in);
    g_qfrc.emplace_back(g_mj->jnt_dofadr[id], in ? g_u[static_cast<std::size_t>(j)] : C::kParamDefaults[j]);
  }
}

double mbsc_param(const char* name) {
  bool in = false;
  const int j = param_or_input(name, in);
  if (in) die(std::string(name) + " is an input");
  return C::kParamDefaults[j];
}

// (qpos, qvel) for an mbsc state x (or, with acc = true, the accelerations mapped to
// MuJoCo's dofs from xdot: NaN where a dof has no mbsc counterpart).
std::vector<double> mujoco_state(const std::vector<double>& x) {
  std::vector<double> y(static_cast<std::size_t>(g_mj->nq + g_mj->nv), 0.0);
  auto at = [&](int i) { return i < 0 ? 0.0 : x[static_cast<std::size_t>(i)]; };
  for (const JointIdx& j : g_joints) {
    if (j.slot) {  // Whitworth: crank pin P = (0, 0.3) + L4 e(tc), s = P . e(tk)
      const double l4 = mbsc_param("L4");
      const double tc = at(index_of("crank.theta")), tk = at(index_of("rocker.theta"));
      const double wc = at(index_of("crank.w")), wk = at(index_of("rocker.w"));
      const double px = l4 * std::cos(tc), py = 0.3 + l4 * std::sin(tc);
      const double vx = -l4 * std::sin(tc) * wc, vy = l4 * std::cos(tc) * wc;
      y[static_cast<std::size_t>(j.qadr)] = px * std::cos(tk) + py * std::sin(tk);
      y[static_cast<std::size_t>(g_mj->nq + j.vadr)] =
          vx * std::cos(tk) + vy * std::sin(tk) + (-px * std::sin(tk) + py * std::cos(tk)) * wk;
      continue;
    }
    y[static_cast<std::size_t>(j.qadr)] = at(j.pq) - at(j.mq);
    y[static_cast<std::size_t>(g_mj->nq + j.vadr)] = at(j.pu) - at(j.mu);
  }
  return y;
}

void mujoco_set(const double* y) {
  std::memcpy(g_md->qpos, y, sizeof(double) * static_cast<std::size_t>(g_mj->nq));
  std::memcpy(g_md->qvel, y + g_mj->nq, sizeof(double) * static_cast<std::size_t>(g_mj->nv));
  mju_zero(g_md->qfrc_applied, g_mj->nv);
  for (const auto& [dof, f] : g_qfrc) g_md->qfrc_applied[dof] = f;
}

int rhs_mj(const double* y, double* out) {
  mujoco_set(y);
  mj_forward(g_mj, g_md);
  std::memcpy(out, g_md->qacc, sizeof(double) * static_cast<std::size_t>(g_mj->nv));
  return 0;
}

// MuJoCo's qacc at the mbsc state x against mbsc's rates xdot mapped to its joints.
double mujoco_diff(const std::vector<double>& x, const std::vector<double>& xdot) {
  const auto y = mujoco_state(x);
  std::vector<double> acc(static_cast<std::size_t>(g_mj->nv));
  rhs_mj(y.data(), acc.data());
  std::vector<std::pair<double, double>> pairs;
  for (const JointIdx& j : g_joints) {
    if (j.slot) continue;
    const double am = xdot[static_cast<std::size_t>(j.pu)] - (j.mu < 0 ? 0.0 : xdot[static_cast<std::size_t>(j.mu)]);
    pairs.emplace_back(am, acc[static_cast<std::size_t>(j.vadr)]);
  }
  return rel_diff(pairs);
}

double eq_error() {
  double e = 0.0;
  for (int i = 0; i < g_md->nefc; ++i)
    if (g_md->efc_type[i] == mjCNSTR_EQUALITY) e = std::max(e, std::fabs(g_md->efc_pos[i]));
  return e;
}
#endif

using Rhs = int (*)(const double*, double*);

struct Timed {
  const char* tag;
  Rhs f;
  std::vector<std::vector<double>> xs;
  int nout;
  long calls = 1000;
  std::vector<double> reps;
};

double time_loop(Timed& b, double& sink) {
  std::vector<double> out(static_cast<std::size_t>(b.nout));
  const std::size_t ns = b.xs.size();
  for (;;) {
    double acc = 0.0;
    const auto t0 = std::chrono::steady_clock::now();
    for (long i = 0; i < b.calls; ++i) {
      if (b.f(b.xs[static_cast<std::size_t>(i) % ns].data(), out.data()) != 0) die(std::string(b.tag) + ": rhs failed");
      acc += out[0];
    }
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    sink += acc;
    if (s >= 0.3) return s * 1e9 / static_cast<double>(b.calls);
    b.calls = static_cast<long>(static_cast<double>(b.calls) * std::max(2.0, 0.4 / std::max(s, 1e-9)));
  }
}

}  // namespace

int main() {
  const mbsc::runtime::AssemblyModel model{C::kNq,          C::kNu,          C::kNposc, C::kNc, C::position_constraints,
                                           C::position_jacobian, C::velocity_constraints, C::constraint_jacobian,
                                           C::kPositionConstraintNames, C::kConstraintNames};
  std::vector<double> x(C::kNx, 0.0);
  for (const auto& [name, value] : std::vector<std::pair<const char*, double>>{GUESS}) x[static_cast<std::size_t>(index_of(name))] = value;
  std::vector<bool> gq(C::kNq, false), gu(C::kNu, false);
  for (const char* n : {DRIVERS}) {
    const int i = index_of(n);
    if (i < C::kNq) gq[static_cast<std::size_t>(i)] = true;
    else gu[static_cast<std::size_t>(i - C::kNq)] = true;
  }
  g_u.assign(static_cast<std::size_t>(std::max(1, C::kNin)), 0.05);
  const auto r = mbsc::runtime::assemble(model, 0.0, x, gq, gu, g_u.data(), C::kParamDefaults);
  if (!r.ok()) die(r.message);
  const std::vector<double> x0 = x;
  g_pm.assign(C::kParamDefaults, C::kParamDefaults + C::kNp);
  g_pm.push_back(10.0);
  g_pm.push_back(10.0);
#ifdef WITH_SYMPY
  sympy_setup();
#endif
#ifdef WITH_MUJOCO
  mujoco_setup();
#endif
#ifdef WITH_SYMPY
  {
    // sympy at the assembled start state too (not among the 50: its pivots can vanish there)
    const auto y = sympy_state(x0);
    std::vector<double> ys(y.size()), a0(C::kNx);
    const int st = rhs_s(y.data(), ys.data());
    if (rhs_c(x0.data(), a0.data()) != 0) die("mbsc rhs failed");
    std::vector<std::pair<double, double>> pairs;
    for (int k = 0; k < kS; ++k)
      pairs.emplace_back(a0[static_cast<std::size_t>(g_su[static_cast<std::size_t>(k)])], ys[static_cast<std::size_t>(kS + k)]);
    if (st == 0) std::printf("sympy_rel_diff_start=%.3e\n", rel_diff(pairs));
    else std::printf("sympy_rel_diff_start=status %d\n", st);
  }
#endif
  // 50 states along 0.5 s of motion (complement rhs, RK4), and the agreement there.
  std::vector<std::vector<double>> xs;
  auto f = [&](double t, const double* s, double* d) { return C::rhs(t, s, g_u.data(), C::kParamDefaults, d); };
  double worst = 0.0, worst_s = 0.0, worst_mj = 0.0, worst_mj0 = 0.0, eq_states = 0.0;
  std::vector<double> mj_diffs, mj_diffs0;  // per state
  double worst_min = 0.0;
  for (int k = 0; k < 50; ++k) {
    if (mbsc::runtime::rk4_integrate(f, 0.0, 0.01, 20, x, [](double, const std::vector<double>&) {}) != 0) return 1;
    xs.push_back(x);
    std::vector<double> a(C::kNx), b(C::kNx);
    if (rhs_c(x.data(), a.data()) != 0 || rhs_m(x.data(), b.data()) != 0) die("mbsc rhs failed");
    std::vector<std::pair<double, double>> ab;
    for (int i = C::kNq; i < C::kNx; ++i) ab.emplace_back(a[static_cast<std::size_t>(i)], b[static_cast<std::size_t>(i)]);
    worst = std::max(worst, rel_diff(ab));
#ifdef WITH_MINIMAL
    {
      const auto y = minimal_state(x);
      std::vector<double> yd(y.size());
      if (rhs_min(y.data(), yd.data()) != 0) die("minimal rhs failed");
      std::vector<std::pair<double, double>> pairs;
      for (int i = Mn::kNq; i < Mn::kNx; ++i)
        pairs.emplace_back(a[static_cast<std::size_t>(g_min[static_cast<std::size_t>(i)])], yd[static_cast<std::size_t>(i)]);
      worst_min = std::max(worst_min, rel_diff(pairs));
    }
#endif
#ifdef WITH_SYMPY
    {
      const auto y = sympy_state(x);
      std::vector<double> ys(y.size());
      if (rhs_s(y.data(), ys.data()) != 0) die("sympy rhs failed");
      std::vector<std::pair<double, double>> pairs;
      for (int k2 = 0; k2 < kS; ++k2)
        pairs.emplace_back(a[static_cast<std::size_t>(g_su[static_cast<std::size_t>(k2)])], ys[static_cast<std::size_t>(kS + k2)]);
      worst_s = std::max(worst_s, rel_diff(pairs));
    }
#endif
#ifdef WITH_MUJOCO
    {
      mj_diffs.push_back(mujoco_diff(x, a));
      worst_mj = std::max(worst_mj, mj_diffs.back());
      eq_states = std::max(eq_states, eq_error());
      // the same state at rest: MuJoCo's constraint model has no J'v term (see the notes)
      std::vector<double> x2 = x, a2(C::kNx);
      for (int i = C::kNq; i < C::kNx; ++i) x2[static_cast<std::size_t>(i)] = 0.0;
      if (rhs_c(x2.data(), a2.data()) != 0) die("mbsc rhs failed");
      mj_diffs0.push_back(mujoco_diff(x2, a2));
      worst_mj0 = std::max(worst_mj0, mj_diffs0.back());
    }
#endif
  }
  (void)worst_s;
  (void)worst_min;
  (void)worst_mj;
  (void)worst_mj0;
  (void)eq_states;
#ifdef WITH_MUJOCO
  {
    // MuJoCo's loop-closure error: 1 s of mj_step from the assembled state.
    const auto y = mujoco_state(x0);
    mujoco_set(y.data());
    mj_forward(g_mj, g_md);
    std::printf("mujoco_eq_start=%.3e\n", eq_error());
    std::printf("mujoco_eq_states=%.3e\n", eq_states);
    const int steps = static_cast<int>(std::lround(1.0 / g_mj->opt.timestep));
    double emax = 0.0;
    for (int s = 0; s < steps; ++s) {
      mj_step(g_mj, g_md);
      mj_forward(g_mj, g_md);  // efc_pos at the new state
      emax = std::max(emax, eq_error());
    }
    std::printf("mujoco_eq_1s=%.3e\nmujoco_eq_end=%.3e\nmujoco_timestep=%g\nmujoco_version=%d\n", emax, eq_error(),
                g_mj->opt.timestep, mj_version());
    std::printf("mujoco_rel_diff=%.3e\nmujoco_rel_diff_rest=%.3e\nmujoco_nv=%d\n", worst_mj, worst_mj0, g_mj->nv);
    for (auto* v : {&mj_diffs, &mj_diffs0}) std::sort(v->begin(), v->end());
    std::printf("mujoco_rel_diff_median=%.3e\nmujoco_rel_diff_rest_median=%.3e\n", mj_diffs[mj_diffs.size() / 2],
                mj_diffs0[mj_diffs0.size() / 2]);
  }
#endif
#ifdef WITH_SYMPY
  std::printf("sympy_rel_diff=%.3e\n", worst_s);
#endif
#ifdef WITH_MINIMAL
  std::printf("minimal_rel_diff=%.3e\n", worst_min);
#endif
  std::printf("max_rel_diff=%.3e\n", worst);
  std::fflush(stdout);

  std::vector<Timed> runs;
  runs.push_back(Timed{"complement", rhs_c, xs, C::kNx, 1000, {}});
  runs.push_back(Timed{"multipliers", rhs_m, xs, C::kNx, 1000, {}});
#ifdef WITH_MINIMAL
  {
    std::vector<std::vector<double>> ys;
    for (const auto& s : xs) ys.push_back(minimal_state(s));
    runs.push_back(Timed{"minimal", rhs_min, ys, Mn::kNx, 1000, {}});
  }
#endif
#ifdef WITH_SYMPY
  {
    std::vector<std::vector<double>> ys;
    for (const auto& s : xs) ys.push_back(sympy_state(s));
    runs.push_back(Timed{"sympy", rhs_s, ys, 2 * kS, 1000, {}});
  }
#endif
#ifdef WITH_MUJOCO
  {
    std::vector<std::vector<double>> ys;
    for (const auto& s : xs) ys.push_back(mujoco_state(s));
    runs.push_back(Timed{"mujoco", rhs_mj, ys, g_mj->nv, 1000, {}});
  }
#endif
  double sink = 0.0;
  for (Timed& b : runs) time_loop(b, sink);  // warm-up and calibration
  for (int rep = 0; rep < 5; ++rep)
    for (Timed& b : runs) b.reps.push_back(time_loop(b, sink));
  for (Timed& b : runs) {
    std::sort(b.reps.begin(), b.reps.end());
    std::printf("%s_ns=%.1f\n%s_ns_min=%.1f\n%s_ns_max=%.1f\n", b.tag, b.reps[2], b.tag, b.reps[0], b.tag, b.reps[4]);
  }
  if (sink == 42.0) std::printf("#\n");
#ifdef WITH_MUJOCO
  {
    // A check of the state mapping, not a benchmark setting: near-hard equality
    // constraints (solimp 0.99999, solref 2 ms); at rest MuJoCo then meets the rigid loop.
    for (int i = 0; i < g_mj->neq; ++i) {
      g_mj->eq_solref[i * mjNREF] = 0.002;
      g_mj->eq_solref[i * mjNREF + 1] = 1.0;
      g_mj->eq_solimp[i * mjNIMP] = 0.99999;
      g_mj->eq_solimp[i * mjNIMP + 1] = 0.99999;
    }
    double hard = 0.0, hard0 = 0.0;
    for (const auto& s : xs) {
      std::vector<double> a(C::kNx), s0 = s, a0(C::kNx);
      for (int i = C::kNq; i < C::kNx; ++i) s0[static_cast<std::size_t>(i)] = 0.0;
      if (rhs_c(s.data(), a.data()) != 0 || rhs_c(s0.data(), a0.data()) != 0) die("mbsc rhs failed");
      hard = std::max(hard, mujoco_diff(s, a));
      hard0 = std::max(hard0, mujoco_diff(s0, a0));
    }
    std::printf("mujoco_hard_rel_diff=%.3e\nmujoco_hard_rel_diff_rest=%.3e\n", hard, hard0);
  }
  mj_deleteData(g_md);
  mj_deleteModel(g_mj);
#endif
  return 0;
}
