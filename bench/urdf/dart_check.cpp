// SPDX-License-Identifier: GPL-2.0-or-later
// The accelerations of a URDF robot imported by mbsc against DART's (Debian libdart-dev,
// libdart-utils-urdf-dev), which reads the same file: bench/urdf/run_dart_check.sh
// builds this once per robot with the generated code of `mbsc generate ROBOT.urdf
// --state minimal` (MBSC_MODEL_HEADER, MBSC_NS) and prints the largest relative
// difference over random states, joint torques and (floating base) base motions.
//
// Usage: dart_check ROBOT.urdf fixed|floating [SAMPLES]
//
// State map. Joints: DART's joint position, rate and force are mbsc's q_JOINT,
// q_JOINT_dot and tau_JOINT. A floating base is DART's FreeJoint (rotation vector and
// origin; angular and linear velocity of the link in its own axes) and mbsc's free body:
// the mass centre x, y, z of the root link with the links welded to it, a unit
// quaternion, the mass centre's velocity in space u, v, w and the body-axes angular
// speeds wx, wy, wz (the root's axes are its link's). The mass centre and its velocity
// and acceleration are DART's, summed over the welded group's body nodes.
#include <dart/dynamics/FreeJoint.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <dart/dynamics/BodyNode.hpp>
#include <dart/utils/urdf/urdf.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <vector>

#include MBSC_MODEL_HEADER

namespace M = mbsc_gen::MBSC_NS;

namespace {

int index_of(const char* const* names, int n, const std::string& name) {
  for (int i = 0; i < n; ++i)
    if (name == names[i]) return i;
  return -1;
}

/// The model identifier mbsc import makes of a URDF name (other characters become '_').
std::string identifier(const std::string& name) {
  std::string s;
  for (const char c : name) s += std::isalnum(static_cast<unsigned char>(c)) || c == '_' ? c : '_';
  return s;
}

/// The body nodes welded to the root (its group in mbsc).
std::vector<dart::dynamics::BodyNode*> root_group(const dart::dynamics::SkeletonPtr& skel) {
  std::vector<dart::dynamics::BodyNode*> group = {skel->getRootBodyNode()};
  for (std::size_t k = 0; k < group.size(); ++k)
    for (std::size_t c = 0; c < group[k]->getNumChildBodyNodes(); ++c) {
      auto* child = group[k]->getChildBodyNode(c);
      if (child->getParentJoint()->getNumDofs() == 0) group.push_back(child);
    }
  return group;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s ROBOT.urdf fixed|floating [SAMPLES]\n", argv[0]);
    return 2;
  }
  const bool floating = std::string(argv[2]) == "floating";
  const int samples = argc > 3 ? std::atoi(argv[3]) : 100;
  using dart::utils::DartLoader;
  DartLoader::Options options(nullptr, floating ? DartLoader::RootJointType::FLOATING : DartLoader::RootJointType::FIXED);
  DartLoader loader(options);
  auto skel = loader.parseSkeleton(dart::common::Uri::createFromPath(argv[1]));
  if (!skel) {
    std::fprintf(stderr, "DART could not read %s\n", argv[1]);
    return 2;
  }
  skel->setGravity(Eigen::Vector3d(0, 0, -M::kParamDefaults[0]));

  // DART's one-degree-of-freedom joints and where mbsc has them.
  struct JointMap {
    std::size_t dof;
    int q, rate, input;
  };
  std::vector<JointMap> joints;
  for (std::size_t j = 0; j < skel->getNumJoints(); ++j) {
    auto* joint = skel->getJoint(j);
    if (joint->getNumDofs() != 1) continue;
    const std::string q = "q_" + identifier(joint->getName());
    JointMap m{joint->getIndexInSkeleton(0), index_of(M::kStateNames, M::kNx, q),
               index_of(M::kStateNames, M::kNx, q + "_dot"),
               index_of(M::kInputNames, M::kNin, "tau_" + identifier(joint->getName()))};
    if (m.q < 0 || m.rate < 0) {
      std::fprintf(stderr, "joint %s: no %s in the mbsc model\n", joint->getName().c_str(), q.c_str());
      return 2;
    }
    joints.push_back(m);
  }
  const auto group = root_group(skel);
  const std::string base = identifier(skel->getRootBodyNode()->getName());
  auto at = [&](const std::string& component) { return index_of(M::kStateNames, M::kNx, base + "." + component); };

  std::mt19937 rng(27);
  std::uniform_real_distribution<double> unit(-1, 1);
  double worst = 0, worst_abs = 0;
  std::vector<double> x(M::kNx), u(M::kNin > 0 ? M::kNin : 1), xdot(M::kNx);
  for (int s = 0; s < samples; ++s) {
    Eigen::VectorXd q = Eigen::VectorXd::Zero(skel->getNumDofs()), v = q, f = q;
    std::fill(x.begin(), x.end(), 0.0);
    std::fill(u.begin(), u.end(), 0.0);
    for (const auto& j : joints) {
      q[j.dof] = 2 * unit(rng);
      v[j.dof] = 2 * unit(rng);
      x[j.q] = q[j.dof];
      x[j.rate] = v[j.dof];
      if (j.input >= 0) {
        f[j.dof] = 5 * unit(rng);
        u[j.input] = f[j.dof];
      }
    }
    if (floating) {
      Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
      pose.linear() = Eigen::AngleAxisd(2 * unit(rng), Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized())
                          .toRotationMatrix();
      pose.translation() = Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
      q.head<6>() = dart::dynamics::FreeJoint::convertToPositions(pose);
      for (int k = 0; k < 6; ++k) v[k] = unit(rng);
    }
    skel->setPositions(q);
    skel->setVelocities(v);
    skel->setForces(f);
    skel->computeForwardDynamics();
    const Eigen::VectorXd a = skel->getAccelerations();

    // The floating base as mbsc's free body: the group's mass centre, its rates.
    Eigen::Vector3d com = Eigen::Vector3d::Zero(), com_v = com, com_a = com;
    if (floating) {
      double mass = 0;
      for (auto* b : group) {
        const double m = b->getMass();
        mass += m;
        com += m * b->getCOM();
        com_v += m * b->getCOMLinearVelocity();
        com_a += m * b->getCOMLinearAcceleration();
      }
      com /= mass;
      com_v /= mass;
      com_a /= mass;
      const Eigen::Quaterniond e(skel->getRootBodyNode()->getWorldTransform().linear());
      const double xs[] = {com.x(), com.y(), com.z(), e.w(), e.x(), e.y(), e.z(), com_v.x(), com_v.y(), com_v.z(), v[0], v[1], v[2]};
      const char* names[] = {"x", "y", "z", "e0", "e1", "e2", "e3", "u", "v", "w", "wx", "wy", "wz"};
      for (int k = 0; k < 13; ++k) {
        if (at(names[k]) < 0) {
          std::fprintf(stderr, "no %s.%s in the mbsc model\n", base.c_str(), names[k]);
          return 2;
        }
        x[at(names[k])] = xs[k];
      }
    }
    const int status = M::rhs(0, x.data(), u.data(), M::kParamDefaults, xdot.data());
    if (status != 0) {
      std::fprintf(stderr, "sample %d: rhs status %d\n", s, status);
      return 1;
    }
    // Relative to the largest acceleration of the sample.
    double scale = 0, diff = 0;
    for (const auto& j : joints) {
      scale = std::max(scale, std::abs(a[j.dof]));
      diff = std::max(diff, std::abs(xdot[j.rate] - a[j.dof]));
    }
    if (floating) {
      const double want[] = {com_a.x(), com_a.y(), com_a.z(), a[0], a[1], a[2]};
      const char* names[] = {"u", "v", "w", "wx", "wy", "wz"};
      for (int k = 0; k < 6; ++k) {
        scale = std::max(scale, std::abs(want[k]));
        diff = std::max(diff, std::abs(xdot[at(names[k])] - want[k]));
      }
    }
    worst = std::max(worst, diff / scale);
    worst_abs = std::max(worst_abs, diff);
  }
  std::printf("%s (%s base): %zu joints, %d random states: largest difference %.3g relative (%.3g absolute)\n", argv[1],
              floating ? "floating" : "fixed", joints.size(), samples, worst, worst_abs);
  return worst <= 1e-10 ? 0 : 1;
}
