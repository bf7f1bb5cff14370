// SPDX-License-Identifier: GPL-2.0-or-later
// One generic harness (generic_harness.hpp) compiled against every shipped model, a
// minimal-state and a multipliers variant, a model with nothing (no parameter, input,
// constraint or output) and one whose energy is not defined. At a random state it calls
// every function of the common ABI and checks them against each other: sizes written
// exactly, M z' = h against rhs, the Jacobians against central differences of the
// residuals, full_state against the state, the partition dispatchers against rhs, u null
// when the model has no input, the batched rhs against rhs.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "double_pendulum/double_pendulum.hpp"
#include "dc_motor/dc_motor.hpp"
#include "dc_motor_mult/dc_motor_mult.hpp"
#include "chaplygin_sleigh/chaplygin_sleigh.hpp"
#include "dp_min/dp_min.hpp"
#include "five_bar/five_bar.hpp"
#include "four_bar/four_bar.hpp"
#include "four_bar_min/four_bar_min.hpp"
#include "four_bar_mult/four_bar_mult.hpp"
#include "four_bar_toggle/four_bar_toggle.hpp"
#include "free_body_euler/free_body_euler.hpp"
#include "free_body_quaternion/free_body_quaternion.hpp"
#include "humanoid_tree/humanoid_tree.hpp"
#include "heavy_top/heavy_top.hpp"
#include "sssp/sssp.hpp"
#include "slider_crank_3d/slider_crank_3d.hpp"
#include "free_particle/free_particle.hpp"
#include "batch_check.hpp"
#include "generic_harness.hpp"
#include "massless_rod_pendulum/massless_rod_pendulum.hpp"
#include "parallelogram_chain/parallelogram_chain.hpp"
#include "ring_disc/ring_disc.hpp"
#include "rolling_disc/rolling_disc.hpp"
#include "rolling_disc_incline/rolling_disc_incline.hpp"
#include "sphere_trough/sphere_trough.hpp"
#include "ring_disc_joints/ring_disc_joints.hpp"
#include "slider_crank/slider_crank.hpp"
#include "spherical_pendulum_angles/spherical_pendulum_angles.hpp"
#include "spherical_pendulum_cartesian/spherical_pendulum_cartesian.hpp"
#include "spherical_pendulum_extra_speed/spherical_pendulum_extra_speed.hpp"
#include "stiff_spring_damper/stiff_spring_damper.hpp"
#include "three_r_arm/three_r_arm.hpp"
#include "three_r_arm_joint/three_r_arm_joint.hpp"
#include "three_rrr/three_rrr.hpp"
#include "whipple_bicycle/whipple_bicycle.hpp"
#include "whipple_bicycle_joints/whipple_bicycle_joints.hpp"
#include "whitworth/whitworth.hpp"
#include "gantry_crane/gantry_crane.hpp"
#include "spatial_arm/spatial_arm.hpp"

MBSC_GENERIC_MODEL(chaplygin_sleigh);
MBSC_GENERIC_MODEL(double_pendulum);
MBSC_GENERIC_MODEL(dc_motor);
MBSC_GENERIC_MODEL(dc_motor_mult);
MBSC_GENERIC_MODEL(dp_min);
MBSC_GENERIC_MODEL(five_bar);
MBSC_GENERIC_MODEL(four_bar);
MBSC_GENERIC_MODEL(four_bar_min);
MBSC_GENERIC_MODEL(four_bar_mult);
MBSC_GENERIC_MODEL(four_bar_toggle);
MBSC_GENERIC_MODEL(free_body_euler);
MBSC_GENERIC_MODEL(free_body_quaternion);
MBSC_GENERIC_MODEL(humanoid_tree);
MBSC_GENERIC_MODEL(heavy_top);
MBSC_GENERIC_MODEL(sssp);
MBSC_GENERIC_MODEL(slider_crank_3d);
MBSC_GENERIC_MODEL(free_particle);
MBSC_GENERIC_MODEL(massless_rod_pendulum);
MBSC_GENERIC_MODEL(parallelogram_chain);
MBSC_GENERIC_MODEL(ring_disc);
MBSC_GENERIC_MODEL(rolling_disc);
MBSC_GENERIC_MODEL(rolling_disc_incline);
MBSC_GENERIC_MODEL(sphere_trough);
MBSC_GENERIC_MODEL(ring_disc_joints);
MBSC_GENERIC_MODEL(slider_crank);
MBSC_GENERIC_MODEL(spherical_pendulum_angles);
MBSC_GENERIC_MODEL(spherical_pendulum_cartesian);
MBSC_GENERIC_MODEL(spherical_pendulum_extra_speed);
MBSC_GENERIC_MODEL(stiff_spring_damper);
MBSC_GENERIC_MODEL(three_r_arm);
MBSC_GENERIC_MODEL(three_r_arm_joint);
MBSC_GENERIC_MODEL(three_rrr);
MBSC_GENERIC_MODEL(whipple_bicycle);
MBSC_GENERIC_MODEL(whipple_bicycle_joints);
MBSC_GENERIC_MODEL(whitworth);
MBSC_GENERIC_MODEL(gantry_crane);
MBSC_GENERIC_MODEL(spatial_arm);

using mbsc_test::Arguments;
using mbsc_test::call;
using mbsc_test::find_name;
using mbsc_test::Result;

namespace {

double scale(const std::vector<double>& v) {
  double s = 1.0;
  for (double e : v) s = std::max(s, std::abs(e));
  return s;
}

void require_ok(const Result& r, const std::string& what) {
  INFO(what);
  REQUIRE(r.guard_intact);
  REQUIRE(r.status == 0);
  for (double v : r.values) REQUIRE(std::isfinite(v));
}

// d(f)/d(x[first + j]) by central differences, row-major rows x n.
template <class M>
std::vector<double> central_difference(mbsc_test::Function f, int rows, int first, int n, const Arguments<M>& a) {
  std::vector<double> d(static_cast<std::size_t>(rows * n));
  for (int j = 0; j < n; ++j) {
    const double h = 1e-6;
    std::vector<double> xp = a.x, xm = a.x;
    xp[static_cast<std::size_t>(first + j)] += h;
    xm[static_cast<std::size_t>(first + j)] -= h;
    const Result rp = call(f, rows, a, xp), rm = call(f, rows, a, xm);
    REQUIRE(rp.status == 0);
    REQUIRE(rm.status == 0);
    for (int i = 0; i < rows; ++i)
      d[static_cast<std::size_t>(i * n + j)] = (rp.values[static_cast<std::size_t>(i)] - rm.values[static_cast<std::size_t>(i)]) / (2 * h);
  }
  return d;
}

// `reduced`: the rhs integrates M z' = h (the complement form). The multipliers form's
// rhs adds Baumgarte terms away from the constraint manifold; its M and h are compared
// with the complement model's in check_against_full.
template <class M>
void check_model(std::mt19937& rng, bool reduced = true) {
  INFO("model " << M::kName);
  const Arguments<M> a(rng);
  // The sizes hold together.
  REQUIRE(M::kNx == M::kNq + M::kNu);
  REQUIRE(M::kNxFull == M::kNqFull + M::kNuFull);
  REQUIRE(M::kNposc <= M::kNc);
  REQUIRE(M::kNpartitions >= 1);

  const Result xdot = call(M::rhs, M::kNx, a, a.x);
  require_ok(xdot, "rhs");
  const Result mass = call(M::mass_matrix, M::kNdof * M::kNdof, a, a.x);
  require_ok(mass, "mass_matrix");
  const Result h = call(M::forcing, M::kNdof, a, a.x);
  require_ok(h, "forcing");
  const Result r = call(M::position_constraints, M::kNposc, a, a.x);
  require_ok(r, "position_constraints");
  const Result v = call(M::velocity_constraints, M::kNc, a, a.x);
  require_ok(v, "velocity_constraints");
  const Result A = call(M::constraint_jacobian, M::kNc * M::kNuFull, a, a.x);
  require_ok(A, "constraint_jacobian");
  const Result J = call(M::position_jacobian, M::kNposc * M::kNqFull, a, a.x);
  require_ok(J, "position_jacobian");
  const Result y = call(M::outputs, M::kNy, a, a.x);
  require_ok(y, "outputs");
  const Result full = call(M::full_state, M::kNxFull, a, a.x);
  require_ok(full, "full_state");
  const Result rc = call(M::conditioning, M::kNblocks, a, a.x);
  require_ok(rc, "conditioning");
  for (double c : rc.values) {
    INFO("rcond " << c);
    REQUIRE((c > 0.0 && c <= 1.0 + 1e-12));
  }

  // energy: {T, V, T + V}, or status 4 and NaN where the model's energy is not defined.
  const Result E = call(M::energy, 3, a, a.x);
  REQUIRE(E.guard_intact);
  if (E.status == 4) {
    for (double e : E.values) REQUIRE(std::isnan(e));
  } else {
    require_ok(E, "energy");
    REQUIRE(E.values[2] == Approx(E.values[0] + E.values[1]).margin(1e-12));
  }

  // M z' = h, with z' read from rhs by the names of the independent speeds.
  for (int i = 0; i < M::kNdof && reduced; ++i) {
    double lhs = 0.0;
    for (int j = 0; j < M::kNdof; ++j) {
      const int s = find_name(M::kStateNames, M::kNx, M::kDofNames[j]);
      REQUIRE(s >= M::kNq);
      lhs += mass.values[static_cast<std::size_t>(i * M::kNdof + j)] * xdot.values[static_cast<std::size_t>(s)];
    }
    REQUIRE(lhs == Approx(h.values[static_cast<std::size_t>(i)]).margin(1e-9 * scale(h.values)));
  }

  // inverse_dynamics(x, z') gives back the inputs that rhs was called with: z' is read
  // from rhs (M z' = h0 + H u holds there), and H u = M z' - h0 has the solution u when
  // there are no more inputs than degrees of freedom (least squares with fewer: the
  // residual is zero, so u again). With more, it gives the smallest inputs that produce
  // z': rhs at them gives z' back.
  {
    std::vector<double> zdot(static_cast<std::size_t>(std::max(M::kNdof, 1)), 0.0);
    for (int j = 0; j < M::kNdof; ++j)
      zdot[static_cast<std::size_t>(j)] = xdot.values[static_cast<std::size_t>(find_name(M::kStateNames, M::kNx, M::kDofNames[j]))];
    const Result inv = call(M::inverse_dynamics, M::kNin, a.t, a.x, zdot.data(), a.p);
    REQUIRE(inv.guard_intact);
    if (inv.status == 4) {
      // Not defined for this model (Coulomb friction: the inputs and the friction are one
      // coupled problem): NaN, never a number.
      for (double v : inv.values) REQUIRE(std::isnan(v));
    } else {
      require_ok(inv, "inverse_dynamics");
      if (M::kNin > M::kNdof && reduced) {
        const Result again = call(M::rhs, M::kNx, a.t, a.x, inv.values.data(), a.p);
        require_ok(again, "rhs at the inverse's inputs");
        for (int j = 0; j < M::kNdof; ++j) {
          const auto s = static_cast<std::size_t>(find_name(M::kStateNames, M::kNx, M::kDofNames[j]));
          REQUIRE(again.values[s] == Approx(xdot.values[s]).margin(1e-8 * scale(xdot.values)));
        }
      } else {
        for (int k = 0; k < M::kNin && reduced && M::kNdof > 0; ++k)
          REQUIRE(inv.values[static_cast<std::size_t>(k)] == Approx(a.u[static_cast<std::size_t>(k)]).margin(1e-8));
      }
    }
  }

  // full_state: the state's own entries, by name (all of them with --state full).
  for (int i = 0; i < M::kNx; ++i) {
    const int f = find_name(M::kFullStateNames, M::kNxFull, M::kStateNames[i]);
    REQUIRE(f >= 0);
    REQUIRE(full.values[static_cast<std::size_t>(f)] == a.x[static_cast<std::size_t>(i)]);
  }

  // The Jacobians against central differences of the residuals (full layout only: the
  // minimal-state twins are compared with their full-state models below).
  if (M::kNx == M::kNxFull) {
    const auto dr = central_difference(M::position_constraints, M::kNposc, 0, M::kNqFull, a);
    for (std::size_t k = 0; k < dr.size(); ++k) REQUIRE(J.values[k] == Approx(dr[k]).margin(1e-6 * scale(J.values)));
    const auto dv = central_difference(M::velocity_constraints, M::kNc, M::kNqFull, M::kNuFull, a);
    for (std::size_t k = 0; k < dv.size(); ++k) REQUIRE(A.values[k] == Approx(dv[k]).margin(1e-6 * scale(A.values)));
  }

  // The partition dispatchers: partition 0 is rhs; an index out of range is status 3.
  const Result xdot0 = call(
      [](double t, const double* x, const double* u, const double* p, double* o) { return M::rhs_partition(0, t, x, u, p, o); },
      M::kNx, a, a.x);
  require_ok(xdot0, "rhs_partition(0)");
  REQUIRE(xdot0.values == xdot.values);
  double scratch[1] = {0.0};
  std::vector<double> out(static_cast<std::size_t>(M::kNx) + 1);
  REQUIRE(M::rhs_partition(M::kNpartitions, a.t, a.x.data(), a.u_ptr(), a.p.data(), out.data()) == 3);
  REQUIRE(M::conditioning_partition(-1, a.t, a.x.data(), a.u_ptr(), a.p.data(), scratch) == 3);
  for (int k = 0; k < M::kNpartitions; ++k) {
    REQUIRE(M::conditioning_partition(k, a.t, a.x.data(), a.u_ptr(), a.p.data(), scratch) == 0);
    REQUIRE((scratch[0] > 0.0 && scratch[0] <= 1.0));
  }
  // The batched rhs: instance by instance the ordinary rhs (batch_check.hpp).
  mbsc_test::check_batch<M>(rng);
}

// A Jacobian's CSR twin against the dense function at the arguments `a`: a well-formed
// pattern (offsets from 0 to nnz, columns in range and increasing within each row), the
// values written exactly (nnz of them), and the dense matrix equal to their expansion,
// with exact zeros everywhere else (the dense OUT starts as a guard value, not 0).
template <class M>
void check_csr(mbsc_test::Function dense, mbsc_test::Function values, int rows, int cols, int nnz, const int* row_ptr,
               const int* col_idx, const Arguments<M>& a, const char* what) {
  INFO(what);
  REQUIRE(row_ptr[0] == 0);
  REQUIRE(row_ptr[rows] == nnz);
  REQUIRE(nnz <= rows * cols);
  std::vector<double> expanded(static_cast<std::size_t>(rows * cols), 0.0);
  const Result v = call(values, nnz, a, a.x);
  require_ok(v, what);
  for (int i = 0; i < rows; ++i) {
    REQUIRE(row_ptr[i] <= row_ptr[i + 1]);
    for (int k = row_ptr[i]; k < row_ptr[i + 1]; ++k) {
      REQUIRE((col_idx[k] >= 0 && col_idx[k] < cols));
      if (k > row_ptr[i]) REQUIRE(col_idx[k - 1] < col_idx[k]);
      expanded[static_cast<std::size_t>(i * cols + col_idx[k])] = v.values[static_cast<std::size_t>(k)];
    }
  }
  const Result d = call(dense, rows * cols, a, a.x);
  require_ok(d, what);
  for (std::size_t k = 0; k < expanded.size(); ++k) {
    INFO("entry " << k / static_cast<std::size_t>(cols) << ", " << k % static_cast<std::size_t>(cols));
    if (expanded[k] == 0.0) REQUIRE(d.values[k] == 0.0);
    else REQUIRE(d.values[k] == Approx(expanded[k]).epsilon(1e-13).margin(1e-13 * scale(d.values)));
  }
}

template <class M>
void check_sparse_jacobians(std::mt19937& rng) {
  INFO("model " << M::kName);
  const Arguments<M> a(rng);
  check_csr(M::constraint_jacobian, M::constraint_jacobian_values, M::kNc, M::kNuFull, M::kConstraintJacobianNnz,
            M::kConstraintJacobianRowPtr, M::kConstraintJacobianColIdx, a, "constraint_jacobian");
  check_csr(M::position_jacobian, M::position_jacobian_values, M::kNposc, M::kNqFull, M::kPositionJacobianNnz,
            M::kPositionJacobianRowPtr, M::kPositionJacobianColIdx, a, "position_jacobian");
}

// A reduced-state or other-formulation variant against its full-state complement model
// at the same full state: the Jacobians (over the full layout) and M, h agree.
template <class Variant, class Full>
void check_against_full(std::mt19937& rng, bool compare_reduced) {
  INFO("variant " << Variant::kName << " against " << Full::kName);
  REQUIRE(Variant::kNxFull == Full::kNx);
  Arguments<Variant> a(rng);
  if (Variant::kNx == Variant::kNxFull) {
    // Same layout: same state names in the same order.
    for (int i = 0; i < Full::kNx; ++i) REQUIRE(std::string(Variant::kStateNames[i]) == Full::kStateNames[i]);
  }
  const Result xf = call(Variant::full_state, Variant::kNxFull, a, a.x);
  require_ok(xf, "full_state");
  std::vector<double> p_full(Full::kParamDefaults, Full::kParamDefaults + Full::kNp);
  auto same = [&](mbsc_test::Function fv, mbsc_test::Function ff, int n, const char* what) {
    INFO(what);
    const Result rv = call(fv, n, a, a.x);
    const Result rf = call(ff, n, a.t, xf.values, nullptr, p_full);
    require_ok(rv, what);
    require_ok(rf, what);
    for (int k = 0; k < n; ++k)
      REQUIRE(rv.values[static_cast<std::size_t>(k)] == Approx(rf.values[static_cast<std::size_t>(k)]).margin(1e-9 * scale(rf.values)));
  };
  same(Variant::constraint_jacobian, Full::constraint_jacobian, Full::kNc * Full::kNu, "constraint_jacobian");
  same(Variant::position_jacobian, Full::position_jacobian, Full::kNposc * Full::kNq, "position_jacobian");
  if (compare_reduced) {
    same(Variant::mass_matrix, Full::mass_matrix, Full::kNdof * Full::kNdof, "mass_matrix");
    same(Variant::forcing, Full::forcing, Full::kNdof, "forcing");
  }
}

}  // namespace

TEST_CASE("one generic harness compiles and runs against every shipped model", "[abi]") {
  // Every model in models/ is checked below: a new model must be added here.
  int shipped = 0;
  for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(MBSC_SOURCE_DIR) / "models"))
    shipped += e.path().extension() == ".mbs";
  REQUIRE(shipped == 30);
  std::mt19937 rng(20261201);
  for (int trial = 0; trial < 3; ++trial) {
    check_model<chaplygin_sleigh_abi>(rng);
    check_model<double_pendulum_abi>(rng);
    check_model<five_bar_abi>(rng);
    check_model<four_bar_abi>(rng);
    check_model<four_bar_toggle_abi>(rng);
    check_model<free_body_euler_abi>(rng);
    check_model<free_body_quaternion_abi>(rng);
    check_model<humanoid_tree_abi>(rng);
    check_model<heavy_top_abi>(rng);
    check_model<sssp_abi>(rng);
    check_model<slider_crank_3d_abi>(rng);
    check_model<massless_rod_pendulum_abi>(rng);
    check_model<parallelogram_chain_abi>(rng);
    check_model<ring_disc_abi>(rng);
    check_model<rolling_disc_abi>(rng);
    check_model<rolling_disc_incline_abi>(rng);
    check_model<sphere_trough_abi>(rng);
    check_model<ring_disc_joints_abi>(rng);
    check_model<slider_crank_abi>(rng);
    check_model<spherical_pendulum_angles_abi>(rng);
    check_model<spherical_pendulum_cartesian_abi>(rng);
    check_model<spherical_pendulum_extra_speed_abi>(rng);
    check_model<stiff_spring_damper_abi>(rng);
    check_model<three_r_arm_abi>(rng);
    check_model<three_r_arm_joint_abi>(rng);
    check_model<three_rrr_abi>(rng);
    check_model<whipple_bicycle_abi>(rng);
    check_model<whipple_bicycle_joints_abi>(rng);
    check_model<whitworth_abi>(rng);
    check_model<gantry_crane_abi>(rng);
    check_model<spatial_arm_abi>(rng);
  }
}

TEST_CASE("the generic harness runs against --state minimal and --formulation multipliers", "[abi]") {
  std::mt19937 rng(7);
  check_model<dp_min_abi>(rng);
  check_model<four_bar_min_abi>(rng);
  check_model<four_bar_mult_abi>(rng, false);
  // --state minimal: the Jacobians are over the full layout, at the rebuilt full state.
  // The complement's reduced M and h depend on the state only through q0 and the
  // independent speeds, so a rebuilt state gives the same ones as well.
  check_against_full<dp_min_abi, double_pendulum_abi>(rng, true);
  check_against_full<four_bar_min_abi, four_bar_abi>(rng, true);
  // --formulation multipliers: the same full state, the same reduced M z' = h.
  check_against_full<four_bar_mult_abi, four_bar_abi>(rng, true);
}

TEST_CASE("a model with nothing still has the whole ABI, with zero rows, and takes null u and p", "[abi]") {
  static_assert(free_particle_abi::kNin == 0 && free_particle_abi::kNp == 0 && free_particle_abi::kNc == 0 &&
                free_particle_abi::kNposc == 0 && free_particle_abi::kNy == 0 && free_particle_abi::kNblocks == 0);
  std::mt19937 rng(3);
  check_model<free_particle_abi>(rng);
  // Null u and p, and the closed form: free fall, x'' = 0, y'' = -9.81.
  const double x[4] = {0.1, 0.2, 0.3, -0.4};
  double xdot[4];
  REQUIRE(mbsc_gen::free_particle::rhs(0.0, x, nullptr, nullptr, xdot) == 0);
  REQUIRE(xdot[0] == 0.3);
  REQUIRE(xdot[1] == -0.4);
  REQUIRE(xdot[2] == 0.0);
  REQUIRE(xdot[3] == Approx(-9.81));
  double E[3];
  REQUIRE(mbsc_gen::free_particle::energy(0.0, x, nullptr, nullptr, E) == 0);
  REQUIRE(E[0] == Approx(0.5 * 2 * (0.09 + 0.16)));
  REQUIRE(E[1] == Approx(2 * 9.81 * 0.2));
}

TEST_CASE("a model whose energy is not defined keeps energy, returning 4 and NaN", "[abi]") {
  std::mt19937 rng(5);
  check_model<dc_motor_abi>(rng);
  check_model<dc_motor_mult_abi>(rng, false);
  static_assert(dc_motor_mult_abi::kNp == dc_motor_abi::kNp + 2);  // + the Baumgarte gains
  const double x[2] = {3.0, 0.5}, u[1] = {12.0};
  const double* p = mbsc_gen::dc_motor::kParamDefaults;
  double E[3] = {0.0, 0.0, 0.0};
  REQUIRE(mbsc_gen::dc_motor::energy(0.0, x, u, p, E) == 4);
  REQUIRE(std::isnan(E[0]));
  // rhs against the motor's closed form: Im w' = k i - bm w, Lm i' = v_in - Rm i - kappa w.
  double xdot[2];
  REQUIRE(mbsc_gen::dc_motor::rhs(0.0, x, u, p, xdot) == 0);
  auto param = [&](const char* name) {
    const int i = find_name(mbsc_gen::dc_motor::kParamNames, mbsc_gen::dc_motor::kNp, name);
    REQUIRE(i >= 0);
    return p[i];
  };
  const double k = param("k"), Im = param("Im"), bm = param("bm"), Lm = param("Lm"), Rm = param("Rm"), kappa = param("kappa");
  REQUIRE(std::string(mbsc_gen::dc_motor::kStateNames[0]) == "motor.w");
  REQUIRE(xdot[0] == Approx((k * x[1] - bm * x[0]) / Im));
  REQUIRE(xdot[1] == Approx((u[0] - Rm * x[1] - kappa * x[0]) / Lm));
}

TEST_CASE("the CSR values of both Jacobians expand to the dense Jacobians", "[abi][sparse]") {
  std::mt19937 rng(20261202);
  for (int trial = 0; trial < 5; ++trial) {
    check_sparse_jacobians<chaplygin_sleigh_abi>(rng);
    check_sparse_jacobians<double_pendulum_abi>(rng);
    check_sparse_jacobians<five_bar_abi>(rng);
    check_sparse_jacobians<four_bar_abi>(rng);
    check_sparse_jacobians<four_bar_toggle_abi>(rng);
    check_sparse_jacobians<free_body_euler_abi>(rng);
    check_sparse_jacobians<free_body_quaternion_abi>(rng);
    check_sparse_jacobians<humanoid_tree_abi>(rng);
    check_sparse_jacobians<heavy_top_abi>(rng);
    check_sparse_jacobians<sssp_abi>(rng);
    check_sparse_jacobians<slider_crank_3d_abi>(rng);
    check_sparse_jacobians<massless_rod_pendulum_abi>(rng);
    check_sparse_jacobians<parallelogram_chain_abi>(rng);
    check_sparse_jacobians<ring_disc_abi>(rng);
    check_sparse_jacobians<rolling_disc_abi>(rng);
    check_sparse_jacobians<rolling_disc_incline_abi>(rng);
    check_sparse_jacobians<sphere_trough_abi>(rng);
    check_sparse_jacobians<ring_disc_joints_abi>(rng);
    check_sparse_jacobians<slider_crank_abi>(rng);
    check_sparse_jacobians<spherical_pendulum_angles_abi>(rng);
    check_sparse_jacobians<spherical_pendulum_cartesian_abi>(rng);
    check_sparse_jacobians<spherical_pendulum_extra_speed_abi>(rng);
    check_sparse_jacobians<stiff_spring_damper_abi>(rng);
    check_sparse_jacobians<three_r_arm_abi>(rng);
    check_sparse_jacobians<three_rrr_abi>(rng);
    check_sparse_jacobians<whipple_bicycle_abi>(rng);
    check_sparse_jacobians<whipple_bicycle_joints_abi>(rng);
    check_sparse_jacobians<whitworth_abi>(rng);
    // --state minimal (evaluated at the rebuilt full state), the multipliers form, and a
    // model without constraints (empty patterns).
    check_sparse_jacobians<dp_min_abi>(rng);
    check_sparse_jacobians<four_bar_min_abi>(rng);
    check_sparse_jacobians<four_bar_mult_abi>(rng);
    check_sparse_jacobians<free_particle_abi>(rng);
    check_sparse_jacobians<dc_motor_mult_abi>(rng);
  }
  // The closed loops are sparse: a pin couples two bodies' coordinates, not all of them.
  REQUIRE(4 * mbsc_gen::parallelogram_chain::kConstraintJacobianNnz <
          mbsc_gen::parallelogram_chain::kNc * mbsc_gen::parallelogram_chain::kNuFull);
  REQUIRE(mbsc_gen::parallelogram_chain::kPositionJacobianNnz < mbsc_gen::parallelogram_chain::kNposc * mbsc_gen::parallelogram_chain::kNqFull);
}
