// SPDX-License-Identifier: GPL-2.0-or-later
// rigid3d bodies: their variables and attitude (a unit quaternion or Euler angles, with
// the kinematic equations of their rates), bodies placed by joints with a coordinate
// (parents before children), and what only a spatial body has: points and axes of three
// components, the inertia tensor, torques.
#include "build_internal.hpp"

#include <fmt/format.h>

#include <exception>

#include "mbsc/model/rigid3d.hpp"

namespace mbsc::model::build_detail {

/// A rigid3d leaf's variables (model.hpp Rigid3dData): x, y, z and the attitude
/// coordinates, u, v, w and wx, wy, wz; the attitude's rates are the kinematic
/// equations in the angular speeds (model/rigid3d.hpp), its rotation matrix kept for
/// forces, energy and joints. `attitude` chooses; the default is a unit quaternion with
/// body-frame angular speeds.
void Builder::declare_rigid3d(int id, const std::string& prefix, const SourcePos& pos,
                              const std::vector<ast::StatementPtr>& body) {
  Rigid3dData data;
  data.sequence = "quaternion";
  const Statement* placing = placing_joint(id, prefix);
  const Statement* given = nullptr;
  for (const auto& s : body) {
    if (s->kind != Kind::Attitude) continue;
    if (placing) {
      diags_.error(s->pos, fmt::format("body '{}' is placed by joint '{}' with coordinate '{}' (at {}): its attitude is "
                                       "its parent's turned by the joint, so it takes no 'attitude' statement",
                                       prefix, placing->name, placing->joint_coordinates.front().text,
                                       position_text(placing->pos, s->pos)));
      return;
    }
    if (given) {
      diags_.error(s->pos, fmt::format("attitude of body '{}' is given twice (first at {})", prefix,
                                       position_text(given->pos, s->pos)));
      continue;
    }
    given = s.get();
    if (s->name == "euler") {
      if (!rigid3d::valid_sequence(s->path.text)) {
        diags_.error(s->path.pos, fmt::format("'{}' is not an Euler sequence (body '{}'): write three axes of x, y, z "
                                              "with no axis twice in a row, e.g. zyx, zxz, xyz",
                                              s->path.text, prefix));
        return;
      }
      data.sequence = s->path.text;
    } else if (s->name != "quaternion") {
      diags_.error(s->name_pos, fmt::format("unknown attitude '{}' of body '{}' (quaternion or euler SEQUENCE)", s->name,
                                            prefix));
      return;
    }
    data.space_frame = s->option2.text == "space";
  }
  if (placing) {
    data.sequence = "joint";
    data.joint_name = placing->name;
  }
  const bool quaternion = data.sequence == "quaternion";
  const char* const position[] = {"x", "y", "z"};
  const char* const velocity[] = {"u", "v", "w"};
  std::vector<int> q, u;
  for (int i = 0; i < 3; ++i) q.push_back(add_variable(id, join(prefix, position[i]), pos, true, true));
  const std::vector<const char*> attitude = placing      ? std::vector<const char*>{}
                                            : quaternion ? std::vector<const char*>{"e0", "e1", "e2", "e3"}
                                                         : std::vector<const char*>{"phi", "theta", "psi"};
  for (const char* a : attitude) q.push_back(add_variable(id, join(prefix, a), pos, true, true));
  for (int i = 0; i < 3; ++i) u.push_back(add_variable(id, join(prefix, velocity[i]), pos, false, true));
  for (const char* w : {"wx", "wy", "wz"}) u.push_back(add_variable(id, join(prefix, w), pos, false, true));
  for (int i : q)
    if (i < 0) return;  // a name declared twice (reported)
  for (int i : u)
    if (i < 0) return;
  rigid3d::Vec a, w;
  for (std::size_t k = 3; k < q.size(); ++k) a.push_back(m_.coords[static_cast<std::size_t>(q[k])].sym);
  for (int k = 3; k < 6; ++k) w.push_back(m_.speeds[static_cast<std::size_t>(u[k])].sym);
  for (int k = 0; k < 3; ++k) builtin_rates_[q[k]] = m_.speeds[static_cast<std::size_t>(u[k])].sym;
  if (placing) {  // the rotation is set once the parent's is known (place_joint_bodies)
    m_.nodes[id].rigid3d = data;
    return;
  }
  const rigid3d::Vec rates =
      quaternion ? rigid3d::quaternion_rates(a, w, data.space_frame) : rigid3d::euler_rates(data.sequence, a, w, data.space_frame);
  for (std::size_t k = 0; k < rates.size(); ++k) builtin_rates_[q[3 + k]] = rates[k];
  data.rotation = quaternion ? rigid3d::quaternion_rotation(a) : rigid3d::euler_rotation(data.sequence, a);
  m_.nodes[id].rigid3d = data;
}

/// The joint with a coordinate that places rigid3d body `prefix`, if any: a revolute
/// joint written in an enclosing subsystem (or the top level) whose second end is one
/// of this body's axes, its path resolved as body() resolves it (inner scopes first).
/// Every such joint is recorded (placements_); the first is returned.
const Statement* Builder::placing_joint(int id, const std::string& prefix) {
  const Statement* first = nullptr;
  for (std::size_t k = scopes_.size(); k-- > 0;) {
    for (const auto& s : *scopes_[k].second) {
      if (s->kind != Kind::Joint || s->joint_coordinates.empty() || !SpatialLibrary::places(s->kind_name) ||
          s->paths.size() < 2)
        continue;
      const std::string& end = s->paths[1].text;
      const auto dot = end.rfind('.');
      if (dot == std::string::npos) continue;
      const std::string path = end.substr(0, dot);
      for (std::size_t j = k + 1; j-- > 0;) {
        if (join(scopes_[j].first, path) != prefix) continue;
        placements_.push_back({id, s.get(), scopes_[k].first});
        if (!first) first = s.get();
        break;
      }
    }
  }
  return first;
}

/// Points, axes and com of a rigid3d body (pass B's statements, read early in models
/// with placed bodies: the joints' axes give the placed bodies' attitudes).
void Builder::fill_rigid3d_geometry(int id) {
  for (const auto& sp : pending_[static_cast<std::size_t>(id)].body)
    if (sp->kind == Kind::Point || sp->kind == Kind::Com || sp->kind == Kind::Axis) {
      element_ = element_of(*sp, id);
      fill_geometry(id, *sp);
    }
  element_.clear();
  geometry_done_.insert(id);
}

/// Every placement, parents before their children; a body placed twice, or placements
/// in a loop, are errors.
void Builder::place_joint_bodies() {
  std::map<int, const Placement*> by_child;
  for (const auto& p : placements_) {
    const auto [it, fresh] = by_child.emplace(p.child, &p);
    if (fresh) continue;
    const Statement* first = it->second->joint;
    diags_.error(p.joint->pos, fmt::format("joint '{}': body '{}' is already placed by joint '{}' (at {}); a body is the "
                                           "second end of at most one joint with a coordinate (close a loop with a "
                                           "joint without one)",
                                           p.joint->name, m_.nodes[p.child].name, first->name,
                                           position_text(first->pos, p.joint->pos)));
  }
  std::vector<const Placement*> todo;
  for (const auto& [child, p] : by_child) todo.push_back(p);
  // The naming rule counts turns (a revolute joint's rotation is one, a spherical joint's
  // three): what a written-out rotation's size grows with.
  int turns = 0;
  for (const Placement* p : todo) turns += SpatialLibrary::turn_count(p->joint->kind_name);
  spatial_.expect_turns(turns);
  bool failed = false;
  while (!todo.empty()) {
    std::vector<const Placement*> later;
    for (const Placement* p : todo) {
      // The node the joint is written in: the one of that name holding the statement
      // (every instance of a component holds the same statements).
      int owner = -1;
      for (std::size_t n = 0; n < pending_.size() && owner < 0; ++n) {
        if (m_.nodes[n].name != p->owner) continue;
        for (const auto& sp : pending_[n].body)
          if (sp.get() == p->joint) owner = static_cast<int>(n);
      }
      const auto jv = joint_variables_.find({owner, p->joint});
      if (owner < 0 || jv == joint_variables_.end()) {  // its coordinate failed (reported)
        failed = true;
        continue;
      }
      const auto r = spatial_.place(owner, placement_element(*p->joint, jv->second), p->child);
      if (r == SpatialLibrary::Placed::Later) later.push_back(p);
      failed = failed || r == SpatialLibrary::Placed::Failed;
    }
    if (later.size() == todo.size()) {
      // Nothing placed in this round: a loop, unless a placement failed (reported),
      // which leaves the bodies below it waiting.
      if (!failed)
        for (const Placement* p : later)
          diags_.error(p->joint->pos, fmt::format("joint '{}': joints with coordinates would form a loop through '{}'; "
                                                  "close the loop with a joint without a coordinate",
                                                  p->joint->name, m_.nodes[p->child].name));
      break;
    }
    todo = later;
  }
}

PlanarLibrary::Element Builder::placement_element(const Statement& s, const JointVariables& variables) const {
  PlanarLibrary::Element e;
  e.name = s.name;
  e.kind = s.kind_name;
  e.pos = s.pos;
  e.kind_pos = s.kind_pos;
  e.end1 = s.paths[0].text;
  e.end1_pos = s.paths[0].pos;
  e.end2 = s.paths[1].text;
  e.end2_pos = s.paths[1].pos;
  fill_joint_coordinates(e, s, variables);
  return e;
}

/// A joint element's own coordinates and speeds, where they are written, and the
/// sequence of a spherical joint's angles.
void Builder::fill_joint_coordinates(PlanarLibrary::Element& e, const Statement& s, const JointVariables& variables) {
  e.coordinates = variables.coordinates;
  e.coordinate_speeds = variables.speeds;
  for (const auto& c : s.joint_coordinates) e.coordinate_positions.push_back(c.pos);
  e.coordinate = e.coordinates.empty() ? -1 : e.coordinates.front();
  e.coordinate_speed = e.coordinate_speeds.empty() ? -1 : e.coordinate_speeds.front();
  e.coordinate_pos = s.joint_coordinates.empty() ? s.pos : s.joint_coordinates.front().pos;
  e.sequence = s.joint_sequence.text;
  e.sequence_pos = s.joint_sequence.pos;
}

/// `inertia (Ixx, Iyy, Izz [, Ixy, Ixz, Iyz])` of a rigid3d body: the tensor about the
/// mass centre in body axes (principal values alone, or with its off-diagonal entries).
void Builder::fill_rigid3d_inertia(int id, const Statement& s) {
  Node& node = m_.nodes[id];
  inertia_given_.insert(id);
  if (s.exprs.size() != 3 && s.exprs.size() != 6) {
    diags_.error(s.pos, fmt::format("inertia of rigid3d body '{}' has {} {}: give (Ixx, Iyy, Izz) or (Ixx, Iyy, Izz, "
                                    "Ixy, Ixz, Iyz) about the mass centre in body axes",
                                    node.name, s.exprs.empty() ? 1 : s.exprs.size(),
                                    s.exprs.size() == 1 || s.exprs.empty() ? "entry" : "entries"));
    return;
  }
  std::vector<GiNaC::ex> e;
  for (const auto& x : s.exprs) {
    auto c = convert(id, x, true, false, false);
    if (!c) return;
    e.push_back(*c);
  }
  while (e.size() < 6) e.push_back(0);
  node.rigid3d.inertia = {e[0], e[3], e[4], e[3], e[1], e[5], e[4], e[5], e[2]};
  node.inertia_pos = s.pos;
  rigid3d_inertia_pos_[id] = s.pos;
}

/// `torque [space|body] (Tx, Ty, Tz)` in a rigid3d body: an applied torque given in
/// space axes (the default) or body axes, turned into generalized forces along the
/// angular speeds (their frame: R^T tau for body-frame speeds given a space torque, R tau
/// for space-frame speeds given a body torque). It may read the state, inputs and t.
void Builder::add_rigid3d_torque(int id, const Statement& s) {
  const Node& node = m_.nodes[id];
  if (node.kind != LeafKind::Rigid3d) {
    diags_.error(s.pos, fmt::format("'torque' is only allowed in rigid3d bodies ('{}' is {}); a torque on a "
                                    "planar body is a force on its w",
                                    m_.label(id), to_string(node.kind)));
    return;
  }
  rigid3d::Vec tau;
  for (const auto& e : s.exprs) {
    auto c = convert(id, e, true, false, false);
    if (!c) return;
    tau.push_back(*c);
  }
  if (node.rigid3d.rotation.empty()) return;  // its variables failed (reported)
  const bool given_in_body = s.option2.text == "body";
  rigid3d::Vec along = tau;
  if (given_in_body && node.rigid3d.space_frame) along = rigid3d::mat_vec(node.rigid3d.rotation, tau);
  if (!given_in_body && !node.rigid3d.space_frame) along = rigid3d::mat_t_vec(node.rigid3d.rotation, tau);
  for (int k = 0; k < 3; ++k)
    if (!along[static_cast<std::size_t>(k)].is_zero())
      m_.forces.push_back(Force{node.speeds[3 + static_cast<std::size_t>(k)], along[static_cast<std::size_t>(k)], s.pos});
}

/// A rigid3d body's points and axes, in body coordinates relative to its mass centre.
void Builder::add_rigid3d_geometry(int id, const Statement& s, const std::vector<GiNaC::ex>& v) {
  Node& node = m_.nodes[id];
  if (s.kind == Kind::Com) {
    if (rigid3d_com_pos_.count(id)) {
      diags_.error(s.pos, fmt::format("com of body '{}' is given twice (first at {})", node.name,
                                      position_text(rigid3d_com_pos_[id], s.pos)));
      return;
    }
    rigid3d_com_pos_[id] = s.pos;
    node.rigid3d.com = v;
    return;
  }
  auto& into = s.kind == Kind::Point ? node.rigid3d.points : node.rigid3d.axes;
  if (node.rigid3d.points.count(s.name) || node.rigid3d.axes.count(s.name)) {
    diags_.error(s.name_pos, fmt::format("point or axis '{}' of body '{}' is already declared", s.name, node.name));
    return;
  }
  if (s.kind == Kind::Axis) {
    double len2 = 0;
    bool known = true;
    for (int k = 3; k < 6; ++k) {
      double d;
      try {
        known = known && evaluate_number(substitute_param_defaults(v[static_cast<std::size_t>(k)], true), d);
      } catch (const std::exception&) {
        known = false;
      }
      if (known) len2 += d * d;
    }
    if (known && !(len2 > 0)) {
      diags_.error(s.name_pos, fmt::format("axis '{}' of body '{}' has a zero direction", s.name, node.name));
      spatial_.add_failed(id, s.name);  // a joint naming it says no more
      return;
    }
  }
  into[s.name] = v;
}

}  // namespace mbsc::model::build_detail
