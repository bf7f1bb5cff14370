// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// An independent reading of a URDF's dynamics for tests/numeric/urdf_import_test.cpp:
// the file read here with tinyxml2 (not through mbsc's importer), links kept apart (a
// fixed joint is a joint without motion, not a merge), and the recursive Newton-Euler
// equations in world coordinates (Featherstone's RNEA in its classical vector form):
//   outwards  R_i = R_p R_origin Rot(a, q), w_i = w_p + n q', a_i = ... (n = R_p R_origin a)
//   inwards   f_i = m_i a_ci - m_i g + sum f_child, moments about each joint origin,
//             tau = n . moment (revolute, continuous) or n . f (prismatic).
// The mass matrix is its columns ID(q, 0, e_k) without gravity, the bias ID(q, q', 0); a
// floating joint's six generalized speeds are the base's angular velocity and its
// origin's velocity, in world axes. <mimic> joints follow their joint: q_m = k q_f + o,
// and the reduced equations are G^T M G nu' = G^T (tau - bias), G the map from the
// independent speeds to all of them.
#include <tinyxml2.h>

#include <Eigen/Dense>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace urdf_reference {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

inline Mat3 rpy(const Vec3& a) {
  return (Eigen::AngleAxisd(a.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(a.y(), Vec3::UnitY()) *
          Eigen::AngleAxisd(a.x(), Vec3::UnitX()))
      .toRotationMatrix();
}

inline Vec3 triple(const tinyxml2::XMLElement* e, const char* attribute, const Vec3& fallback) {
  if (!e || !e->Attribute(attribute)) return fallback;
  std::istringstream in(e->Attribute(attribute));
  Vec3 v;
  in >> v.x() >> v.y() >> v.z();
  return v;
}

struct Link {
  std::string name;
  double m = 0;
  Vec3 c = Vec3::Zero();     // mass centre, link frame
  Mat3 I = Mat3::Zero();     // about the mass centre, link frame
  int parent_joint = -1;
};

struct Joint {
  std::string name, type;
  int parent = -1, child = -1;
  Vec3 xyz = Vec3::Zero();
  Mat3 R = Mat3::Identity();
  Vec3 axis = Vec3::UnitX();
  double damping = 0;
  std::string mimic;
  double multiplier = 1, offset = 0;
  int dof = -1;  // first generalized speed (6 for floating, 1 for the others, none for fixed)
};

/// What the recursion needs of the state: each link's pose and motion in the world.
struct LinkState {
  Mat3 R = Mat3::Identity();
  Vec3 p = Vec3::Zero(), w = Vec3::Zero(), v = Vec3::Zero(), alpha = Vec3::Zero(), a = Vec3::Zero();
};

class Robot {
 public:
  explicit Robot(const std::string& path) {
    tinyxml2::XMLDocument doc;
    if (doc.LoadFile(path.c_str()) != tinyxml2::XML_SUCCESS) throw std::runtime_error("cannot read " + path);
    const auto* robot = doc.RootElement();
    std::map<std::string, int> index;
    for (auto* e = robot->FirstChildElement("link"); e; e = e->NextSiblingElement("link")) {
      Link l;
      l.name = e->Attribute("name");
      if (const auto* in = e->FirstChildElement("inertial")) {
        const auto* o = in->FirstChildElement("origin");
        l.c = triple(o, "xyz", Vec3::Zero());
        const Mat3 Ri = rpy(triple(o, "rpy", Vec3::Zero()));
        l.m = in->FirstChildElement("mass")->DoubleAttribute("value");
        const auto* i = in->FirstChildElement("inertia");
        Mat3 own;
        own << i->DoubleAttribute("ixx"), i->DoubleAttribute("ixy"), i->DoubleAttribute("ixz"), i->DoubleAttribute("ixy"),
            i->DoubleAttribute("iyy"), i->DoubleAttribute("iyz"), i->DoubleAttribute("ixz"), i->DoubleAttribute("iyz"),
            i->DoubleAttribute("izz");
        l.I = Ri * own * Ri.transpose();
      }
      index[l.name] = static_cast<int>(links.size());
      links.push_back(l);
    }
    for (auto* e = robot->FirstChildElement("joint"); e; e = e->NextSiblingElement("joint")) {
      Joint j;
      j.name = e->Attribute("name");
      j.type = e->Attribute("type");
      j.parent = index.at(e->FirstChildElement("parent")->Attribute("link"));
      j.child = index.at(e->FirstChildElement("child")->Attribute("link"));
      const auto* o = e->FirstChildElement("origin");
      j.xyz = triple(o, "xyz", Vec3::Zero());
      j.R = rpy(triple(o, "rpy", Vec3::Zero()));
      j.axis = triple(e->FirstChildElement("axis"), "xyz", Vec3::UnitX()).normalized();
      if (const auto* d = e->FirstChildElement("dynamics")) j.damping = d->DoubleAttribute("damping");
      if (const auto* m = e->FirstChildElement("mimic")) {
        j.mimic = m->Attribute("joint");
        j.multiplier = m->DoubleAttribute("multiplier", 1.0);
        j.offset = m->DoubleAttribute("offset", 0.0);
      }
      links[static_cast<std::size_t>(j.child)].parent_joint = static_cast<int>(joints.size());
      joints.push_back(j);
    }
    // Joints in an order where each comes after its parent link's joint.
    for (std::size_t l = 0; l < links.size(); ++l)
      if (links[l].parent_joint < 0) add_below(static_cast<int>(l));
    for (int k : order) {
      Joint& j = joints[static_cast<std::size_t>(k)];
      if (j.type == "fixed") continue;
      j.dof = dofs;
      dofs += j.type == "floating" ? 6 : 1;
    }
  }

  std::vector<Link> links;
  std::vector<Joint> joints;
  std::vector<int> order;  // joints, parents first
  int dofs = 0;

  const Joint& joint(const std::string& name) const {
    for (const auto& j : joints)
      if (j.name == name) return j;
    throw std::runtime_error("no joint " + name);
  }

  /// Joint forces (the base's moment about its origin and force, world axes, for a
  /// floating joint) that give the generalized accelerations `nudot` at q (positions of
  /// the one-coordinate joints, by dof; a floating joint's pose in base_R, base_p) and nu.
  Eigen::VectorXd inverse(const Eigen::VectorXd& q, const Mat3& base_R, const Vec3& base_p, const Eigen::VectorXd& nu,
                          const Eigen::VectorXd& nudot, const Vec3& g) const {
    std::vector<LinkState> s(links.size());
    for (int k : order) {
      const Joint& j = joints[static_cast<std::size_t>(k)];
      const LinkState& P = s[static_cast<std::size_t>(j.parent)];
      LinkState& C = s[static_cast<std::size_t>(j.child)];
      if (j.type == "floating") {
        C.R = base_R;
        C.p = base_p;
        C.w = nu.segment<3>(j.dof);
        C.v = nu.segment<3>(j.dof + 3);
        C.alpha = nudot.segment<3>(j.dof);
        C.a = nudot.segment<3>(j.dof + 3);
        continue;
      }
      const Mat3 Rj = P.R * j.R;
      const Vec3 n = Rj * j.axis;
      const double qj = j.dof >= 0 ? q[j.dof] : 0, qd = j.dof >= 0 ? nu[j.dof] : 0, qdd = j.dof >= 0 ? nudot[j.dof] : 0;
      C.p = P.p + P.R * j.xyz;
      C.R = Rj;
      C.w = P.w;
      C.alpha = P.alpha;
      if (j.type == "revolute" || j.type == "continuous") {
        C.R = Rj * Eigen::AngleAxisd(qj, j.axis).toRotationMatrix();
        C.w += n * qd;
        C.alpha += n * qdd + P.w.cross(n * qd);
      } else if (j.type == "prismatic") {
        C.p += n * qj;
      }
      const Vec3 r = C.p - P.p;
      C.v = P.v + P.w.cross(r);
      C.a = P.a + P.alpha.cross(r) + P.w.cross(P.w.cross(r));
      if (j.type == "prismatic") {
        C.v += n * qd;
        C.a += n * qdd + 2 * P.w.cross(n * qd);
      }
    }
    // Inwards: the force and moment (about the link's origin) its parent joint carries.
    std::vector<Vec3> f(links.size(), Vec3::Zero()), mo(links.size(), Vec3::Zero());
    Eigen::VectorXd tau = Eigen::VectorXd::Zero(dofs);
    for (auto it = order.rbegin(); it != order.rend(); ++it) {
      const Joint& j = joints[static_cast<std::size_t>(*it)];
      const std::size_t c = static_cast<std::size_t>(j.child);
      const Link& L = links[c];
      const LinkState& C = s[c];
      const Vec3 rc = C.R * L.c;
      const Vec3 ac = C.a + C.alpha.cross(rc) + C.w.cross(C.w.cross(rc));
      const Mat3 Iw = C.R * L.I * C.R.transpose();
      const Vec3 F = L.m * (ac - g);
      const Vec3 N = Iw * C.alpha + C.w.cross(Iw * C.w);
      f[c] += F;
      mo[c] += N + rc.cross(F);
      if (j.type == "floating") {
        tau.segment<3>(j.dof) = mo[c];
        tau.segment<3>(j.dof + 3) = f[c];
      } else if (j.dof >= 0) {
        const Vec3 n = s[static_cast<std::size_t>(j.parent)].R * j.R * j.axis;
        tau[j.dof] = j.type == "prismatic" ? n.dot(f[c]) : n.dot(mo[c]);
      }
      const std::size_t p = static_cast<std::size_t>(j.parent);
      f[p] += f[c];
      mo[p] += mo[c] + (C.p - s[p].p).cross(f[c]);
    }
    return tau;
  }

 private:
  void add_below(int link) {
    for (std::size_t k = 0; k < joints.size(); ++k)
      if (joints[k].parent == link) {
        order.push_back(static_cast<int>(k));
        add_below(joints[k].child);
      }
  }
};

}  // namespace urdf_reference
