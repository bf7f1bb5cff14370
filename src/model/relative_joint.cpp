// SPDX-License-Identifier: GPL-2.0-or-later
// Joints with a coordinate of their own (relative, or joint, coordinates, as in robotics):
//   joint elbow : revolute link1.D link2.P coordinate q2
// declares the relative angle q2 (and its rate) at the node where the joint is written and
// places the second body from the first:
//   revolute:   r_Q = r_P,                        theta_c = theta_p + q
//   prismatic:  r_Q = r_A + s n (n the unit axis), theta_c = theta_p + angle
// Each row is explicit in one coordinate of the second (child) body, with coefficient 1,
// so the position of every body of a tree of such joints is a closed-form function of the
// joint coordinates: `--state minimal` keeps the joint coordinates only, and the automatic
// independent set, which prefers the children's speeds as pivots, keeps the joint rates.
// The bodies stay in absolute coordinates (their own effective forces, the same library
// for every other joint), so closing a loop is one more ordinary joint.
#include <fmt/format.h>

#include "planar_library.hpp"

namespace mbsc::model {

bool PlanarLibrary::add_relative_rows(int owner, const Element& e, const std::string& name, const std::string& what,
                                      const Located& p1, const Located& p2, const GiNaC::ex& rel) {
  const bool revolute = e.kind == "revolute";
  const int parent = p1.node, child = p2.node;
  // The child: a body in absolute coordinates whose pose the joint gives.
  const LeafKind child_kind = child == kGround ? LeafKind::Node : m_.nodes[child].kind;
  if (child == kGround) {
    diags_.error(e.end2_pos, fmt::format("{}: the second end '{}' is on the ground, but a joint's coordinate places its "
                                         "second body; write the ground's end first",
                                         what, e.end2));
    return false;
  }
  if (!(child_kind == LeafKind::Rigid2d || (!revolute && child_kind == LeafKind::Particle2d))) {
    diags_.error(e.end2_pos,
                 fmt::format("{}: the second end '{}' is on '{}', a {} body; the body a {} joint's coordinate places must "
                             "be {}",
                             what, e.end2, m_.nodes[child].name, to_string(child_kind), e.kind,
                             revolute ? "a rigid2d body (absolute coordinates)"
                                      : "a rigid2d body (absolute coordinates) or a particle2d body"));
    return false;
  }
  // The parent: the frame the coordinate is measured in.
  if (parent != kGround && m_.nodes[parent].kind != LeafKind::Rigid2d) {
    diags_.error(e.end1_pos, fmt::format("{}: the first end '{}' is on '{}', a {} body; a joint's coordinate is measured "
                                         "from the ground or a rigid2d body (absolute coordinates)",
                                         what, e.end1, m_.nodes[parent].name, to_string(m_.nodes[parent].kind)));
    return false;
  }
  // One placement per body, and no loop of placements (a loop is closed by a joint
  // without a coordinate).
  if (const auto it = placed_.find(child); it != placed_.end()) {
    const SourcePos& first = it->second.pos;
    diags_.error(e.coordinate_pos,
                 fmt::format("{}: body '{}' is already placed by joint '{}' (at {}{}:{}); a body is the second end of at "
                             "most one joint with a coordinate (close a loop with a joint without one)",
                             what, m_.nodes[child].name, it->second.joint, first.file == e.pos.file ? "" : first.file + ":",
                             first.line, first.col));
    return false;
  }
  for (int b = parent; b != kGround;) {
    const auto it = placed_.find(b);
    if (it == placed_.end()) break;
    if (it->second.parent == child) {
      diags_.error(e.coordinate_pos,
                   fmt::format("{}: joints with coordinates would form a loop through '{}' and '{}'; close the loop with a "
                               "joint without a coordinate",
                               what, m_.nodes[child].name, m_.nodes[b].name));
      return false;
    }
    b = it->second.parent;
  }
  placed_[child] = Placement{parent, name, e.pos};

  const Node& c = m_.nodes[child];
  const GiNaC::ex q = m_.coords[static_cast<std::size_t>(e.coordinate)].sym;
  GiNaC::ex ox = 0, oy = 0;  // the point's offset from the first end along the joint
  if (!revolute) {
    // The slide is a length: the axis direction made a unit vector (body frame).
    int node = kGround;
    const Axis* a = element_of(owner, e.end1, axes_, node);
    if (!a) return false;  // reported by axis()
    const GiNaC::ex len = GiNaC::sqrt(a->dx * a->dx + a->dy * a->dy);
    const auto d = rotate(node, a->dx / len, a->dy / len);
    ox = q * d.first;
    oy = q * d.second;
  }
  add_constraint(owner, name + ".x", p2.x - p1.x - ox, e.pos, Constraint::Level::Position, c.coords[0]);
  add_constraint(owner, name + ".y", p2.y - p1.y - oy, e.pos, Constraint::Level::Position, c.coords[1]);
  if (child_kind == LeafKind::Rigid2d) {
    const GiNaC::ex turn = revolute ? q : rel;
    add_constraint(owner, name + ".angle", *angle(child) - *angle(parent) - turn, e.pos, Constraint::Level::Position,
                   c.coords[2]);
  }
  return true;
}

}  // namespace mbsc::model
