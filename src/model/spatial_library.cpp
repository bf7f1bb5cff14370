// SPDX-License-Identifier: GPL-2.0-or-later
#include "spatial_library.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>
#include <limits>

#include <fmt/format.h>

#include "mbsc/diag/name_suggestions.hpp"
#include "mbsc/model/exact_guard.hpp"
#include "mbsc/model/expr_convert.hpp"
#include "mbsc/model/rigid3d.hpp"
#include "mbsc/model/varying_part.hpp"

namespace mbsc::model {

namespace {
std::string join(const std::string& a, const std::string& b) { return a.empty() ? b : a + "." + b; }
using Vec = SpatialLibrary::Vec;
Vec sub(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
// The joint kinds whose ends are axes (the first end of point_on_line / point_on_plane).
bool first_is_axis(const std::string& k) {
  return k == "revolute" || k == "universal" || k == "cylindrical" || k == "prismatic" || k == "point_on_line" ||
         k == "point_on_plane";
}
bool second_is_axis(const std::string& k) {
  return k == "revolute" || k == "universal" || k == "cylindrical" || k == "prismatic";
}
}  // namespace

const std::vector<std::string>& SpatialLibrary::kinds() {
  static const std::vector<std::string> k = {"spherical", "revolute",      "universal",     "cylindrical",
                                             "prismatic", "weld",          "point_on_line", "point_on_plane",
                                             "rolling",   "rolling_sphere"};
  return k;
}

SpatialLibrary::SpatialLibrary(Model& m, Diagnostics& diags) : m_(m), diags_(diags) {
  ground_points_["origin"] = {0, 0, 0};
  ground_axes_["x_axis"] = {0, 0, 0, 1, 0, 0};
  ground_axes_["y_axis"] = {0, 0, 0, 0, 1, 0};
  ground_axes_["z_axis"] = {0, 0, 0, 0, 0, 1};
}

void SpatialLibrary::add_ground_point(const std::string& name, const Vec& p, const SourcePos& pos) {
  if (has_ground(name) && name != "origin") {
    diags_.error(pos, fmt::format("point 'ground.{}' is declared twice", name));
    return;
  }
  ground_points_[name] = p;
}

void SpatialLibrary::add_ground_axis(const std::string& name, const Vec& v, const SourcePos& pos) {
  if (has_ground(name)) {
    diags_.error(pos, fmt::format("axis 'ground.{}' is declared twice", name));
    return;
  }
  if (at_defaults(v[3] * v[3] + v[4] * v[4] + v[5] * v[5]) == 0.0) {
    diags_.error(pos, fmt::format("axis 'ground.{}' has a zero direction vector", name));
    add_failed(PlanarLibrary::kGround, name);
    return;
  }
  ground_axes_[name] = v;
}

double SpatialLibrary::at_defaults(const GiNaC::ex& e) const {
  try {
    double value = std::numeric_limits<double>::quiet_NaN();
    if (GiNaC::is_a<GiNaC::numeric>(e)) {
      evaluate_number(e, value);
      return value;
    }
    // The parameters' defaults, built once (parameters are all declared before the joints).
    if (defaults_size_ != m_.params.size()) {
      defaults_.clear();
      for (std::size_t i = 0; i < m_.params.size(); ++i) defaults_[m_.params[i].sym] = m_.param_defaults[i];
      defaults_size_ = m_.params.size();
    }
    return evaluate_number(GiNaC::evalf(subs_present(e, defaults_)), value) ? value : std::numeric_limits<double>::quiet_NaN();
  } catch (const std::exception&) {
    return std::numeric_limits<double>::quiet_NaN();
  }
}

std::string SpatialLibrary::varies(const GiNaC::ex& e, const std::vector<int>& except) const {
  return varying_part(m_, e, except);
}

std::optional<int> SpatialLibrary::body(int owner, const std::string& path) const {
  if (path == "ground") return PlanarLibrary::kGround;
  for (int n = owner; n >= 0; n = m_.nodes[n].parent) {
    const std::string full = join(m_.nodes[n].name, path);
    for (std::size_t k = 0; k < m_.nodes.size(); ++k)
      if (m_.nodes[k].name == full && is_body(m_.nodes[k].kind)) return static_cast<int>(k);
    if (m_.nodes[n].parent < 0) break;
  }
  return std::nullopt;
}

bool SpatialLibrary::is_force_element(const std::string& kind) {
  return kind == "spring" || kind == "damper" || kind == "rotational_spring" || kind == "rotational_damper";
}

bool SpatialLibrary::claims(int owner, const PlanarLibrary::Element& e) const {
  const auto& k = kinds();
  const bool force = is_force_element(e.kind);
  if (!force && std::find(k.begin(), k.end(), e.kind) == k.end()) return false;
  if (!force && e.kind != "revolute" && e.kind != "prismatic" && e.kind != "weld" && e.kind != "rolling")
    return true;  // spatial only
  // A rotational spring or damper is spatial when an end is an axis (BODY.NAME) of the
  // ground or of a rigid3d body; the planar one names two bodies.
  if (e.kind == "rotational_spring" || e.kind == "rotational_damper") {
    for (const std::string& path : {e.end1, e.end2}) {
      const auto dot = path.rfind('.');
      if (dot == std::string::npos) continue;
      const auto b = body(owner, path.substr(0, dot));
      if (b && (*b == PlanarLibrary::kGround || m_.nodes[*b].kind == LeafKind::Rigid3d)) return true;
    }
    return false;
  }
  for (const std::string& path : {e.end1, e.end2}) {
    const auto dot = path.rfind('.');
    if (dot == std::string::npos) continue;
    const auto b = body(owner, path.substr(0, dot));
    if (!b) continue;
    if (*b == PlanarLibrary::kGround) {
      const std::string name = path.substr(dot + 1);
      if (name == "z_axis" || (has_ground(name) && name != "origin" && name != "x_axis" && name != "y_axis")) return true;
    } else if (m_.nodes[*b].kind == LeafKind::Rigid3d) {
      return true;
    }
  }
  return false;
}

std::pair<Vec, Vec> SpatialLibrary::normals(const Vec& d) const {
  // n1 = d x e_k with e_k the coordinate axis least aligned with d, n2 = d x n1.
  int k = 0;
  double least = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i) {
    const double a = std::fabs(at_defaults(d[static_cast<std::size_t>(i)]));
    if (a < least) least = a, k = i;
  }
  Vec e{0, 0, 0};
  e[static_cast<std::size_t>(k)] = 1;
  const Vec n1 = rigid3d::cross(d, e);
  return {n1, rigid3d::cross(d, n1)};
}

std::optional<SpatialLibrary::AxisKey> SpatialLibrary::axis_key(int owner, const std::string& path) const {
  const auto dot = path.rfind('.');
  if (dot == std::string::npos) return std::nullopt;
  const auto b = body(owner, path.substr(0, dot));
  if (!b) return std::nullopt;
  return AxisKey{*b, path.substr(dot + 1)};
}

std::optional<SpatialLibrary::End> SpatialLibrary::end(int owner, const std::string& path, bool axis, const SourcePos& pos,
                                                       const std::string& what, const char* element) {
  const char* const noun = axis ? "axis" : "point";
  const auto dot = path.rfind('.');
  const auto b = dot == std::string::npos ? std::nullopt : body(owner, path.substr(0, dot));
  if (!b) {
    // A body named alone (a particle3d, which has no points of its own) is not an end.
    if (const auto whole = body(owner, path); whole && *whole != PlanarLibrary::kGround) {
      diags_.error(pos, fmt::format("{}: '{}' is a {} body, not a {}; a spatial {} connects {}s (BODY.NAME) of rigid3d "
                                    "bodies and the ground",
                                    what, path, to_string(m_.nodes[*whole].kind), noun, element, noun));
      return std::nullopt;
    }
    diags_.error(pos, fmt::format("{}: unknown {} '{}' (BODY.NAME on a rigid3d body or the ground)", what, noun, path));
    return std::nullopt;
  }
  const std::string name = path.substr(dot + 1);
  End out;
  out.node = *b;
  Vec local, dir;
  if (*b == PlanarLibrary::kGround) {
    const auto& table = axis ? ground_axes_ : ground_points_;
    const auto it = table.find(name);
    if (it == table.end() && failed_.count({PlanarLibrary::kGround, name})) return std::nullopt;
    if (it == table.end() && planar_ground_.count(name)) {
      diags_.error(pos, fmt::format("{}: {} '{}' of the ground is planar (two components); a spatial {} needs a "
                                    "spatial one: {}",
                                    what, noun, path, element,
                                    axis ? "axis NAME (px, py, pz) (dx, dy, dz)" : "point NAME (x, y, z)"));
      return std::nullopt;
    }
    if (it == table.end()) {
      diags_.error(pos, fmt::format("{}: unknown {} '{}' of the ground{}", what, noun, path,
                                    (axis ? ground_points_ : ground_axes_).count(name)
                                        ? fmt::format(" ('{}' is a{} there)", path, axis ? " point" : "n axis")
                                        : std::string()));
      return std::nullopt;
    }
    out.p = {it->second[0], it->second[1], it->second[2]};
    if (axis) dir = {it->second[3], it->second[4], it->second[5]};
    out.ex = {1, 0, 0};
    out.ey = {0, 1, 0};
    out.ez = {0, 0, 1};
    if (axis) {
      out.d = dir;
      out.d_length = rigid3d::length(dir);
      std::tie(out.n1, out.n2) = normals(dir);
    }
    return out;
  }
  const Node& node = m_.nodes[*b];
  if (node.kind != LeafKind::Rigid3d) {
    diags_.error(pos, fmt::format("{}: '{}' is on {} body '{}'; a spatial {} connects rigid3d bodies and the ground", what,
                                  path, to_string(node.kind), node.name, element));
    return std::nullopt;
  }
  if (node.rigid3d.rotation.empty()) return std::nullopt;  // its variables failed (reported)
  const auto& table = axis ? node.rigid3d.axes : node.rigid3d.points;
  const auto it = table.find(name);
  if (it == table.end() && failed_.count({*b, name})) return std::nullopt;
  if (it == table.end()) {
    const auto& other = axis ? node.rigid3d.points : node.rigid3d.axes;
    diags_.error(pos, fmt::format("{}: unknown {} '{}' of body '{}'{}", what, noun, path, node.name,
                                  other.count(name) ? fmt::format(" ('{}' is a{} there)", name, axis ? " point" : "n axis")
                                                    : std::string()));
    return std::nullopt;
  }
  out.p = rigid3d::point_in_space(m_, node, {it->second[0], it->second[1], it->second[2]});
  out.ex = rigid3d::direction_in_space(m_, node, {1, 0, 0});
  out.ey = rigid3d::direction_in_space(m_, node, {0, 1, 0});
  out.ez = rigid3d::direction_in_space(m_, node, {0, 0, 1});
  if (axis) {
    const Vec d{it->second[3], it->second[4], it->second[5]};
    const auto n = normals(d);
    out.d = rigid3d::direction_in_space(m_, node, d);
    out.d_length = rigid3d::length(d);
    out.n1 = rigid3d::direction_in_space(m_, node, n.first);
    out.n2 = rigid3d::direction_in_space(m_, node, n.second);
  }
  return out;
}

void SpatialLibrary::row(int owner, const std::string& name, const GiNaC::ex& residual, const SourcePos& pos,
                         Constraint::Level level, int explicit_coordinate) {
  Constraint c;
  c.explicit_coordinate = explicit_coordinate;
  c.name = join(m_.nodes[owner].name, name);
  c.node = owner;
  c.level = level;
  c.residual = residual;
  c.pos = pos;
  m_.nodes[owner].constraints.push_back(static_cast<int>(m_.constraints.size()));
  m_.constraints.push_back(c);
}

void SpatialLibrary::add_element(int owner, const PlanarLibrary::Element& e) {
  const std::string name = e.name.empty() ? fmt::format("{}{}", e.kind, ++unnamed_) : e.name;
  const std::string what = fmt::format("joint '{}'", name);
  if (e.kind == "rolling_sphere" && e.coordinate < 0) {
    add_rolling_sphere(owner, e, name, what);
    return;
  }
  if (e.coordinate >= 0 && places(e.kind)) {
    if (e.kind == "revolute" || e.kind == "cylindrical") {
      const auto a = axis_key(owner, e.end1), b = axis_key(owner, e.end2);
      if (a && b) hinged_.insert(std::minmax(*a, *b));
    }
    add_placement(owner, e, name, what);
    return;
  }
  if (e.coordinate >= 0) {
    diags_.error(e.coordinate_pos, fmt::format("{}: in space revolute, prismatic, cylindrical, universal and spherical "
                                               "joints take coordinates of their own (a {} joint does not)",
                                               what, e.kind));
    return;
  }
  if (e.kind == "rolling") {
    add_rolling(owner, e, name, what);
    return;
  }
  if (is_force_element(e.kind)) {
    add_force_element(owner, e);
    return;
  }
  // A revolute or cylindrical joint keeps its axes parallel: a rotational spring or damper
  // may act between them. Noted before the ends are checked, so that a joint whose end is
  // wrong (reported there) does not make its spring an error too.
  if (e.kind == "revolute" || e.kind == "cylindrical") {
    const auto a = axis_key(owner, e.end1), b = axis_key(owner, e.end2);
    if (a && b) hinged_.insert(std::minmax(*a, *b));
  }
  if (!e.end3.empty()) {
    diags_.error(e.end3_pos, fmt::format("{} has two ends", what));
    return;
  }
  const auto a = end(owner, e.end1, first_is_axis(e.kind), e.end1_pos, what, "joint");
  const auto b = end(owner, e.end2, second_is_axis(e.kind), e.end2_pos, what, "joint");
  if (!a || !b) return;
  if (a->node == b->node) {
    diags_.error(e.end2_pos, fmt::format("{} connects '{}' to itself", what,
                                         a->node == PlanarLibrary::kGround ? std::string("ground") : m_.label(a->node)));
    return;
  }
  const std::string& k = e.kind;
  auto put = [&](const char* suffix, const GiNaC::ex& r) { row(owner, name + "." + suffix, r, e.pos); };
  // The vector forms, in the order listed in spatial_library.hpp.
  if (k == "spherical" || k == "revolute" || k == "universal" || k == "weld") {
    const Vec d = sub(a->p, b->p);
    put("x", d[0]);
    put("y", d[1]);
    put("z", d[2]);
  }
  if (k == "cylindrical" || k == "prismatic" || k == "point_on_line") {
    const Vec d = sub(b->p, a->p);
    put("n1", rigid3d::dot(d, a->n1));
    put("n2", rigid3d::dot(d, a->n2));
  }
  if (k == "point_on_plane") put("normal", rigid3d::dot(a->d, sub(b->p, a->p)));
  if (k == "revolute" || k == "cylindrical" || k == "prismatic") {
    put("align1", rigid3d::dot(b->d, a->n1));
    put("align2", rigid3d::dot(b->d, a->n2));
  }
  if (k == "universal") put("cross", rigid3d::dot(a->d, b->d));
  if (k == "prismatic") put("twist", rigid3d::dot(a->n1, b->n2));
  if (k == "weld") {
    put("rx", rigid3d::dot(a->ey, b->ez));
    put("ry", rigid3d::dot(a->ez, b->ex));
    put("rz", rigid3d::dot(a->ex, b->ey));
  }
  if (!e.option.empty()) {
    const std::string& prefix = m_.nodes[static_cast<std::size_t>(owner)].name;
    add_actuators(e, what, prefix.empty() ? name : prefix + "." + name, *a, *b);
  }
}

void SpatialLibrary::finish() {
  // A rotational element's torque is -dV/dtheta only while its two axes stay parallel
  // (theta' = (omega_b - omega_a) . n needs it: docs/formulation.md "Force elements in space").
  for (const Rotational& r : rotational_) {
    if (hinged_.count(std::minmax(r.a, r.b))) continue;
    diags_.error(r.pos, fmt::format("{}: a rotational {} in space needs a revolute or cylindrical joint between its axes "
                                    "'{}' and '{}' (none joins them), which keeps them parallel",
                                    r.what, r.noun, r.end1, r.end2));
  }
  rotational_.clear();
}

}  // namespace mbsc::model
