// SPDX-License-Identifier: GPL-2.0-or-later
// The linearization benchmark (issue 13): mbsc's generated linear_parts of the ring-disc
// (models/ring_disc.mbs, thesis Ex 4.2 / 4.7) and of the Whipple bicycle in joint
// coordinates (models/whipple_bicycle_joints.mbs), turned into linear models by
// include/mbsc/runtime/linear_model.hpp:
//  (a) one linear_model() call at the reference (median of many);
//  (b) a 1000-point sweep: linear_model + minimal_components + restrict_to + eigenvalues
//      (Eigen's EigenSolver) per point; the ring-disc over the mass ratio m2/m1 in [0, 5]
//      (the thesis' range; 0 left out: a massless disc has no dynamics) with the steady angle theta_bar solved per point, the bicycle
//      over the forward speed v in [0, 10] m/s with the upright reference rebuilt per v.
// Independent checks printed with the times:
//  * the ring-disc's oscillation frequency against the closed form
//    omega = sqrt(-G_thetadot,theta) (thesis Ex 4.7, the methodology notes), at the
//    thesis data (omega = 2.63296508333) and at every sweep point;
//  * the bicycle's weave, capsize and castering eigenvalues at 5 m/s against Meijaard,
//    Papadopoulos, Ruina and Schwab (2007), Table 2;
//  * both linear models against central differences of the nonlinear rhs along the
//    tangent space (the same generated code, no linear_parts).
//   driver                 key=value lines (times in ns, errors)
//   driver sweep-out FILE  also writes every sweep point's eigenvalues (for sympy's check)
//   driver count ring|bike one call in a count_calls() frame, for callgrind
#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "mbsc/runtime/linear_model.hpp"
#include "ring_disc/ring_disc.hpp"
#include "whipple_bicycle_joints/whipple_bicycle_joints.hpp"

namespace RD = mbsc_gen::ring_disc;
namespace WB = mbsc_gen::whipple_bicycle_joints;
using mbsc::runtime::LinearModel;
using cplx = std::complex<double>;
using Vec = std::vector<double>;

namespace {

template <int N>
int index_of(const char* const (&names)[N], const char* name) {
  for (int i = 0; i < N; ++i)
    if (std::strcmp(names[i], name) == 0) return i;
  std::fprintf(stderr, "no state or parameter %s\n", name);
  std::exit(2);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// ---------------- the ring-disc ----------------
struct Ring {
  Vec p{RD::kParamDefaults, RD::kParamDefaults + RD::kNp};
  double& m1 = p[static_cast<std::size_t>(index_of(RD::kParamNames, "m1"))];
  double& m2 = p[static_cast<std::size_t>(index_of(RD::kParamNames, "m2"))];
  double r1() const { return p[static_cast<std::size_t>(index_of(RD::kParamNames, "r1"))]; }
  double r2() const { return p[static_cast<std::size_t>(index_of(RD::kParamNames, "r2"))]; }
  double g() const { return p[static_cast<std::size_t>(index_of(RD::kParamNames, "g"))]; }
  double xi() const { return p[static_cast<std::size_t>(index_of(RD::kParamNames, "xi"))]; }

  /// theta_bar of the steady motion for the current m2/m1: Newton on
  /// sin T = (m2/m1 + 1)(sin xi - 3 sin T + 2 cos(T - xi) sin xi), from `guess`.
  double steady_theta(double guess) const {
    const double k = m2 / m1 + 1.0, X = xi();
    double T = guess;
    for (int it = 0; it < 50; ++it) {
      const double f = std::sin(T) - k * (std::sin(X) - 3 * std::sin(T) + 2 * std::cos(T - X) * std::sin(X));
      const double df = std::cos(T) - k * (-3 * std::cos(T) - 2 * std::sin(T - X) * std::sin(X));
      const double step = f / df;
      T -= step;
      if (std::fabs(step) < 1e-15) break;
    }
    return T;
  }
  /// The closed form of Ex 4.7: omega^2 = -G_thetadot,theta (methodology notes).
  double omega_closed(double T) const {
    const double X = xi(), G = g(), s2 = std::sin(2 * T - X), s3 = std::sin(T - 2 * X), s4 = std::sin(2 * T - 3 * X);
    const double G_tt = 2 * G * (std::cos(T) + 2 * std::cos(X)) * std::sin(X) /
                        ((2 * std::cos(T - X) + 1) * (2 * std::sin(T) + 3 * s2 - 2 * std::sin(X) + 2 * s3 + s4) * (r1() - r2()));
    return std::sqrt(-G_tt);
  }
  /// The reference: theta = T, at rest (the accelerations follow from the model).
  Vec state(double T) const {
    Vec x(static_cast<std::size_t>(RD::kNx), 0.0);
    x[static_cast<std::size_t>(index_of(RD::kStateNames, "R.y"))] = r1();
    x[static_cast<std::size_t>(index_of(RD::kStateNames, "D.x"))] = (r1() - r2()) * std::sin(xi() - T);
    x[static_cast<std::size_t>(index_of(RD::kStateNames, "D.y"))] = r1() - (r1() - r2()) * std::cos(xi() - T);
    x[static_cast<std::size_t>(index_of(RD::kStateNames, "theta"))] = T;
    return x;
  }
};

// ---------------- the bicycle ----------------
struct Bike {
  Vec p{WB::kParamDefaults, WB::kParamDefaults + WB::kNp};
  double par(const char* n) const { return p[static_cast<std::size_t>(index_of(WB::kParamNames, n))]; }
  /// Upright, straight, at forward speed v (every body moving at v, the wheels rolling).
  Vec state(double v) const {
    Vec x(static_cast<std::size_t>(WB::kNx), 0.0);
    auto at = [](const std::string& n) { return static_cast<std::size_t>(index_of(WB::kStateNames, n.c_str())); };
    const char* bodies[] = {"rear_wheel", "rear_frame", "front_frame", "front_wheel"};
    const double xc[] = {0.0, par("xB"), par("xH"), par("w")}, zc[] = {-par("rR"), par("zB"), par("zH"), -par("rF")};
    for (int k = 0; k < 4; ++k) {
      const std::string b = bodies[k];
      x[at(b + ".x")] = xc[k];
      x[at(b + ".z")] = zc[k];
      x[at(b + ".u")] = v;
    }
    x[at("rear_wheel.wy")] = -v / par("rR");
    x[at("front_wheel.wy")] = -v / par("rF");
    x[at("theta_R_dot")] = -v / par("rR");
    x[at("theta_F_dot")] = -v / par("rF");
    return x;
  }
  std::vector<int> preferred() const {
    return {index_of(WB::kStateNames, "rear_frame.theta"), index_of(WB::kStateNames, "delta"),
            index_of(WB::kStateNames, "rear_frame.wx"), index_of(WB::kStateNames, "delta_dot")};
  }
};

// Eigenvalues of the m x m row-major matrix, sorted by real part then imaginary part.
std::vector<cplx> eigenvalues(const Vec& A, int m) {
  Eigen::MatrixXd M(m, m);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) M(i, j) = A[static_cast<std::size_t>(i * m + j)];
  Eigen::EigenSolver<Eigen::MatrixXd> es(M, false);
  std::vector<cplx> e(es.eigenvalues().data(), es.eigenvalues().data() + m);
  std::sort(e.begin(), e.end(), [](cplx a, cplx b) { return a.real() != b.real() ? a.real() < b.real() : a.imag() < b.imag(); });
  return e;
}

/// The minimal linear model and its eigenvalues at a reference.
struct Point {
  LinearModel lin;
  std::vector<int> sel;
  Vec Am, Bm;
  std::vector<cplx> eig;
};
bool point(const mbsc::runtime::LinearParts& s, const Vec& x, const double* p, const std::vector<int>& preferred, Point& out) {
  std::string why;
  if (mbsc::runtime::linear_model(s, 0.0, x.data(), nullptr, p, out.lin, why) != 0) {
    std::fprintf(stderr, "linear_model: %s\n", why.c_str());
    return false;
  }
  out.sel = mbsc::runtime::minimal_components(out.lin, preferred);
  if (!mbsc::runtime::restrict_to(out.lin, out.sel, out.Am, out.Bm)) return false;
  out.eig = eigenvalues(out.Am, out.lin.m);
  return true;
}

/// The minimal model from central differences of the nonlinear rhs along the tangent
/// space: T = V (S V)^-1 maps the selected components to consistent increments, and
/// Am_fd[:, c] = S (rhs(x + h T_c) - rhs(x - h T_c)) / 2h.
using Rhs = int (*)(double, const double*, const double*, const double*, double*);
Vec fd_minimal(Rhs rhs, const Point& pt, const Vec& x, const double* p) {
  const int n = pt.lin.n, m = pt.lin.m;
  Eigen::MatrixXd V(n, m), SV(m, m);
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < m; ++c) V(i, c) = pt.lin.tangent[static_cast<std::size_t>(i * m + c)];
  for (int a = 0; a < m; ++a) SV.row(a) = V.row(pt.sel[static_cast<std::size_t>(a)]);
  const Eigen::MatrixXd T = V * SV.inverse();
  Vec Am(static_cast<std::size_t>(m * m)), xp(x), xm(x), fp(x.size()), fm(x.size());
  const double h = 1e-6;
  for (int c = 0; c < m; ++c) {
    for (int i = 0; i < n; ++i) {
      xp[static_cast<std::size_t>(i)] = x[static_cast<std::size_t>(i)] + h * T(i, c);
      xm[static_cast<std::size_t>(i)] = x[static_cast<std::size_t>(i)] - h * T(i, c);
    }
    rhs(0.0, xp.data(), nullptr, p, fp.data());
    rhs(0.0, xm.data(), nullptr, p, fm.data());
    for (int a = 0; a < m; ++a) {
      const std::size_t r = static_cast<std::size_t>(pt.sel[static_cast<std::size_t>(a)]);
      Am[static_cast<std::size_t>(a * m + c)] = (fp[r] - fm[r]) / (2 * h);
    }
  }
  return Am;
}

double max_abs_diff(const Vec& a, const Vec& b) {
  double d = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, std::fabs(a[i] - b[i]));
  return d;
}
double max_abs(const Vec& a) {
  double d = 0.0;
  for (double e : a) d = std::max(d, std::fabs(e));
  return d;
}

double largest_imag(const std::vector<cplx>& e) {
  double w = 0.0;
  for (const auto& z : e) w = std::max(w, z.imag());
  return w;
}

/// Distance from `want` to the nearest eigenvalue in `have`.
double nearest(const std::vector<cplx>& have, cplx want) {
  double d = INFINITY;
  for (const auto& z : have) d = std::min(d, std::abs(z - want));
  return d;
}

// Meijaard, Papadopoulos, Ruina and Schwab (2007), Table 2, at v = 5 m/s.
const cplx kWeave{-0.775341882195845, 4.464867713788234};
const cplx kCapsize{-0.322866429004087, 0.0};
const cplx kCastering{-14.0783896927982, 0.0};

// The four non-zero eigenvalues of the bicycle (the others are the ignorable coordinates').
std::vector<cplx> bike_modes(const std::vector<cplx>& e) {
  std::vector<cplx> out;
  for (const auto& z : e)
    if (std::abs(z) > 1e-6) out.push_back(z);
  return out;
}

volatile double g_sink = 0.0;
extern "C" __attribute__((noinline)) void count_calls(const mbsc::runtime::LinearParts& s, const Vec& x, const double* p,
                                                      int reps) {
  LinearModel lin;
  std::string why;
  for (int r = 0; r < reps; ++r) {
    mbsc::runtime::linear_model(s, 0.0, x.data(), nullptr, p, lin, why);
    g_sink = g_sink + lin.A[0];
  }
}

template <class F>
double time_ns(F&& f, int reps, int rounds, double* min_ns = nullptr) {
  std::vector<double> per;
  for (int r = 0; r < rounds; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int k = 0; k < reps; ++k) f();
    const auto t1 = std::chrono::steady_clock::now();
    per.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / reps);
  }
  if (min_ns) *min_ns = *std::min_element(per.begin(), per.end());
  return median(per);
}

}  // namespace

int main(int argc, char** argv) {
  const auto ring_parts = MBSC_LINEAR_PARTS(RD);
  const auto bike_parts = MBSC_LINEAR_PARTS(WB);
  Ring ring;
  const Bike bike;
  const double theta_thesis = ring.steady_theta(0.6);
  const Vec x_ring = ring.state(theta_thesis), x_bike = bike.state(5.0);

  if (argc == 3 && std::string(argv[1]) == "count") {
    const bool is_ring = std::string(argv[2]) == "ring";
    const auto& s = is_ring ? ring_parts : bike_parts;
    const Vec& x = is_ring ? x_ring : x_bike;
    const double* p = is_ring ? ring.p.data() : bike.p.data();
    LinearModel warm;
    std::string why;
    for (int k = 0; k < 20; ++k) mbsc::runtime::linear_model(s, 0.0, x.data(), nullptr, p, warm, why);  // not counted
    const int calls = 100;
    count_calls(s, x, p, calls);
    std::printf("count_calls=%d\n", calls);
    return 0;
  }
  std::FILE* sweep_out = nullptr;
  if (argc == 3 && std::string(argv[1]) == "sweep-out") sweep_out = std::fopen(argv[2], "w");

  // ---- checks at the reference points ----
  Point pr, pb;
  if (!point(ring_parts, x_ring, ring.p.data(), {}, pr) || !point(bike_parts, x_bike, bike.p.data(), bike.preferred(), pb)) return 1;
  std::printf("ring_theta_bar=%.15g\n", theta_thesis);
  std::printf("ring_m=%d\nring_n=%d\n", pr.lin.m, pr.lin.n);
  std::printf("ring_omega=%.15g\n", largest_imag(pr.eig));
  std::printf("ring_omega_err_closed=%.3g\n", std::fabs(largest_imag(pr.eig) - ring.omega_closed(theta_thesis)));
  std::printf("ring_omega_err_thesis=%.3g\n", std::fabs(largest_imag(pr.eig) - 2.63296508333));
  const Vec ring_fd = fd_minimal(&RD::rhs, pr, x_ring, ring.p.data());
  std::printf("ring_fd_rel_diff=%.3g\n", max_abs_diff(ring_fd, pr.Am) / max_abs(pr.Am));
  std::printf("bike_m=%d\nbike_n=%d\n", pb.lin.m, pb.lin.n);
  const auto modes = bike_modes(pb.eig);
  std::printf("bike_eigs=");
  for (const auto& z : pb.eig) std::printf("%.10g%+.10gi ", z.real(), z.imag());
  std::printf("\n");
  const double bike_err = std::max({nearest(modes, kWeave), nearest(modes, std::conj(kWeave)), nearest(modes, kCapsize),
                                    nearest(modes, kCastering)});
  std::printf("bike_modes=%zu\nbike_err_paper=%.3g\n", modes.size(), bike_err);
  const Vec bike_fd = fd_minimal(&WB::rhs, pb, x_bike, bike.p.data());
  std::printf("bike_fd_rel_diff=%.3g\n", max_abs_diff(bike_fd, pb.Am) / max_abs(pb.Am));
  const auto fd_eig = bike_modes(eigenvalues(bike_fd, pb.lin.m));
  const double fd_err = std::max({nearest(fd_eig, kWeave), nearest(fd_eig, std::conj(kWeave)), nearest(fd_eig, kCapsize),
                                  nearest(fd_eig, kCastering)});
  std::printf("bike_fd_err_paper=%.3g\n", fd_err);

  // ---- (a) one linear_model call ----
  LinearModel lin;
  std::string why;
  double mn = 0.0;
  double ns = time_ns([&] { mbsc::runtime::linear_model(ring_parts, 0.0, x_ring.data(), nullptr, ring.p.data(), lin, why); g_sink = g_sink + lin.A[0]; },
                      2000, 31, &mn);
  std::printf("ring_linear_model_ns=%.0f\nring_linear_model_ns_min=%.0f\n", ns, mn);
  ns = time_ns([&] { mbsc::runtime::linear_model(bike_parts, 0.0, x_bike.data(), nullptr, bike.p.data(), lin, why); g_sink = g_sink + lin.A[0]; },
               100, 31, &mn);
  std::printf("bike_linear_model_ns=%.0f\nbike_linear_model_ns_min=%.0f\n", ns, mn);

  // ---- (b) 1000-point sweeps (median of 5 sweeps) ----
  const int npts = 1000;
  const double m1 = ring.m1;
  double ring_err = 0.0;
  std::vector<double> omega(npts);
  auto ring_sweep = [&] {
    double T = 0.6;
    ring_err = 0.0;
    for (int k = 0; k < npts; ++k) {
      ring.m2 = m1 * 5.0 * (k + 1) / npts;  // (0, 5]: the disc needs a mass
      T = ring.steady_theta(T);
      Point pt;
      point(ring_parts, ring.state(T), ring.p.data(), {}, pt);
      omega[static_cast<std::size_t>(k)] = largest_imag(pt.eig);
      ring_err = std::max(ring_err, std::fabs(omega[static_cast<std::size_t>(k)] - ring.omega_closed(T)) / ring.omega_closed(T));
    }
  };
  std::vector<std::vector<cplx>> bike_eigs(npts);
  auto bike_sweep = [&] {
    for (int k = 0; k < npts; ++k) {
      const double v = 10.0 * k / (npts - 1);
      Point pt;
      point(bike_parts, bike.state(v), bike.p.data(), bike.preferred(), pt);
      bike_eigs[static_cast<std::size_t>(k)] = pt.eig;
    }
  };
  ns = time_ns(ring_sweep, 1, 5, &mn);
  std::printf("ring_sweep_ms=%.3f\nring_sweep_ms_min=%.3f\nring_sweep_rel_err_closed=%.3g\n", ns * 1e-6, mn * 1e-6, ring_err);
  ns = time_ns(bike_sweep, 1, 5, &mn);
  std::printf("bike_sweep_ms=%.3f\nbike_sweep_ms_min=%.3f\n", ns * 1e-6, mn * 1e-6);
  ring.m2 = m1 * 8.0 / 67.0;
  if (sweep_out) {
    for (int k = 0; k < npts; ++k) std::fprintf(sweep_out, "ring %d %.17g\n", k, omega[static_cast<std::size_t>(k)]);
    for (int k = 0; k < npts; ++k) {
      std::fprintf(sweep_out, "bike %d", k);
      for (const auto& z : bike_eigs[static_cast<std::size_t>(k)]) std::fprintf(sweep_out, " %.17g %.17g", z.real(), z.imag());
      std::fprintf(sweep_out, "\n");
    }
    std::fclose(sweep_out);
  }
  return 0;
}
