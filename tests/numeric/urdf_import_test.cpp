// SPDX-License-Identifier: GPL-2.0-or-later
// URDF robots read by mbsc (docs/urdf.md) against an independent reading of the same
// files (urdf_reference.hpp: tinyxml2 directly, links kept apart, recursive
// Newton-Euler in world axes). tests/data/urdf/every_joint.urdf has revolute, continuous
// and prismatic joints with turned origins (quarter turns and others), a tilted
// prismatic axis, a welded tool with its own inertial frame, joint damping and a mimic
// joint; floating_base.urdf a free-flying trunk with a welded sensor and two legs.
// Both are generated from the .urdf itself with --state minimal. At random states,
// joint torques and base motions the accelerations agree to 1e-10 of the largest.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "derivative_check.hpp"
#include "every_joint/every_joint.hpp"
#include "floating_base/floating_base.hpp"
#include "test_support.hpp"
#include "urdf_reference.hpp"

namespace {

using urdf_reference::Mat3;
using urdf_reference::Robot;
using urdf_reference::Vec3;

int find(const char* const* names, int n, const std::string& name) {
  for (int i = 0; i < n; ++i)
    if (name == names[i]) return i;
  return -1;
}

/// The reference's generalized accelerations for applied joint forces `applied`, with
/// mimic joints following their joints (G^T M G nu' = G^T (applied - bias)).
Eigen::VectorXd accelerations(const Robot& r, const Eigen::VectorXd& q, const Mat3& R, const Vec3& p, const Eigen::VectorXd& nu,
                              const Eigen::VectorXd& applied, const Vec3& g) {
  const int n = r.dofs;
  Eigen::MatrixXd M(n, n);
  for (int k = 0; k < n; ++k)
    M.col(k) = r.inverse(q, R, p, Eigen::VectorXd::Zero(n), Eigen::VectorXd::Unit(n, k), Vec3::Zero());
  const Eigen::VectorXd bias = r.inverse(q, R, p, nu, Eigen::VectorXd::Zero(n), g);
  Eigen::MatrixXd G = Eigen::MatrixXd::Identity(n, n);
  std::vector<int> keep;
  for (const auto& j : r.joints)
    if (!j.mimic.empty()) G.row(j.dof) = j.multiplier * G.row(r.joint(j.mimic).dof);
  for (int k = 0; k < n; ++k) {
    bool follower = false;
    for (const auto& j : r.joints) follower = follower || (!j.mimic.empty() && j.dof == k);
    if (!follower) keep.push_back(k);
  }
  Eigen::MatrixXd Gk(n, static_cast<Eigen::Index>(keep.size()));
  for (std::size_t c = 0; c < keep.size(); ++c) Gk.col(static_cast<Eigen::Index>(c)) = G.col(keep[c]);
  const Eigen::VectorXd z = (Gk.transpose() * M * Gk).ldlt().solve(Gk.transpose() * (applied - bias));
  return Gk * z;
}

/// The mass centre of the links welded to link `base` (by fixed joints), in its frame.
Vec3 welded_mass_centre(const Robot& r, int base) {
  double m = r.links[static_cast<std::size_t>(base)].m;
  Vec3 first = m * r.links[static_cast<std::size_t>(base)].c;
  for (const auto& j : r.joints)
    if (j.type == "fixed" && j.parent == base) {
      const auto& l = r.links[static_cast<std::size_t>(j.child)];
      m += l.m;
      first += l.m * (j.xyz + j.R * l.c);
    }
  return first / m;
}

/// Random states of the generated model NS against the reference; returns the largest
/// difference relative to the largest acceleration of its sample.
template <class Model>
double compare(const Robot& r, const Model& model, int samples) {
  std::mt19937 rng(2027);
  std::uniform_real_distribution<double> unit(-1, 1);
  const Vec3 g(0, 0, -model.p[0]);
  double worst = 0;
  for (int s = 0; s < samples; ++s) {
    const int n = r.dofs;
    Eigen::VectorXd q = Eigen::VectorXd::Zero(n), nu = q, applied = q;
    std::vector<double> x(static_cast<std::size_t>(model.nx), 0.0), u(static_cast<std::size_t>(model.nin) + 1, 0.0),
        xdot(static_cast<std::size_t>(model.nx));
    Mat3 R = Mat3::Identity();
    Vec3 p = Vec3::Zero(), rc = Vec3::Zero();
    std::string base;
    for (const auto& j : r.joints) {
      if (j.type == "floating") {
        R = Eigen::AngleAxisd(2 * unit(rng), Vec3(unit(rng), unit(rng), unit(rng)).normalized()).toRotationMatrix();
        p = Vec3(unit(rng), unit(rng), unit(rng));
        for (int k = 0; k < 6; ++k) nu[j.dof + k] = unit(rng);
        base = r.links[static_cast<std::size_t>(j.child)].name;
        rc = R * welded_mass_centre(r, j.child);
        continue;
      }
      if (j.dof < 0 || !j.mimic.empty()) continue;
      q[j.dof] = j.type == "prismatic" ? 0.2 * unit(rng) : 1.5 * unit(rng);
      nu[j.dof] = 2 * unit(rng);
    }
    for (const auto& j : r.joints)
      if (!j.mimic.empty()) {
        const auto& f = r.joint(j.mimic);
        q[j.dof] = j.multiplier * q[f.dof] + j.offset;
        nu[j.dof] = j.multiplier * nu[f.dof];
      }
    for (const auto& j : r.joints) {
      if (j.dof < 0 || j.type == "floating") continue;
      const int iq = find(model.names, model.nx, "q_" + j.name), iv = find(model.names, model.nx, "q_" + j.name + "_dot");
      REQUIRE((iq >= 0 || !j.mimic.empty()));  // a mimic coordinate follows from its row
      if (iq >= 0) x[static_cast<std::size_t>(iq)] = q[j.dof];
      if (iv >= 0) x[static_cast<std::size_t>(iv)] = nu[j.dof];
      applied[j.dof] = -j.damping * nu[j.dof];
      const int iu = find(model.inputs, model.nin, "tau_" + j.name);
      if (iu >= 0) {
        u[static_cast<std::size_t>(iu)] = 5 * unit(rng);
        applied[j.dof] += u[static_cast<std::size_t>(iu)];
      }
    }
    int w_at = -1, u_at = -1, dof0 = 0;
    if (!base.empty()) {
      const Eigen::Quaterniond e(R);
      const Vec3 w_body = R.transpose() * nu.head<3>();
      const Vec3 vc = nu.segment<3>(3) + nu.head<3>().cross(rc);
      const Vec3 xc = p + rc;
      const double values[] = {xc.x(), xc.y(), xc.z(), e.w(), e.x(), e.y(), e.z(), vc.x(), vc.y(), vc.z(), w_body.x(), w_body.y(), w_body.z()};
      const char* names[] = {"x", "y", "z", "e0", "e1", "e2", "e3", "u", "v", "w", "wx", "wy", "wz"};
      for (int k = 0; k < 13; ++k) {
        const int i = find(model.names, model.nx, base + "." + names[k]);
        REQUIRE(i >= 0);
        x[static_cast<std::size_t>(i)] = values[k];
      }
      w_at = find(model.names, model.nx, base + ".wx");
      u_at = find(model.names, model.nx, base + ".u");
      dof0 = 6;
    }
    REQUIRE(model.rhs(0.0, x.data(), u.data(), model.p, xdot.data()) == 0);
    const Eigen::VectorXd a = accelerations(r, q, R, p, nu, applied, g);
    double scale = 0, diff = 0;
    for (const auto& j : r.joints) {
      if (j.dof < dof0 || !j.mimic.empty()) continue;
      const int iv = find(model.names, model.nx, "q_" + j.name + "_dot");
      REQUIRE(iv >= 0);
      scale = std::max(scale, std::abs(a[j.dof]));
      diff = std::max(diff, std::abs(xdot[static_cast<std::size_t>(iv)] - a[j.dof]));
    }
    if (!base.empty()) {
      const Vec3 alpha = a.head<3>(), w = nu.head<3>();
      const Vec3 alpha_body = R.transpose() * alpha;
      const Vec3 ac = a.segment<3>(3) + alpha.cross(rc) + w.cross(w.cross(rc));
      for (int k = 0; k < 3; ++k) {
        scale = std::max({scale, std::abs(alpha_body[k]), std::abs(ac[k])});
        diff = std::max(diff, std::abs(xdot[static_cast<std::size_t>(w_at + k)] - alpha_body[k]));
        diff = std::max(diff, std::abs(xdot[static_cast<std::size_t>(u_at + k)] - ac[k]));
      }
    }
    worst = std::max(worst, diff / scale);
  }
  return worst;
}

struct ModelView {
  const char* const* names;
  int nx;
  const char* const* inputs;
  int nin;
  const double* p;
  int (*rhs)(double, const double*, const double*, const double*, double*);
};

}  // namespace

TEST_CASE("URDF import: every joint type against an independent recursion", "[urdf]") {
  namespace M = mbsc_gen::every_joint;
  const Robot r(MBSC_SOURCE_DIR "/tests/data/urdf/every_joint.urdf");
  const ModelView view{M::kStateNames, M::kNx, M::kInputNames, M::kNin, M::kParamDefaults, M::rhs};
  // The mimic joint follows the finger: the finger's angle and rate are the state's.
  CHECK(find(M::kStateNames, M::kNx, "q_finger_dot") >= 0);
  CHECK(find(M::kStateNames, M::kNx, "q_thumb_dot") < 0);
  CHECK(M::kNdof == 4);
  const double worst = compare(r, view, 60);
  INFO("largest relative difference " << worst);
  CHECK(worst < 1e-10);
}

TEST_CASE("URDF import: a floating base with a welded sensor against an independent recursion", "[urdf]") {
  namespace M = mbsc_gen::floating_base;
  const Robot r(MBSC_SOURCE_DIR "/tests/data/urdf/floating_base.urdf");
  const ModelView view{M::kStateNames, M::kNx, M::kInputNames, M::kNin, M::kParamDefaults, M::rhs};
  CHECK(M::kNdof == 10);
  CHECK(M::kNquaternions == 1);
  const double worst = compare(r, view, 60);
  INFO("largest relative difference " << worst);
  CHECK(worst < 1e-10);
}

TEST_CASE("URDF import: the generated derivatives agree with central differences", "[urdf][derivatives]") {
  std::mt19937 rng(20261206);
  for (int trial = 0; trial < 3; ++trial) {
    mbsc_test::check_derivatives(MBSC_DERIVATIVE_MODEL(every_joint), rng);
    mbsc_test::check_derivatives(MBSC_DERIVATIVE_MODEL(floating_base), rng);
  }
}
