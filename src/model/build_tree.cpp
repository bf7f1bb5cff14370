// SPDX-License-Identifier: GPL-2.0-or-later
// Pass A: the subsystem tree, children before their parent, components instantiated with
// their arguments, and the variables each node declares: those its leaf kind brings (a
// particle's x, y with u, v), its own coordinates and speeds, its lets, and the
// coordinates of joints that have one and of rolling spheres' contact points.
#include "build_internal.hpp"

#include <fmt/format.h>

#include "mbsc/diag/activity.hpp"
#include "mbsc/diag/limits.hpp"
#include "mbsc/diag/name_suggestions.hpp"
#include "mbsc/model/rigid3d.hpp"

namespace mbsc::model::build_detail {

namespace {

bool leaf_kind_from_name(const std::string& s, LeafKind& kind) {
  if (s == "particle2d") kind = LeafKind::Particle2d;
  else if (s == "particle3d") kind = LeafKind::Particle3d;
  else if (s == "rigid2d") kind = LeafKind::Rigid2d;
  else if (s == "custom") kind = LeafKind::Custom;
  else if (s == "rigid2d_nodal") kind = LeafKind::Rigid2dNodal;
  else if (s == "rigid3d") kind = LeafKind::Rigid3d;
  else return false;
  return true;
}

}  // namespace

int Builder::declare_node(const std::vector<ast::StatementPtr>& body, const std::string& prefix, const SourcePos& pos,
                          const Statement* decl, int depth) {
  if (depth > 64) {
    diags_.error(pos, fmt::format("subsystem '{}' nests too deeply (recursive component?)", prefix));
    return -1;
  }
  // Components that each hold two instances of the next one double the tree at every
  // level: bound the count, not only the depth.
  if (++declared_nodes_ > limits::kMaxNodes) {
    if (declared_nodes_ == limits::kMaxNodes + 1)
      diags_.error(pos, fmt::format("the model has more than {} subsystems (components instantiated many times "
                                    "over?); stopped at '{}'",
                                    limits::kMaxNodes, prefix));
    return -1;
  }
  checkpoint("declaring", fmt::format("subsystem '{}'", prefix.empty() ? (m_.name.empty() ? std::string("the model") : m_.name) : prefix), pos,
             declared_nodes_, 0);
  Node node;
  node.name = prefix;
  node.pos = pos;
  if (decl && !decl->kind_name.empty()) {
    LeafKind kind;
    if (leaf_kind_from_name(decl->kind_name, kind)) {
      // `parametrization nodal` makes every plain rigid2d body a nodal one.
      node.kind = kind == LeafKind::Rigid2d && nodal_default_ ? LeafKind::Rigid2dNodal : kind;
      if (!decl->exprs.empty())
        diags_.error(decl->kind_pos, fmt::format("leaf kind '{}' of subsystem '{}' takes no arguments", decl->kind_name, prefix));
    } else if (components_.count(decl->kind_name)) {
      node.component = decl->kind_name;
    } else {
      diags_.error(decl->kind_pos, unknown_kind_message(prefix, decl->kind_name));
      return -1;
    }
  }
  // Children first (post-order).
  std::vector<int> children;
  std::vector<ast::StatementPtr> own_body = body;
  if (!node.component.empty()) {
    const Statement* comp = components_.at(node.component);
    if (comp->formals.size() != decl->exprs.size()) {
      diags_.error(decl->kind_pos, fmt::format("component '{}' takes {} argument(s), subsystem '{}' gives {}", node.component,
                                               comp->formals.size(), prefix, decl->exprs.size()));
      return -1;
    }
    own_body = comp->body;
    own_body.insert(own_body.end(), body.begin(), body.end());
    for (size_t i = 0; i < comp->formals.size(); ++i) {
      std::string full = join(prefix, comp->formals[i]);
      if (!declare_local(full, comp->formal_pos[i], "formal parameter")) continue;
      GiNaC::symbol sym(full);
      table_[full] = Entry{Entry::Formal, 0, sym, "a component parameter", comp->formal_pos[i]};
      formal_args_.push_back({full, decl->exprs[i], prefix});
      m_.formals[full] = Formal{sym, 0};
    }
  }
  scopes_.push_back({prefix, &own_body});
  for (const auto& s : own_body) {
    if (s->kind != Kind::Subsystem) continue;
    std::string child = join(prefix, s->name);
    if (s->name == kGlobalScope) {
      diags_.error(s->name_pos, fmt::format("'{0}' cannot name a subsystem: it names the model's global scope "
                                            "('{0}.g' is the parameter g)",
                                            kGlobalScope));
      continue;
    }
    LeafKind leaf;
    const bool body = leaf_kind_from_name(s->kind_name, leaf) && leaf != LeafKind::Custom;
    if (!declare_local(child, s->name_pos, body ? "body" : "subsystem")) continue;
    table_[child] = Entry{Entry::NodeName, 0, GiNaC::symbol(), body ? "a body" : "a subsystem", s->name_pos};
    int c = declare_node(s->body, child, s->name_pos, s.get(), depth + 1);
    if (c >= 0) children.push_back(c);
  }
  scopes_.pop_back();
  const int id = static_cast<int>(m_.nodes.size());
  node.children = children;
  m_.nodes.push_back(node);
  pending_.push_back(Pending{own_body, decl});
  for (int c : children) m_.nodes[c].parent = id;
  // Leaf kinds bring their variables: coordinates with speeds defined as their rates.
  const char* const planar[] = {"x", "y"};
  const char* const spatial[] = {"x", "y", "z"};
  const char* const rigid[] = {"x", "y", "theta"};
  const char* const speeds2[] = {"u", "v"};
  const char* const speeds3[] = {"u", "v", "w"};
  auto add_kinematic = [&](const char* const* qs, const char* const* us, int n) {
    for (int i = 0; i < n; ++i) {
      int q = add_variable(id, join(prefix, qs[i]), pos, /*coordinate=*/true, /*builtin=*/true);
      int u = add_variable(id, join(prefix, us[i]), pos, /*coordinate=*/false, /*builtin=*/true);
      if (q >= 0 && u >= 0) builtin_rates_[q] = m_.speeds[u].sym;
    }
  };
  switch (m_.nodes[id].kind) {
    case LeafKind::Particle2d: add_kinematic(planar, speeds2, 2); break;
    case LeafKind::Particle3d: add_kinematic(spatial, speeds3, 3); break;
    case LeafKind::Rigid2d: add_kinematic(rigid, speeds3, 3); break;
    case LeafKind::Rigid2dNodal: {
      // Nodal coordinates: each point P brings P_x, P_y with rates P_u, P_v; then the
      // angular speed w (no coordinate of its own).
      int npoints = 0;
      for (const auto& s : own_body) {
        if (s->kind != Kind::Point) continue;
        ++npoints;
        const std::string qx = s->name + "_x", qy = s->name + "_y", ux = s->name + "_u", uy = s->name + "_v";
        const char* const qs[] = {qx.c_str(), qy.c_str()};
        const char* const us[] = {ux.c_str(), uy.c_str()};
        add_kinematic(qs, us, 2);
      }
      add_variable(id, join(prefix, "w"), pos, /*coordinate=*/false, /*builtin=*/true);
      if (npoints < 2)
        diags_.error(pos, fmt::format("rigid2d_nodal body '{}' needs at least two points (its nodes); it has {}", prefix,
                                      npoints));
      break;
    }
    case LeafKind::Rigid3d: declare_rigid3d(id, prefix, pos, own_body); break;
    default: break;
  }
  // Declared coordinates and speeds, and named expressions.
  for (const auto& s : own_body) {
    if (s->kind == Kind::Coordinate) add_variable(id, join(prefix, s->name), s->name_pos, true);
    if (s->kind == Kind::Speed) add_variable(id, join(prefix, s->name), s->name_pos, false);
    if (s->kind == Kind::Let) declare_let(id, join(prefix, s->name), *s);
    if (s->kind == Kind::Joint && !s->joint_coordinates.empty()) declare_joint_coordinate(id, prefix, *s);
    if (s->kind == Kind::Joint && s->kind_name == "rolling_sphere") declare_contact_coordinates(id, prefix, *s);
  }
  return id;
}

/// `joint ... coordinate q1, q2 [speed s1, s2]`: the joint's relative coordinates and
/// their rates (default q1_dot, ...; s = q') become variables of the node the joint is
/// written at. How many a joint kind takes is checked where the joint is built.
void Builder::declare_joint_coordinate(int id, const std::string& prefix, const Statement& s) {
  const std::string joint = s.name.empty() ? std::string("joint") : fmt::format("joint '{}'", s.name);
  if (s.joint_sequence.text == "quaternion") {
    declare_joint_quaternion(id, prefix, s, joint);
    return;
  }
  if (!s.joint_speeds.empty() && s.joint_speeds.size() != s.joint_coordinates.size()) {
    diags_.error(s.joint_speeds.front().pos,
                 fmt::format("{} names {} {} for {} {}: give one speed per coordinate, in the same order, or none", joint,
                             s.joint_speeds.size(), s.joint_speeds.size() == 1 ? "speed" : "speeds",
                             s.joint_coordinates.size(), s.joint_coordinates.size() == 1 ? "coordinate" : "coordinates"));
    return;
  }
  JointVariables v;
  for (std::size_t k = 0; k < s.joint_coordinates.size(); ++k) {
    const ast::Path& c = s.joint_coordinates[k];
    const ast::Path speed = s.joint_speeds.empty() ? ast::Path{c.text + "_dot", c.pos} : s.joint_speeds[k];
    const int q = add_variable(id, join(prefix, c.text), c.pos, /*coordinate=*/true);
    const int u = add_variable(id, join(prefix, speed.text), speed.pos, /*coordinate=*/false);
    if (q < 0 || u < 0) return;  // reported: a name declared twice
    const char* article = s.joint_coordinates.size() == 1 ? "the" : "a";
    table_[join(prefix, c.text)].what = fmt::format("{} coordinate of {}", article, joint);
    table_[join(prefix, speed.text)].what = fmt::format("{} speed of {}", article, joint);
    builtin_rates_[q] = m_.speeds[static_cast<std::size_t>(u)].sym;
    v.coordinates.push_back(q);
    v.speeds.push_back(u);
  }
  joint_variables_[{id, &s}] = v;
}

/// `joint NAME : spherical P.a B.a coordinate e0, e1, e2, e3 quaternion [speed w1, w2, w3]`:
/// four coordinates, the joint's quaternion (scalar part first), and three speeds, the
/// child's angular velocity relative to its parent in the child's axes (default
/// NAME_wx, NAME_wy, NAME_wz). The speeds are not coordinate rates: the rates are the
/// kinematic equations e' = 1/2 e o (0, w), as for a body's `attitude quaternion body`.
void Builder::declare_joint_quaternion(int id, const std::string& prefix, const Statement& s, const std::string& joint) {
  if (s.kind_name != "spherical") {
    diags_.error(s.joint_sequence.pos, fmt::format("{}: 'quaternion' names a spherical joint's four quaternion "
                                                   "coordinates; a {} joint turns about its axes",
                                                   joint, s.kind_name));
    return;
  }
  if (s.joint_coordinates.size() != 4) {
    const SourcePos& at = s.joint_coordinates.size() > 4 ? s.joint_coordinates[4].pos : s.joint_coordinates.front().pos;
    diags_.error(at, fmt::format("{}: a spherical joint with a quaternion takes 4 coordinates (the scalar part, then "
                                 "the vector part, e.g. `coordinate e0, e1, e2, e3 quaternion`), not {}",
                                 joint, s.joint_coordinates.size()));
    return;
  }
  if (!s.joint_speeds.empty() && s.joint_speeds.size() != 3) {
    diags_.error(s.joint_speeds.front().pos,
                 fmt::format("{} names {} {} for its quaternion: give three, the angular speeds about the second "
                             "body's x, y and z axes relative to the first body, or none",
                             joint, s.joint_speeds.size(), s.joint_speeds.size() == 1 ? "speed" : "speeds"));
    return;
  }
  if (s.joint_speeds.empty() && s.name.empty()) {
    diags_.error(s.joint_sequence.pos, "an unnamed spherical joint with a quaternion needs its three speeds named "
                                       "(`speed w1, w2, w3`), or a name (`joint NAME : ...`) for the default NAME_wx, "
                                       "NAME_wy, NAME_wz");
    return;
  }
  JointVariables v;
  for (const ast::Path& c : s.joint_coordinates) {
    const int q = add_variable(id, join(prefix, c.text), c.pos, /*coordinate=*/true);
    if (q < 0) return;  // reported: a name declared twice
    table_[join(prefix, c.text)].what = fmt::format("a quaternion coordinate of {}", joint);
    v.coordinates.push_back(q);
  }
  const char* const axes[] = {"wx", "wy", "wz"};
  for (std::size_t k = 0; k < 3; ++k) {
    const ast::Path speed = s.joint_speeds.empty() ? ast::Path{s.name + "_" + axes[k], s.name_pos} : s.joint_speeds[k];
    const int u = add_variable(id, join(prefix, speed.text), speed.pos, /*coordinate=*/false);
    if (u < 0) return;
    table_[join(prefix, speed.text)].what = fmt::format("an angular speed of {}", joint);
    v.speeds.push_back(u);
  }
  rigid3d::Vec e, w;
  for (int q : v.coordinates) e.push_back(m_.coords[static_cast<std::size_t>(q)].sym);
  for (int u : v.speeds) w.push_back(m_.speeds[static_cast<std::size_t>(u)].sym);
  const rigid3d::Vec rates = rigid3d::quaternion_rates(e, w, /*space_frame=*/false);
  for (std::size_t k = 0; k < 4; ++k) builtin_rates_[v.coordinates[k]] = rates[k];
  joint_variables_[{id, &s}] = v;
}

/// `joint NAME : rolling_sphere ...`: the contact point's x and y on the surface are two
/// coordinates NAME.xc, NAME.yc of the node the joint is written at, with their rates
/// NAME.xc_dot, NAME.yc_dot as speeds (formulation.md, "A sphere rolling on a surface").
void Builder::declare_contact_coordinates(int id, const std::string& prefix, const Statement& s) {
  if (s.name.empty()) {
    // Its contact coordinates are named after it (and `initial` places them by name).
    diags_.error(s.kind_pos, "a rolling_sphere joint needs a name (`joint NAME : rolling_sphere ...`): its contact "
                             "coordinates are NAME.xc and NAME.yc");
    return;
  }
  const std::string& joint = s.name;
  const SourcePos pos = s.name_pos;
  std::vector<int> qs;
  for (const char* c : {"xc", "yc"}) {
    const std::string q_name = join(prefix, joint + "." + c);
    const int q = add_variable(id, q_name, pos, /*coordinate=*/true);
    const int u = add_variable(id, q_name + "_dot", pos, /*coordinate=*/false);
    if (q < 0 || u < 0) return;  // reported: a name declared twice
    table_[q_name].what = fmt::format("a contact coordinate of joint '{}'", joint);
    table_[q_name + "_dot"].what = fmt::format("a contact speed of joint '{}'", joint);
    builtin_rates_[q] = m_.speeds[static_cast<std::size_t>(u)].sym;
    qs.push_back(q);
  }
  contact_coordinates_[{id, &s}] = qs;
}

/// "unknown kind", with the close name if any, the leaf kinds and the components.
std::string Builder::unknown_kind_message(const std::string& subsystem, const std::string& kind) const {
  std::vector<std::string> kinds;
  for (LeafKind k : {LeafKind::Particle2d, LeafKind::Particle3d, LeafKind::Rigid2d, LeafKind::Rigid2dNodal,
                     LeafKind::Rigid3d, LeafKind::Custom})
    kinds.push_back(to_string(k));
  std::vector<std::string> components, all = kinds;
  for (const auto& [name, stmt] : components_) components.push_back(name);
  all.insert(all.end(), components.begin(), components.end());
  // A file of thousands of components lists the first few (alphabetically) and a count.
  constexpr std::size_t kListed = 12;
  const std::size_t more = components.size() > kListed ? components.size() - kListed : 0;
  components.resize(components.size() - more);
  if (more > 0) components.push_back(fmt::format("{} more", more));
  return fmt::format("subsystem '{}' has unknown kind or component '{}'{}; the leaf kinds are {}{}", subsystem, kind,
                     did_you_mean(kind, all), list_names(kinds),
                     components.empty() ? std::string(" (no component is defined)")
                                        : fmt::format(", the components {}", list_names(components)));
}

/// A coordinate or speed; `builtin` for those a leaf kind brings (declared at the body).
int Builder::add_variable(int node, const std::string& full, const SourcePos& pos, bool coordinate, bool builtin) {
  if (!declare_local(full, pos, coordinate ? "coordinate" : "speed")) return -1;
  const std::string what = fmt::format("{}{}", coordinate ? "a coordinate" : "a speed",
                                       builtin ? fmt::format(" of the {} body", to_string(m_.nodes[node].kind)) : "");
  Variable v{full, node, GiNaC::symbol(full), pos};
  if (coordinate) {
    int i = static_cast<int>(m_.coords.size());
    m_.coords.push_back(v);
    m_.nodes[node].coords.push_back(i);
    coord_dot_.push_back(GiNaC::symbol(full + "'"));
    table_[full] = Entry{Entry::Coord, i, v.sym, what, pos};
    return i;
  }
  int i = static_cast<int>(m_.speeds.size());
  m_.speeds.push_back(v);
  m_.speed_dots.push_back(GiNaC::symbol(full + "'"));
  m_.nodes[node].speeds.push_back(i);
  table_[full] = Entry{Entry::Speed, i, v.sym, what, pos};
  return i;
}

}  // namespace mbsc::model::build_detail
