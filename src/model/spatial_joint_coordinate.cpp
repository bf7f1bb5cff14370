// SPDX-License-Identifier: GPL-2.0-or-later
// Joint coordinates in space: a revolute joint with a coordinate of its own,
//   joint steering : revolute rear_frame.steer front_frame.steer coordinate delta
// places its second body from the first, as the planar `coordinate` option does
// (relative_joint.cpp), so that a tree of such joints is written in joint angles:
//   * the child has no attitude coordinates: its attitude is R = R_parent R_joint(q), the
//     parent's turned by q about the joint axis n (a unit vector in the parent's body
//     frame; the two bodies' frames coincide at q = 0, so n is the child's axis too);
//   * its mass centre x, y, z stays a coordinate, given explicitly by the joint point:
//       NAME.x, NAME.y, NAME.z   P_child - P_parent = 0          (position, explicit in x, y, z)
//   * its body-frame angular speeds are given explicitly by the parent's and q':
//       NAME.wx, NAME.wy, NAME.wz  w - R_joint(q)^T w_parent - n q' = 0   (velocity)
//     (w_parent in the parent's body frame; R_joint^T w = w turned by -q). These are the
//     time derivative of R^T R' = [w]x for R = R_parent R_joint, so they are integrable:
//     the child's attitude follows from q, no drift.
// Each row has coefficient 1 on one of the child's variables, so the complement pivots
// on them with no numeric solve, and `--state minimal` keeps the joint angle and drops
// x, y, z. The revolute's two alignment rows are implied and not written.
#include <cmath>

#include <fmt/format.h>

#include "mbsc/model/rigid3d.hpp"
#include "spatial_library.hpp"

namespace mbsc::model {

namespace {
using Vec = SpatialLibrary::Vec;

/// e expanded with sin(a)^2 written as 1 - cos(a)^2.
GiNaC::ex tidy_expand(const GiNaC::ex& e) {
  const GiNaC::wildcard a(0);
  return GiNaC::expand(GiNaC::expand(e).subs(GiNaC::pow(GiNaC::sin(a), 2) == 1 - GiNaC::pow(GiNaC::cos(a), 2),
                                             GiNaC::subs_options::algebraic));
}

/// n . n tidied: 1 for the unit axes users write, e.g. (sin(lambda), 0, cos(lambda)).
GiNaC::ex tidy_square_length(const Vec& n) { return tidy_expand(rigid3d::dot(n, n)); }
}  // namespace

std::optional<std::pair<int, Vec>> SpatialLibrary::axis_direction(int owner, const std::string& path) const {
  const auto dot = path.rfind('.');
  if (dot == std::string::npos) return std::nullopt;
  const auto b = body(owner, path.substr(0, dot));
  if (!b) return std::nullopt;
  const std::string name = path.substr(dot + 1);
  const std::map<std::string, Vec>* table = nullptr;
  if (*b == PlanarLibrary::kGround) table = &ground_axes_;
  else if (m_.nodes[*b].kind == LeafKind::Rigid3d) table = &m_.nodes[*b].rigid3d.axes;
  if (!table) return std::nullopt;
  const auto it = table->find(name);
  if (it == table->end() || it->second.size() != 6) return std::nullopt;
  return std::make_pair(*b, Vec{it->second[3], it->second[4], it->second[5]});
}

SpatialLibrary::Placed SpatialLibrary::place(int owner, const PlanarLibrary::Element& e, int child) {
  const std::string what = fmt::format("joint '{}'", e.name);
  const auto pa = axis_direction(owner, e.end1), ca = axis_direction(owner, e.end2);
  if (!pa || !ca || ca->first != child) return Placed::Failed;  // pass B's end() says why
  const int parent = pa->first;
  if (parent != PlanarLibrary::kGround) {
    const Rigid3dData& p = m_.nodes[parent].rigid3d;
    if (p.placed() && p.rotation.empty()) return Placed::Later;
    if (p.rotation.empty()) return Placed::Failed;  // its variables failed (reported)
  }
  // The axis as a unit vector (exactly, when its length is 1 symbolically).
  const Vec& d = pa->second;
  const GiNaC::ex len2 = tidy_square_length(d);
  Vec n = d;
  if (!(len2 - 1).is_zero())
    for (auto& x : n) x = x / GiNaC::sqrt(len2);
  // The child's axis must be the parent's in body coordinates: same direction and sense,
  // for every parameter value. The same expressions pass at once; otherwise their cross
  // product must vanish symbolically (sin^2 as 1 - cos^2) and their dot product be
  // positive at the defaults. A direction that cannot be evaluated at the defaults (it
  // reads an input or a component's parameter) must be written the same on both ends.
  const Vec& c = ca->second;
  bool same = true;
  for (std::size_t k = 0; k < 3; ++k) same = same && GiNaC::expand(d[k] - c[k]).is_zero();
  if (!same) {
    const Vec cr = rigid3d::cross(d, c);
    bool cross_zero = true;
    for (const auto& x : cr) cross_zero = cross_zero && tidy_expand(x).is_zero();
    const double dc = at_defaults(rigid3d::dot(d, c)), dd = at_defaults(rigid3d::dot(d, d)),
                 cc = at_defaults(rigid3d::dot(c, c));
    if (std::isnan(dc) || std::isnan(dd) || std::isnan(cc)) {
      diags_.error(e.end2_pos, fmt::format("{}: the directions of the axes '{}' and '{}' cannot be compared at the parameter "
                                           "defaults (they read an input or a component's parameter); write the same "
                                           "direction for both",
                                           what, e.end1, e.end2));
      return Placed::Failed;
    }
    if (!(dd > 0) || !(cc > 0)) return Placed::Failed;  // a zero direction: reported where the axis is declared
    if (!cross_zero || !(dc > 0)) {
      diags_.error(e.end2_pos, fmt::format("{}: the axes '{}' and '{}' point differently in their bodies' coordinates; a "
                                           "joint with a coordinate turns '{}' from the attitude of '{}' about the axis "
                                           "(the two bodies' frames coincide at {} = 0), so give both axes the same "
                                           "direction",
                                           what, e.end1, e.end2, m_.nodes[child].name,
                                           parent == PlanarLibrary::kGround ? std::string("ground") : m_.nodes[parent].name,
                                           m_.coords[static_cast<std::size_t>(e.coordinate)].name));
      return Placed::Failed;
    }
  }
  Rigid3dData& data = m_.nodes[child].rigid3d;
  data.joint_parent = parent;
  data.joint_axis = n;
  data.joint_angle = m_.coords[static_cast<std::size_t>(e.coordinate)].sym;
  data.joint_rate = m_.speeds[static_cast<std::size_t>(e.coordinate_speed)].sym;
  const Vec turn = rigid3d::rotation_about(n, data.joint_angle);
  data.rotation = parent == PlanarLibrary::kGround ? turn : rigid3d::mat_mat(m_.nodes[parent].rigid3d.rotation, turn);
  if (names_rotation(parent)) name_rotation(child);
  return Placed::Done;
}

bool SpatialLibrary::names_rotation(int parent) const {
  // The rule of docs/formulation.md, "Named body rotations": a body placed under a body
  // with an attitude of its own (a free base: its rotation is already a full matrix of
  // attitude coordinates) is always named, and so is every placed body of a model with
  // more than kGroundJointsWritten of them (the tree recursion reads each body's rows in
  // its parent's speeds alone; a written-out rotation carries the joint rates of every
  // joint above it). In a small model the first kGroundJointsWritten bodies below the
  // ground keep their rotations as written-out products of joint rotations: the exact
  // axes' zeros and ones cancel there, and naming them costs operations (202 -> 264 for
  // two links).
  if (placements_ > kGroundJointsWritten) return true;
  int depth = 1;
  int p = parent;
  while (p != PlanarLibrary::kGround && m_.nodes[static_cast<std::size_t>(p)].rigid3d.placed()) {
    ++depth;
    p = m_.nodes[static_cast<std::size_t>(p)].rigid3d.joint_parent;
  }
  return p != PlanarLibrary::kGround || depth > kGroundJointsWritten;
}

void SpatialLibrary::name_rotation(int child) {
  // R = R_parent Q(q) as 9 names (R_parent itself names when the parent is named too),
  // each with its time derivative R' = R [w]x, w the child's body-frame
  // angular speeds (the joint's velocity rows make them the parent's turned back by q
  // plus n q'). Constant entries (a first joint on the ground) stay numbers.
  Node& node = m_.nodes[static_cast<std::size_t>(child)];
  Rigid3dData& data = node.rigid3d;
  Vec named(9);
  std::string base = node.name;
  for (auto& ch : base)
    if (ch == '.') ch = '_';
  std::vector<std::size_t> fresh;
  for (std::size_t k = 0; k < 9; ++k) {
    const GiNaC::ex v = GiNaC::expand(data.rotation[k]);
    if (GiNaC::is_a<GiNaC::numeric>(v)) {
      named[k] = v;
      continue;
    }
    const GiNaC::symbol s(fmt::format("R_{}_{}{}", base, k / 3, k % 3));
    named[k] = s;
    m_.kinematic_names.push_back({s, v, 0});
    fresh.push_back(m_.kinematic_names.size() - 1);
  }
  // Column j of R [w]x is R (w x e_j).
  const Vec w = rigid3d::angular_speeds(m_, node);
  Vec rate(9, GiNaC::ex(0));
  for (int j = 0; j < 3; ++j) {
    Vec e(3, GiNaC::ex(0));
    e[static_cast<std::size_t>(j)] = 1;
    const Vec col = rigid3d::mat_vec(named, rigid3d::cross(w, e));
    for (int i = 0; i < 3; ++i) rate[static_cast<std::size_t>(3 * i + j)] = col[static_cast<std::size_t>(i)];
  }
  std::size_t f = 0;
  for (std::size_t k = 0; k < 9; ++k)
    if (!GiNaC::is_a<GiNaC::numeric>(named[k])) m_.kinematic_names[fresh[f++]].rate = rate[k];
  data.rotation = named;
  data.named_rotation = true;
}

void SpatialLibrary::add_placement(int owner, const PlanarLibrary::Element& e, const std::string& name,
                                   const std::string& what) {
  const auto a = end(owner, e.end1, true, e.end1_pos, what, "joint");
  const auto b = end(owner, e.end2, true, e.end2_pos, what, "joint");
  if (!a || !b) return;
  if (b->node == PlanarLibrary::kGround) {
    diags_.error(e.end2_pos, fmt::format("{}: the second end '{}' is on the ground, but a joint's coordinate places its "
                                         "second body; write the ground's end first",
                                         what, e.end2));
    return;
  }
  if (a->node == b->node) {
    diags_.error(e.end2_pos, fmt::format("{} connects '{}' to itself", what, m_.label(a->node)));
    return;
  }
  const Node& child = m_.nodes[b->node];
  const Rigid3dData& data = child.rigid3d;
  if (data.placed() && data.joint_name != e.name) return;  // placed by another joint (reported)
  if (!data.placed()) {
    diags_.error(e.end2_pos, fmt::format("{}: body '{}' cannot be placed by this joint's coordinate (the joint must be "
                                         "written in a subsystem that encloses '{}', and name it by its path from there)",
                                         what, child.name, child.name));
    return;
  }
  if (data.rotation.empty()) {  // its placement failed (reported; the guard is for a path that would not say why)
    if (!diags_.has_errors())
      diags_.error(e.pos, fmt::format("{}: body '{}' could not be placed by this joint", what, child.name));
    return;
  }
  if (data.joint_parent != a->node) return;  // (cannot happen: both ends resolved alike)
  // The joint point: the child's mass centre follows from it (explicit in x, y, z).
  const char* const xyz[] = {"x", "y", "z"};
  for (std::size_t k = 0; k < 3; ++k)
    row(owner, name + "." + xyz[k], b->p[k] - a->p[k], e.pos, Constraint::Level::Position, child.coords[k]);
  // The child's body-frame angular velocity: the parent's turned back by q, plus n q'.
  const Vec wp = rigid3d::rotate_back_about(data.joint_axis, data.joint_angle,
                                            rigid3d::parent_angular_velocity_in_parent_frame(m_, child));
  const Vec w = rigid3d::angular_speeds(m_, child);
  const char* const names[] = {"wx", "wy", "wz"};
  for (std::size_t k = 0; k < 3; ++k)
    row(owner, name + "." + names[k], w[k] - wp[k] - data.joint_axis[k] * data.joint_rate, e.pos,
        Constraint::Level::Velocity);
  if (!e.option.empty()) {
    const std::string& prefix = m_.nodes[static_cast<std::size_t>(owner)].name;
    add_actuators(e, what, prefix.empty() ? name : prefix + "." + name, *a, *b);
  }
}

}  // namespace mbsc::model
