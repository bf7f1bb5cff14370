// SPDX-License-Identifier: GPL-2.0-or-later
// Joint coordinates in space: a joint with coordinates of its own,
//   joint steering : revolute rear_frame.steer front_frame.steer coordinate delta
//   joint hip : spherical pelvis.h thigh.h coordinate a, b, c euler zyx
// places its second body from the first, as the planar `coordinate` option does
// (relative_joint.cpp), so that a tree of such joints is written in joint coordinates.
// Every kind is a slide and a list of turns (Rigid3dData::joint_turns):
//   revolute    q about the axis n                     prismatic  s along n
//   cylindrical s along n, then q about it              universal  q1 about the first axis,
//   spherical   three turns about the parent's frame      then q2 about the second
//               axes of an Euler sequence (intrinsic),
//               or no turns but a quaternion e: Q = Q(e), w_rel = the joint's three speeds
// with n the first end's unit axis in the parent's body frame; the two bodies' frames
// coincide at q = 0, so each turn's axis is also where the child's frame has it.
//   * the child has no attitude coordinates: its attitude is R = R_parent Q(q);
//   * its mass centre x, y, z stays a coordinate, given explicitly by the joint point:
//       NAME.x, NAME.y, NAME.z   P_child - P_parent - s R_parent n = 0   (position)
//   * its body-frame angular speeds are given explicitly by the parent's and the rates:
//       NAME.wx, NAME.wy, NAME.wz  w - Q^T w_parent - w_rel = 0          (velocity)
//     with w_rel = sum_i (Q_{i+1} ... Q_k)^T n_i q_i' (rigid3d::joint_relative_angular_velocity).
//     These are the time derivative of R^T R' = [w]x for R = R_parent Q, so they are
//     integrable: the child's attitude follows from q, no drift.
// Each row has coefficient 1 on one of the child's variables, so the complement pivots
// on them with no numeric solve, and `--state minimal` keeps the joint coordinates and
// drops x, y, z. The rows a joint without coordinates writes (alignment, twist, the
// universal's cross) are implied and not written.
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

bool SpatialLibrary::places(const std::string& kind) { return coordinate_count(kind) > 0; }

int SpatialLibrary::coordinate_count(const std::string& kind) {
  if (kind == "revolute" || kind == "prismatic") return 1;
  if (kind == "cylindrical" || kind == "universal") return 2;
  if (kind == "spherical") return 3;
  return 0;
}

std::optional<int> SpatialLibrary::point_body(int owner, const std::string& path) const {
  const auto dot = path.rfind('.');
  if (dot == std::string::npos) return std::nullopt;
  return body(owner, path.substr(0, dot));
}

bool SpatialLibrary::coordinates_fit(const PlanarLibrary::Element& e, const std::string& what) {
  // A spherical joint's quaternion (four coordinates, three speeds) was checked where its
  // variables were declared (build_tree.cpp).
  if (e.kind == "spherical" && e.sequence == "quaternion") return e.coordinates.size() == 4 && e.coordinate_speeds.size() == 3;
  const int want = coordinate_count(e.kind);
  const int given = static_cast<int>(e.coordinates.size());
  static const std::map<std::string, std::string> meaning = {
      {"revolute", "its angle"},
      {"prismatic", "its slide"},
      {"cylindrical", "the slide along the axis, then the angle about it"},
      {"universal", "the angle about the first axis, then the angle about the second"},
      {"spherical", "three angles of an Euler sequence, e.g. `coordinate a, b, c euler zyx`, or four of a quaternion, "
                    "`coordinate e0, e1, e2, e3 quaternion`"}};
  if (given != want) {
    const SourcePos& at = given > want ? e.coordinate_positions[static_cast<std::size_t>(want)] : e.coordinate_pos;
    diags_.error(at, fmt::format("{}: a spatial {} joint takes {} {} ({}), not {}", what, e.kind, want,
                                 want == 1 ? "coordinate" : "coordinates", meaning.at(e.kind), given));
    return false;
  }
  if (e.kind == "spherical" && e.sequence.empty()) {
    diags_.error(e.coordinate_pos, fmt::format("{}: a spherical joint's three angles turn about the axes of an Euler "
                                               "sequence; name it after the coordinates, e.g. `coordinate a, b, c euler zyx` "
                                               "(or give four quaternion coordinates: `coordinate e0, e1, e2, e3 quaternion`)",
                                               what));
    return false;
  }
  if (e.kind != "spherical" && !e.sequence.empty()) {
    diags_.error(e.sequence_pos, fmt::format("{}: 'euler' names the sequence of a spherical joint's three angles; a {} "
                                             "joint turns about its axes",
                                             what, e.kind));
    return false;
  }
  if (!e.sequence.empty() && !rigid3d::valid_sequence(e.sequence)) {
    diags_.error(e.sequence_pos, fmt::format("{}: '{}' is not an Euler sequence: write three axes of x, y, z with no axis "
                                             "twice in a row, e.g. zyx, zxz, xyz",
                                             what, e.sequence));
    return false;
  }
  return true;
}

SpatialLibrary::Vec SpatialLibrary::unit(const Vec& d) {
  // Exactly, when the length is 1 symbolically (the unit axes users write).
  const GiNaC::ex len2 = tidy_square_length(d);
  Vec n = d;
  if ((len2 - 1).is_zero()) return n;
  const GiNaC::ex len = GiNaC::is_a<GiNaC::numeric>(len2) ? rigid3d::length(d) : GiNaC::sqrt(len2);
  if (len != 1)
    for (auto& x : n) x = x / len;
  return n;
}

bool SpatialLibrary::same_direction(const PlanarLibrary::Element& e, const std::string& what, const Vec& d, const Vec& c,
                                    int parent, int child) {
  // The child's axis must be the parent's in body coordinates: same direction and sense,
  // for every parameter value. The same expressions pass at once; otherwise their cross
  // product must vanish symbolically (sin^2 as 1 - cos^2) and their dot product be
  // positive at the defaults. A direction that cannot be evaluated at the defaults (it
  // reads an input or a component's parameter) must be written the same on both ends.
  bool same = true;
  for (std::size_t k = 0; k < 3; ++k) same = same && GiNaC::expand(d[k] - c[k]).is_zero();
  if (same) return true;
  const Vec cr = rigid3d::cross(d, c);
  bool cross_zero = true;
  for (const auto& x : cr) cross_zero = cross_zero && tidy_expand(x).is_zero();
  const double dc = at_defaults(rigid3d::dot(d, c)), dd = at_defaults(rigid3d::dot(d, d)), cc = at_defaults(rigid3d::dot(c, c));
  if (std::isnan(dc) || std::isnan(dd) || std::isnan(cc)) {
    diags_.error(e.end2_pos, fmt::format("{}: the directions of the axes '{}' and '{}' cannot be compared at the parameter "
                                         "defaults (they read an input or a component's parameter); write the same "
                                         "direction for both",
                                         what, e.end1, e.end2));
    return false;
  }
  if (!(dd > 0) || !(cc > 0)) return false;  // a zero direction: reported where the axis is declared
  if (!cross_zero || !(dc > 0)) {
    diags_.error(e.end2_pos, fmt::format("{}: the axes '{}' and '{}' point differently in their bodies' coordinates; a "
                                         "joint with a coordinate moves '{}' from the attitude of '{}' along or about the "
                                         "axis (the two bodies' frames coincide at {} = 0), so give both axes the same "
                                         "direction",
                                         what, e.end1, e.end2, m_.nodes[static_cast<std::size_t>(child)].name,
                                         parent == PlanarLibrary::kGround ? std::string("ground")
                                                                          : m_.nodes[static_cast<std::size_t>(parent)].name,
                                         m_.coords[static_cast<std::size_t>(e.coordinate)].name));
    return false;
  }
  return true;
}

SpatialLibrary::Placed SpatialLibrary::place(int owner, const PlanarLibrary::Element& e, int child) {
  const std::string what = fmt::format("joint '{}'", e.name);
  if (!coordinates_fit(e, what)) return Placed::Failed;
  // The two ends' bodies, and for the joints on axes the axes' body-frame directions.
  const bool on_points = e.kind == "spherical";
  std::optional<std::pair<int, Vec>> pa, ca;
  if (on_points) {
    const auto p = point_body(owner, e.end1), c = point_body(owner, e.end2);
    if (p) pa = std::make_pair(*p, Vec{});
    if (c) ca = std::make_pair(*c, Vec{});
  } else {
    pa = axis_direction(owner, e.end1);
    ca = axis_direction(owner, e.end2);
  }
  if (!pa || !ca || ca->first != child) return Placed::Failed;  // pass B's end() says why
  const int parent = pa->first;
  if (parent != PlanarLibrary::kGround) {
    const Rigid3dData& p = m_.nodes[static_cast<std::size_t>(parent)].rigid3d;
    if (p.placed() && p.rotation.empty()) return Placed::Later;
    if (p.rotation.empty()) return Placed::Failed;  // its variables failed (reported)
  }
  const Vec& d = pa->second;
  const Vec& c = ca->second;
  auto coordinate = [&](std::size_t k) { return GiNaC::ex(m_.coords[static_cast<std::size_t>(e.coordinates[k])].sym); };
  auto speed = [&](std::size_t k) { return GiNaC::ex(m_.speeds[static_cast<std::size_t>(e.coordinate_speeds[k])].sym); };
  Rigid3dData& data = m_.nodes[static_cast<std::size_t>(child)].rigid3d;
  data.joint_turns.clear();
  data.slide_axis.clear();
  data.joint_quaternion.clear();
  data.joint_quaternion_speeds.clear();
  data.joint_quaternion_coords.clear();
  if (e.kind == "revolute" || e.kind == "prismatic" || e.kind == "cylindrical") {
    if (!same_direction(e, what, d, c, parent, child)) return Placed::Failed;
    const Vec n = unit(d);
    std::size_t next = 0;
    if (e.kind != "revolute") {
      data.slide_axis = n;
      data.slide = coordinate(0);
      data.slide_rate = speed(0);
      next = 1;
    }
    if (e.kind != "prismatic") data.joint_turns.push_back({n, coordinate(next), speed(next)});
  } else if (e.kind == "universal") {
    // The cross row d_a . d_b = 0 holds at q = 0 only when the axes are perpendicular in
    // the bodies' coordinates (the frames coincide there): for every parameter value.
    if (!tidy_expand(rigid3d::dot(d, c)).is_zero()) {
      diags_.error(e.end2_pos, fmt::format("{}: the axes '{}' and '{}' are not perpendicular in their bodies' coordinates; "
                                           "a universal joint with coordinates turns '{}' about the first axis, then about "
                                           "the second, from the attitude where the two bodies' frames coincide, so give "
                                           "the second axis a direction perpendicular to the first's",
                                           what, e.end1, e.end2, m_.nodes[static_cast<std::size_t>(child)].name));
      return Placed::Failed;
    }
    data.joint_turns.push_back({unit(d), coordinate(0), speed(0)});
    data.joint_turns.push_back({unit(c), coordinate(1), speed(1)});
  } else if (e.sequence == "quaternion") {  // spherical: Q is the quaternion's matrix, no turns
    for (std::size_t k = 0; k < 4; ++k) {
      data.joint_quaternion.push_back(coordinate(k));
      data.joint_quaternion_coords.push_back(e.coordinates[k]);
    }
    for (std::size_t k = 0; k < 3; ++k) data.joint_quaternion_speeds.push_back(speed(k));
  } else {  // spherical: the Euler sequence's axes, intrinsic (each in the frame the turns before leave)
    for (std::size_t k = 0; k < 3; ++k) {
      Vec axis{0, 0, 0};
      axis[static_cast<std::size_t>(e.sequence[k] - 'x')] = 1;
      data.joint_turns.push_back({axis, coordinate(k), speed(k)});
    }
  }
  data.joint_parent = parent;
  const Vec turn = rigid3d::joint_rotation(data);
  data.rotation = parent == PlanarLibrary::kGround
                      ? turn
                      : rigid3d::mat_mat(m_.nodes[static_cast<std::size_t>(parent)].rigid3d.rotation, turn);
  if (names_rotation(parent, turn_count(data))) name_rotation(child);
  return Placed::Done;
}

int SpatialLibrary::turn_count(const std::string& kind) {
  return kind == "prismatic" ? 0 : kind == "cylindrical" ? 1 : kind == "spherical" ? 3 : coordinate_count(kind);
}

std::size_t SpatialLibrary::turn_count(const Rigid3dData& data) {
  return data.joint_quaternion.empty() ? data.joint_turns.size() : 3;  // a quaternion turns about all three axes
}

bool SpatialLibrary::names_rotation(int parent, std::size_t turns) const {
  // The rule of docs/formulation.md, "Named body rotations": a body placed under a body
  // with an attitude of its own (a free base: its rotation is already a full matrix of
  // attitude coordinates) is always named, and so is every placed body of a model whose
  // joints make more than kGroundJointsWritten turns (the tree recursion reads each
  // body's rows in its parent's speeds alone; a written-out rotation carries the joint
  // rates of every joint above it). In a small model the rotations of the bodies fewer
  // than kGroundJointsWritten turns below the ground stay written-out products of joint
  // rotations: the exact axes' zeros and ones cancel there, and naming them costs
  // operations (202 -> 264 for two revolute links).
  if (turns_ > kGroundJointsWritten) return true;
  std::size_t depth = turns;
  int p = parent;
  while (p != PlanarLibrary::kGround && m_.nodes[static_cast<std::size_t>(p)].rigid3d.placed()) {
    depth += turn_count(m_.nodes[static_cast<std::size_t>(p)].rigid3d);
    p = m_.nodes[static_cast<std::size_t>(p)].rigid3d.joint_parent;
  }
  return p != PlanarLibrary::kGround || depth > static_cast<std::size_t>(kGroundJointsWritten);
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
  data.unturned_from_parent = turns_ <= kGroundJointsWritten;
}

void SpatialLibrary::add_placement(int owner, const PlanarLibrary::Element& e, const std::string& name,
                                   const std::string& what) {
  const bool on_axes = e.kind != "spherical";
  const auto a = end(owner, e.end1, on_axes, e.end1_pos, what, "joint");
  const auto b = end(owner, e.end2, on_axes, e.end2_pos, what, "joint");
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
  for (const auto* option : {&e.option, &e.option2})
    if (*option == "friction") {
      diags_.error(*option == e.option ? e.option_pos : e.option2_pos,
                   fmt::format("{}: 'friction' reads the normal reaction of the joint's rows .n1 and .n2, which a joint "
                               "with a coordinate does not write; drop the coordinate to model the friction",
                               what));
      return;
    }
  // The joint point: the child's mass centre follows from it (explicit in x, y, z),
  // moved by s along the axis in space for a slide.
  Vec gap = {b->p[0] - a->p[0], b->p[1] - a->p[1], b->p[2] - a->p[2]};
  if (!data.slide_axis.empty()) {
    const Vec along = unit_axis(*a);
    for (std::size_t k = 0; k < 3; ++k) gap[k] -= data.slide * along[k];
  }
  const char* const xyz[] = {"x", "y", "z"};
  for (std::size_t k = 0; k < 3; ++k)
    row(owner, name + "." + xyz[k], gap[k], e.pos, Constraint::Level::Position, child.coords[k]);
  // The child's body-frame angular velocity: the parent's turned back by the joint, plus
  // the joint's own rates.
  const Vec wp = rigid3d::joint_turn_back(data, rigid3d::parent_angular_velocity_in_parent_frame(m_, child));
  const Vec wr = rigid3d::joint_relative_angular_velocity(data);
  const Vec w = rigid3d::angular_speeds(m_, child);
  const char* const names[] = {"wx", "wy", "wz"};
  for (std::size_t k = 0; k < 3; ++k)
    row(owner, name + "." + names[k], w[k] - wp[k] - wr[k], e.pos, Constraint::Level::Velocity);
  if (!e.option.empty()) {
    const std::string& prefix = m_.nodes[static_cast<std::size_t>(owner)].name;
    add_actuators(e, what, prefix.empty() ? name : prefix + "." + name, *a, *b);
  }
}

}  // namespace mbsc::model
