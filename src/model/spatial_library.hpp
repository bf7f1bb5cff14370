// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The spatial joints of the library level (private to src/model). Every joint is a list
/// of a few vector forms (thesis sections 2.3-2.4), each a handful of position rows a
/// user could write by hand:
///   * coincide      P_a - P_b = 0                          (3 rows: .x .y .z)
///   * on_line       (P_b - A) . n1 = (P_b - A) . n2 = 0    (2 rows: .n1 .n2)
///   * on_plane      d . (P_b - A) = 0                      (1 row:  .normal)
///   * parallel      d_b . n1 = d_b . n2 = 0                (2 rows: .align1 .align2)
///   * perpendicular d_a . d_b = 0                          (1 row:  .cross)
///   * no_twist      n1_a . n2_b = 0                        (1 row:  .twist)
///   * same_axes     y_a . z_b = z_a . x_b = x_a . y_b = 0  (3 rows: .rx .ry .rz)
/// with A, d the point and unit-free direction of the first end's axis and n1, n2 two
/// directions normal to d, fixed in that axis's body. A joint kind is only its list:
/// spherical = coincide; revolute = coincide + parallel; universal = coincide +
/// perpendicular; cylindrical = on_line + parallel; prismatic = cylindrical + no_twist;
/// weld = coincide + same_axes; point_on_line = on_line; point_on_plane = on_plane.
///
/// Force elements (spatial_forces.cpp): joint actuators (revolute torque, prismatic force,
/// cylindrical both), springs and dampers between two points, rotational springs and
/// dampers about a revolute axis. Each is a force F at a point P and a torque tau on a
/// body, turned into generalized forces once, by the virtual power:
/// Q_s = (d v_P / d s) . F + (d omega / d s) . tau over the body's speeds s.
///
/// A disc rolling on a ground plane (`rolling PLANE DISC radius r`, spatial_rolling.cpp)
/// adds one position row (.contact) and two velocity rows (.no_slip, .no_side_slip).
/// A sphere rolling on a surface z = gamma(x, y) (`rolling_sphere BODY radius r surface
/// (gamma)`, spatial_rolling_sphere.cpp) adds three position rows and two velocity rows.
#include <ginac/ginac.h>

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/model/model.hpp"
#include "planar_library.hpp"

namespace mbsc::model {

class SpatialLibrary {
 public:
  using Vec = std::vector<GiNaC::ex>;
  SpatialLibrary(Model& m, Diagnostics& diags);

  /// Ground points (x, y, z) and axes (px, py, pz, dx, dy, dz) in space.
  void add_ground_point(const std::string& name, const Vec& p, const SourcePos& pos);
  void add_ground_axis(const std::string& name, const Vec& v, const SourcePos& pos);
  /// A point or axis whose declaration failed (reported): a joint naming it says no more.
  void add_failed(int node, const std::string& name) { failed_.insert({node, name}); }
  /// A planar ground point or axis (two components): a spatial joint naming it is told so.
  void add_planar_ground_name(const std::string& name) { planar_ground_.insert(name); }
  bool has_ground(const std::string& name) const { return ground_points_.count(name) || ground_axes_.count(name); }

  /// Whether a joint belongs here: a spatial-only kind, or an end on a rigid3d body or on
  /// a spatial ground point or axis.
  bool claims(int owner, const PlanarLibrary::Element& e) const;
  void add_element(int owner, const PlanarLibrary::Element& e);

  /// Springs and dampers (kinds spring, damper, rotational_spring, rotational_damper).
  static bool is_force_element(const std::string& kind);

  /// The joint kinds this library knows.
  static const std::vector<std::string>& kinds();

  /// The joint kinds that take coordinates of their own in space and place their second
  /// body (revolute, prismatic, cylindrical, universal, spherical), and how many.
  static bool places(const std::string& kind);
  static int coordinate_count(const std::string& kind);

  /// Before pass B: body `child`, placed by the joint e with coordinates, gets its
  /// attitude, R_parent Q(q) (spatial_joint_coordinate.cpp). Later when the
  /// parent is itself placed and not yet done; Failed when it cannot be (reported here,
  /// or at the joint in pass B by add_element).
  enum class Placed { Done, Later, Failed };
  Placed place(int owner, const PlanarLibrary::Element& e, int child);
  /// Whether the body a joint with coordinates places under `parent`, turning it by
  /// `turns` rotations, gets a named rotation (docs/formulation.md, "Named body
  /// rotations").
  bool names_rotation(int parent, std::size_t turns) const;
  static constexpr int kGroundJointsWritten = 4;
  /// How many turns a joint kind with coordinates makes (revolute 1, spherical 3, ...).
  static int turn_count(const std::string& kind);
  /// How many turns a placed body's joint makes (a quaternion counts three).
  static std::size_t turn_count(const Rigid3dData& data);
  /// How many turns the joints with coordinates of the whole model make (set before the
  /// first `place`): above kGroundJointsWritten every placed body is named, so that each
  /// body's rows read its parent's speeds alone (what the tree recursion needs).
  void expect_turns(int count) { turns_ = count; }
  /// Replaces a placed body's rotation by kinematic names (Model::kinematic_names):
  /// R = R_parent Q(n, q) entry by entry, with R' = R [w]x.
  void name_rotation(int child);

  /// After every element: each rotational spring or damper must have its two axes joined
  /// by a revolute or cylindrical joint (reported at the element otherwise).
  void finish();

 private:
  int turns_ = 0;
  mutable GiNaC::exmap defaults_;        // parameter -> default, for at_defaults
  mutable std::size_t defaults_size_ = static_cast<std::size_t>(-1);
  struct End {  // a resolved point or axis, in space
    int node = PlanarLibrary::kGround;
    Vec p;          // the point (the axis's point)
    Vec d, n1, n2;  // axis: its direction and two normals fixed in the body (empty for a point)
    GiNaC::ex d_length;  // axis: |d| in the body frame (constant)
    Vec ex, ey, ez; // the body's axes in space (weld)
  };
  std::optional<int> body(int owner, const std::string& path) const;
  /// The end named `path`; `axis` asks for an axis (else a point).
  /// `element` is the element's noun (joint, spring, damper) for the messages.
  std::optional<End> end(int owner, const std::string& path, bool axis, const SourcePos& pos, const std::string& what,
                         const char* element);
  /// An axis as a body and a name, for matching a rotational element to its joint.
  using AxisKey = std::pair<int, std::string>;
  std::optional<AxisKey> axis_key(int owner, const std::string& path) const;
  double at_defaults(const GiNaC::ex& e) const;
  /// What in e changes with the motion (t, an input, a speed or a coordinate other than
  /// those in `except`), named, or "": what a radius, a plane or a surface of the rolling
  /// joints may not read (model::varying_part).
  std::string varies(const GiNaC::ex& e, const std::vector<int>& except = {}) const;
  /// Two directions normal to the body-frame direction d (in the body frame).
  std::pair<Vec, Vec> normals(const Vec& d) const;
  void row(int owner, const std::string& name, const GiNaC::ex& residual, const SourcePos& pos,
           Constraint::Level level = Constraint::Level::Position, int explicit_coordinate = -1);
  /// A joint with coordinates: the rows that place its second body
  /// (spatial_joint_coordinate.cpp).
  void add_placement(int owner, const PlanarLibrary::Element& e, const std::string& name, const std::string& what);
  /// The body-frame direction (dx, dy, dz) of axis `path` (ground or rigid3d body) and its
  /// body, without reporting (pass B's end() reports what is wrong).
  std::optional<std::pair<int, Vec>> axis_direction(int owner, const std::string& path) const;
  /// The body of point `path`, without reporting.
  std::optional<int> point_body(int owner, const std::string& path) const;
  /// Whether e's coordinates are as many as its kind takes (and a spherical joint's
  /// sequence is given and valid); reported at the element otherwise.
  bool coordinates_fit(const PlanarLibrary::Element& e, const std::string& what);
  /// Whether the child's axis c points as the parent's d in body coordinates (reported
  /// otherwise): a joint with coordinates starts where the two frames coincide.
  bool same_direction(const PlanarLibrary::Element& e, const std::string& what, const Vec& d, const Vec& c, int parent,
                      int child);
  /// d over its length (exactly d when that is 1 symbolically).
  static Vec unit(const Vec& d);
  /// A disc (an axis of a rigid3d body: its centre and spin axis) rolling without slip
  /// on a plane of the ground (spatial_rolling.cpp).
  void add_rolling(int owner, const PlanarLibrary::Element& e, const std::string& name, const std::string& what);
  /// A sphere (a rigid3d body) rolling without slip on a surface z = gamma(x, y) of the
  /// ground (spatial_rolling_sphere.cpp).
  void add_rolling_sphere(int owner, const PlanarLibrary::Element& e, const std::string& name, const std::string& what);

  // ---- force elements (spatial_forces.cpp) ----
  /// The unit direction in space of an end's axis: R d / |d| with |d| taken in the body
  /// frame (a homogeneous quaternion matrix scales R d by |e|^2).
  Vec unit_axis(const End& a) const;
  /// Velocity in space of the material point of `node` that is at P (space) now, and the
  /// node's angular velocity in space (zero for the ground).
  Vec point_velocity(int node, const Vec& P) const;
  Vec angular_velocity(int node) const;
  /// Generalized forces of a force F acting at the point P (space) of `node` and a torque
  /// tau (space) on it: Q_s = (d v_P / d s) . F + (d omega / d s) . tau.
  void apply_wrench(int node, const Vec& P, const Vec& F, const Vec& tau, const SourcePos& pos);
  /// A joint's actuators (options torque / force); false when one does not apply (reported).
  /// `rows`: the joint's full name, which its rows' names begin with.
  bool add_actuators(const PlanarLibrary::Element& e, const std::string& what, const std::string& rows, const End& a,
                     const End& b);
  /// `friction mu` on a prismatic joint: the friction force along the slide, a symbol the
  /// generated code defines from the joint's normal reaction (Model::frictions).
  void add_friction(const std::string& what, const std::string& rows, const GiNaC::ex& mu, const SourcePos& pos, const End& a,
                    const End& b);
  void add_force_element(int owner, const PlanarLibrary::Element& e);

  Model& m_;
  Diagnostics& diags_;
  std::map<std::string, Vec> ground_points_, ground_axes_;
  std::set<std::pair<int, std::string>> failed_;
  std::set<std::string> planar_ground_;
  // Axis pairs joined by a revolute or cylindrical joint (ordered pair, smaller first),
  // and the rotational springs and dampers waiting for finish() to find theirs.
  std::set<std::pair<AxisKey, AxisKey>> hinged_;
  struct Rotational {
    std::string what, noun, end1, end2;
    SourcePos pos;
    AxisKey a, b;
  };
  std::vector<Rotational> rotational_;
  int unnamed_ = 0;
};

}  // namespace mbsc::model
