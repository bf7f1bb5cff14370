// SPDX-License-Identifier: GPL-2.0-or-later
// From URDF links and joints to mbsc bodies (docs/urdf.md, "From links to bodies").
//   * One tree: every link but the root is the child of exactly one joint, all reached
//     from the root; a second parent or a cycle is a loop, which URDF cannot describe
//     (it is an error; loops are closed in the written model instead).
//   * Links joined by fixed joints are one rigid body: the group's masses, mass centres
//     and inertia tensors combine (parallel axes) in the frame of its top link.
//   * Axes: mbsc's joint coordinates measure the child from the frame it shares with its
//     parent at q = 0, where URDF turns the child's frame by the joint's rpy. So each
//     body takes as its axes its top link's frame turned back to the world's directions
//     at the zero pose: W_child = W_parent R_P R_rpy (R_P the parent link's turn inside
//     its group), and every vector of the link is written as W v. The joint's axis is
//     then W_child a in both bodies, and R_child(q) = R_parent Rot(W_child a, q) is
//     URDF's R_parent R_rpy Rot(a, q) seen in the turned axes.
//   * A free body (the floating base, or a floating joint's child) keeps its link's
//     frame: its attitude is a coordinate.
#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "mbsc/diag/limits.hpp"
#include "mbsc/diag/name_suggestions.hpp"
#include "urdf_tree.hpp"

namespace mbsc::import {

namespace {

/// The parallel-axis term m (|d|^2 E - d d^T).
Mat3 steiner(double m, const Vec3& d) {
  Mat3 s{};
  const double dd = dot(d, d);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) s[i][j] = m * ((i == j ? dd : 0) - d[i] * d[j]);
  return s;
}

Mat3 turned(const Mat3& r, const Mat3& a) { return mul(r, mul(a, transpose(r))); }

Mat3 plus(const Mat3& a, const Mat3& b) {
  Mat3 c{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) c[i][j] = a[i][j] + b[i][j];
  return c;
}

bool moves(const std::string& type) { return type != "fixed"; }

}  // namespace

std::optional<RobotTree> build_robot_tree(const UrdfDocument& doc, bool floating_base, Diagnostics& diags) {
  // Names: links and joints each once; joints name known, distinct links.
  std::map<std::string, std::size_t> link_index, joint_index;
  std::vector<std::string> link_names;
  for (std::size_t i = 0; i < doc.links.size(); ++i) {
    const auto& l = doc.links[i];
    if (!link_index.emplace(l.name, i).second)
      diags.error(l.pos, fmt::format("link '{}' is defined twice (first at {})", printable(l.name),
                                     to_string(doc.links[link_index[l.name]].pos)));
    link_names.push_back(l.name);
  }
  for (std::size_t i = 0; i < doc.joints.size(); ++i) {
    const auto& j = doc.joints[i];
    if (!joint_index.emplace(j.name, i).second)
      diags.error(j.pos, fmt::format("joint '{}' is defined twice (first at {})", printable(j.name),
                                     to_string(doc.joints[joint_index[j.name]].pos)));
    for (const auto& [end, pos] : {std::pair{&j.parent, j.parent_pos}, std::pair{&j.child, j.child_pos}})
      if (!end->empty() && !link_index.count(*end))
        diags.error(pos, fmt::format("joint '{}': unknown link '{}'{}", printable(j.name), printable(*end),
                                     did_you_mean(*end, link_names)));
    if (!j.parent.empty() && j.parent == j.child)
      diags.error(j.child_pos, fmt::format("joint '{}' joins link '{}' to itself", printable(j.name), printable(j.child)));
  }
  if (diags.has_errors()) return std::nullopt;
  if (doc.links.empty()) {
    diags.error(doc.robot_pos, fmt::format("robot '{}' has no links", doc.robot_name));
    return std::nullopt;
  }

  // One parent joint per link; one root; every link reached from it.
  std::vector<std::optional<std::size_t>> parent_joint(doc.links.size());
  std::vector<std::vector<std::size_t>> child_joints(doc.links.size());
  for (std::size_t i = 0; i < doc.joints.size(); ++i) {
    const auto& j = doc.joints[i];
    const std::size_t c = link_index[j.child];
    if (parent_joint[c]) {
      diags.error(j.child_pos, fmt::format("joint '{}': link '{}' is already the child of joint '{}'; a URDF is a tree, and "
                                           "a second parent would close a loop (import the tree and close the loop in the "
                                           "written model with a joint without a coordinate)",
                                           j.name, j.child, doc.joints[*parent_joint[c]].name));
      continue;
    }
    parent_joint[c] = i;
    child_joints[link_index[j.parent]].push_back(i);
  }
  if (diags.has_errors()) return std::nullopt;
  std::vector<std::size_t> roots;
  for (std::size_t i = 0; i < doc.links.size(); ++i)
    if (!parent_joint[i]) roots.push_back(i);
  if (roots.size() != 1) {
    if (roots.empty())
      diags.error(doc.joints.front().pos, "every link is the child of a joint, so the joints form a loop and there is no "
                                          "root link; a URDF is a tree with one root");
    else
      diags.error(doc.links[roots[1]].pos,
                  fmt::format("links '{}' and '{}' are both roots (no joint has them as its child); a URDF is one tree: "
                              "join them with a joint",
                              doc.links[roots[0]].name, doc.links[roots[1]].name));
    return std::nullopt;
  }

  RobotTree tree;
  std::vector<std::size_t> group(doc.links.size());
  std::vector<Pose> in_group(doc.links.size());  // each link's frame in its group's top link frame
  RobotBody root;
  root.link = doc.links[roots[0]].name;
  root.pos = doc.links[roots[0]].pos;
  root.ground = !floating_base;
  root.free = floating_base;
  tree.bodies.push_back(root);
  group[roots[0]] = 0;
  std::map<std::size_t, std::size_t> moving_of;  // URDF joint -> RobotJoint
  std::vector<std::size_t> queue = {roots[0]};
  std::vector<bool> reached(doc.links.size(), false);
  reached[roots[0]] = true;
  for (std::size_t next = 0; next < queue.size(); ++next) {
    const std::size_t p = queue[next];
    for (const std::size_t ji : child_joints[p]) {
      const UrdfJoint& j = doc.joints[ji];
      const std::size_t c = link_index[j.child];
      reached[c] = true;
      queue.push_back(c);
      const std::size_t pg = group[p];
      if (!moves(j.type)) {
        group[c] = pg;
        in_group[c] = compose(in_group[p], j.origin);
        tree.bodies[pg].welded.push_back(ji);
        continue;
      }
      RobotBody body;
      body.link = j.child;
      body.pos = doc.links[c].pos;
      const RobotBody& parent = tree.bodies[pg];
      RobotJoint rj;
      rj.urdf = ji;
      rj.parent = pg;
      rj.child = tree.bodies.size();
      const Pose at = compose(in_group[p], j.origin);  // the joint frame in the parent group's top link frame
      rj.point = mul(parent.axes, at.position);
      if (j.type == "floating") {
        if (!parent.ground) {
          diags.error(j.type_pos, fmt::format("joint '{}': a floating joint must hang from the fixed root (here its parent "
                                              "'{}' moves); mbsc places a free body in the world, not relative to another",
                                              j.name, j.parent));
          return std::nullopt;
        }
        body.free = true;
        body.start = at;  // the ground group's top link is the world
      } else {
        body.axes = mul(parent.axes, at.rotation);
        body.rpy_path = parent.rpy_path;
        if (j.rpy != Vec3{0, 0, 0}) body.rpy_path.push_back(j.name);
        const double n = std::sqrt(dot(j.axis, j.axis));
        if (!(std::abs(n - 1) <= 1e-6)) {
          diags.error(j.axis_pos, fmt::format("joint '{}': the axis ({} {} {}) is not a unit vector (its length is {:.10g}); "
                                              "write its direction with length 1 to 6 digits or more",
                                              j.name, j.axis[0], j.axis[1], j.axis[2], n));
          return std::nullopt;
        }
        rj.axis = mul(body.axes, scale(1 / n, j.axis));
        rj.axis = scale(1 / std::sqrt(dot(rj.axis, rj.axis)), rj.axis);  // unit to rounding after the turns
      }
      group[c] = tree.bodies.size();
      in_group[c] = Pose{};
      moving_of[ji] = tree.joints.size();
      tree.bodies.push_back(body);
      tree.joints.push_back(rj);
    }
  }
  for (std::size_t i = 0; i < doc.links.size(); ++i)
    if (!reached[i]) {
      diags.error(doc.joints[*parent_joint[i]].pos,
                  fmt::format("joint '{}' is on a loop of joints that does not reach the root link '{}'; a URDF is a tree",
                              doc.joints[*parent_joint[i]].name, root.link));
      return std::nullopt;
    }

  for (auto& body : tree.bodies) body.name = body.link;
  if (floating_base && !doc.links[roots[0]].inertial)
    for (const std::size_t l : queue)
      if (group[l] == 0 && doc.links[l].inertial) {
        tree.bodies[0].name = doc.links[l].name;
        break;
      }

  // Mass, mass centre and inertia of each group, in its top link's frame, then turned.
  std::vector<std::vector<std::size_t>> members(tree.bodies.size());
  for (std::size_t i = 0; i < doc.links.size(); ++i) members[group[i]].push_back(i);
  for (std::size_t b = 0; b < tree.bodies.size(); ++b) {
    RobotBody& body = tree.bodies[b];
    // The members with an inertial, each with its mass centre in the top link's frame.
    std::vector<std::pair<std::size_t, Vec3>> massive;
    double m = 0;
    Vec3 first{0, 0, 0};
    for (const std::size_t i : members[b])
      if (const auto& in = doc.links[i].inertial) {
        massive.emplace_back(i, add(in_group[i].position, mul(in_group[i].rotation, in->origin.position)));
        m += in->mass;
        first = add(first, scale(in->mass, massive.back().second));
      }
    body.has_inertial = !massive.empty();
    // One link's mass centre as the file has it (m c / m need not give c back).
    const Vec3 com = massive.size() == 1 ? massive[0].second : m > 0 ? scale(1 / m, first) : Vec3{0, 0, 0};
    Mat3 inertia{};
    for (const auto& [i, c] : massive) {
      const UrdfInertial& in = *doc.links[i].inertial;
      const Mat3 own = {{{in.ixx, in.ixy, in.ixz}, {in.ixy, in.iyy, in.iyz}, {in.ixz, in.iyz, in.izz}}};
      inertia = plus(inertia, plus(turned(mul(in_group[i].rotation, in.origin.rotation), own), steiner(in.mass, sub(c, com))));
    }
    body.mass = m;
    body.com = mul(body.axes, com);
    body.inertia = turned(body.axes, inertia);
    if (body.ground) continue;
    if (!body.has_inertial) {
      diags.error(body.pos, fmt::format("link '{}' moves ({}) but has no <inertial>, nor does a link welded to it; give it "
                                        "its mass and inertia (mass 0 and a zero tensor for a massless link)",
                                        body.link, body.free ? "it is a free body" : "joint '" + doc.joints[tree.joints[b - 1].urdf].name + "'"));
      continue;
    }
    const Mat3& I = body.inertia;
    const double m1 = I[0][0], m2 = I[0][0] * I[1][1] - I[0][1] * I[1][0];
    const double m3 = I[0][0] * (I[1][1] * I[2][2] - I[1][2] * I[2][1]) - I[0][1] * (I[1][0] * I[2][2] - I[1][2] * I[2][0]) +
                      I[0][2] * (I[1][0] * I[2][1] - I[1][1] * I[2][0]);
    bool zero = !body.free;  // a point mass, or with mass 0 a massless link, on a joint
    for (const auto& row : I)
      for (const double v : row) zero = zero && v == 0;
    if (body.free && !(m > 0)) {
      diags.error(body.pos, fmt::format("link '{}' is a free body (the floating base, or a floating joint's child) with "
                                        "mass {}; a free body needs a positive mass and inertia",
                                        printable(body.link), m));
      continue;
    }
    if (!zero && !(m1 > 0 && m2 > 0 && m3 > 0))
      diags.error(doc.links[link_index[body.link]].inertial ? doc.links[link_index[body.link]].inertial->pos : body.pos,
                  fmt::format("link '{}'{}: the inertia tensor is not positive definite (leading minors {:.6g}, {:.6g}, "
                              "{:.6g}); mbsc needs a positive definite tensor, or a zero one (a point mass, or with mass 0 a "
                              "massless link)",
                              body.link, body.welded.empty() ? "" : " with the links welded to it", m1, m2, m3));
  }

  // What the model text will hold stays inside the range of the language's numbers:
  // inputs within it can still combine beyond it (parallel axes of far, heavy links).
  const auto in_range = [](double x) { return std::isfinite(x) && std::abs(x) <= limits::kMaxValue; };
  for (const RobotBody& body : tree.bodies) {
    bool ok = in_range(body.mass);
    for (int i = 0; i < 3; ++i) {
      ok = ok && in_range(body.com[i]) && in_range(body.start.position[i]);
      for (int k = 0; k < 3; ++k) ok = ok && in_range(body.inertia[i][k]);
    }
    if (!ok) {
      diags.error(body.pos, fmt::format("link '{}': its mass, mass centre or inertia{} comes to a value beyond 1e30 in "
                                        "magnitude, outside the range of mbsc's numbers",
                                        printable(body.link), body.welded.empty() ? "" : " (with the links welded to it)"));
      return std::nullopt;
    }
  }
  for (const RobotJoint& rj : tree.joints)
    for (int i = 0; i < 3; ++i)
      if (!in_range(rj.point[i])) {
        diags.error(doc.joints[rj.urdf].pos, fmt::format("joint '{}': its origin comes to a value beyond 1e30 in magnitude "
                                                         "from the link it hangs from",
                                                         printable(doc.joints[rj.urdf].name)));
        return std::nullopt;
      }

  // Mimics: on a joint with one coordinate, following another such joint that does not
  // itself follow one (a chain would be rows on rows; URDF tools read one level).
  std::vector<std::string> names;
  for (const auto& k : doc.joints) names.push_back(k.name);
  for (std::size_t ji = 0; ji < doc.joints.size(); ++ji) {
    const UrdfJoint& j = doc.joints[ji];
    if (!j.mimic) continue;
    const auto it = joint_index.find(j.mimic->joint);
    if (it == joint_index.end()) {
      diags.error(j.mimic->joint_pos, fmt::format("joint '{}': <mimic> follows unknown joint '{}'{}", j.name,
                                                  printable(j.mimic->joint), did_you_mean(j.mimic->joint, names)));
      continue;
    }
    const UrdfJoint& followed = doc.joints[it->second];
    if (!has_one_coordinate(j.type) || !has_one_coordinate(followed.type) || it->second == ji) {
      diags.error(j.mimic->pos, fmt::format("joint '{}' ({}): <mimic> ties the coordinates of two distinct revolute, "
                                            "continuous or prismatic joints; '{}' is {}",
                                            j.name, j.type, followed.name, followed.type));
      continue;
    }
    if (followed.mimic && followed.mimic->joint == j.name) {
      diags.error(j.mimic->joint_pos, fmt::format("joints '{}' and '{}' mimic each other; one of them must move on its "
                                                  "own (drop its <mimic>)",
                                                  printable(j.name), printable(followed.name)));
      continue;
    }
    if (followed.mimic) {
      diags.error(j.mimic->joint_pos, fmt::format("joint '{}': <mimic> follows joint '{}', which itself follows '{}'; "
                                                  "follow '{}' directly (with the multipliers and offsets combined)",
                                                  printable(j.name), printable(followed.name),
                                                  printable(followed.mimic->joint), printable(followed.mimic->joint)));
      continue;
    }
    if (!std::isfinite(j.mimic->multiplier) || !std::isfinite(j.mimic->offset)) continue;  // reported by the reader
    tree.joints[moving_of.at(ji)].mimics = moving_of.at(it->second);
  }
  if (diags.has_errors()) return std::nullopt;
  return tree;
}

}  // namespace mbsc::import
