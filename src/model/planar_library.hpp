// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The planar library level of the model language (private to src/model): points, axes
/// and mass centres in body coordinates, the ground, joints, springs and dampers. Each
/// element expands into what a user could write by hand at the invariant level:
///   * a joint into position constraints, derived from its vector form (a revolute joint
///     is r_Q - r_P = 0, a prismatic one n . (r_Q - r_A) = 0 plus a relative angle, a
///     weld both), so a new joint type is a new vector constraint, not new derivatives;
///   * an actuator, spring or damper into generalized forces on the bodies' speeds, by the
///     partial velocities of the points it acts at (Q = (d v_P / d q1)^T F), and a spring
///     into a potential-energy term.
/// Body coordinates of a rigid2d body are (x, y, theta) of its mass centre (the absolute
/// parametrization of the AMESim paper); a point p given in the body frame, with the mass
/// centre at c in that frame, is at (x, y) + R(theta) (p - c).
#include <ginac/ginac.h>

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/model/model.hpp"

namespace mbsc::model {

class PlanarLibrary {
 public:
  PlanarLibrary(Model& m, Diagnostics& diags);

  /// Declarations. `node` is the body's node, or kGround.
  static constexpr int kGround = -1;
  void add_point(int node, const std::string& name, const GiNaC::ex& ex, const GiNaC::ex& ey, const SourcePos& pos);
  void set_com(int node, const GiNaC::ex& ex, const GiNaC::ex& ey, const SourcePos& pos);
  void add_axis(int node, const std::string& name, const GiNaC::ex& px, const GiNaC::ex& py, const GiNaC::ex& dx,
                const GiNaC::ex& dy, const SourcePos& pos);
  /// A point or axis whose declaration failed (its error is reported): a joint that
  /// names it reports nothing more, instead of a misleading "unknown point".
  void add_failed(int node, const std::string& name);

  /// A joint, spring or damper stated at node `owner` (its constraints belong there).
  struct Element {
    std::string name;        // "" for an unnamed joint: one is made up
    std::string kind;        // revolute | prismatic | pin_in_slot | weld | gear | rolling | rolling_inside | spring | damper |
                             // rotational_spring | rotational_damper | knife_edge
    SourcePos pos, kind_pos;
    std::string end1, end2;  // paths as written (knife_edge: the body, then its point's name or "")
    SourcePos end1_pos, end2_pos;
    std::string end3;        // knife_edge: the name of the body's axis along the blade, or ""
    SourcePos end3_pos;
    std::string option;      // joints: torque | force | angle | ratio | radius ("" when absent)
    SourcePos option_pos;
    std::optional<GiNaC::ex> value;   // the option's value; spring stiffness; damper coefficient
    std::optional<GiNaC::ex> length;  // spring rest length (rotational: rest angle)
    std::string option2;              // joints: a second option (rolling_inside: ring) or ""
    SourcePos option2_pos;
    std::optional<GiNaC::ex> value2;
    int coordinate = -1;  // `coordinate q, ...`: the joint's first own coordinate (index), or -1
    int coordinate_speed = -1;  // and its rate's speed (index)
    SourcePos coordinate_pos;
    std::vector<int> coordinates, coordinate_speeds;  // all of them, in order (spatial joints take up to three)
    std::vector<SourcePos> coordinate_positions;
    std::string sequence;  // `euler SEQ` (a spherical joint's angles), or ""
    SourcePos sequence_pos;
    std::vector<int> contact;  // rolling_sphere: the contact point's coordinates (xc, yc), indices
  };
  void add_element(int owner, const Element& e);
  /// A rigid2d_nodal body, once its points, mass centre, mass and inertia are known: its
  /// rigidity invariants, inertia and gravity forces, and energy (thesis Ex 2.6).
  void finish_nodal(int node);

 private:
  /// e at the parameters' defaults, in floating point (no exact folding); NaN when it
  /// does not evaluate to a finite real number. For checks of geometry only.
  double at_defaults(const GiNaC::ex& e) const;
  mutable GiNaC::exmap defaults_;  // each parameter's default, for at_defaults
  struct Frame;  // a body's pose: origin of its mass centre, angle, speeds
  struct Point {
    int node;
    GiNaC::ex ex, ey;
    SourcePos pos = {};  // where it is declared (line 0: built in)
  };
  struct Axis {
    int node;
    GiNaC::ex px, py, dx, dy;
    SourcePos pos = {};
  };
  struct Located {  // a resolved point: its body and world position
    int node;
    GiNaC::ex x, y;
  };

  std::optional<Located> point(int owner, const std::string& path, const SourcePos& pos);
  std::optional<std::pair<Located, std::pair<GiNaC::ex, GiNaC::ex>>> axis(int owner, const std::string& path,
                                                                         const SourcePos& pos);
  /// The body a path names, seen from node `owner` (inner scopes first), or kGround.
  std::optional<int> body(int owner, const std::string& path) const;
  template <class Decl>
  const Decl* element_of(int owner, const std::string& path, const std::map<std::string, Decl>& table, int& node) const;
  std::pair<GiNaC::ex, GiNaC::ex> world(int node, const GiNaC::ex& px, const GiNaC::ex& py) const;
  std::optional<GiNaC::ex> angle(int node) const;
  /// A body-frame vector turned into the world frame (identity for the ground and particles).
  std::pair<GiNaC::ex, GiNaC::ex> rotate(int node, const GiNaC::ex& dx, const GiNaC::ex& dy) const;
  /// The speed that is the body's angular velocity (rigid bodies only).
  std::optional<int> omega_speed(int node) const;
  /// A nodal body's nodes: body coordinates, world coordinates and speeds (declaration order).
  struct Node2 {
    GiNaC::ex bx, by;
    GiNaC::ex x, y, u, v;
  };
  std::vector<Node2> nodes_of(int node) const;
  std::size_t node_count(int node) const;  // a nodal body's points
  bool nodal(int node) const;
  /// theta_b - theta_a (continuous where a nodal body is involved) and the residual of
  /// theta_b - theta_a = rel, for joints that lock a relative angle.
  GiNaC::ex relative_angle(int a, int b) const;
  GiNaC::ex angle_residual(int a, int b, const GiNaC::ex& rel) const;
  /// World velocity of the material point of `node` at world position (x, y).
  std::pair<GiNaC::ex, GiNaC::ex> velocity(int node, const GiNaC::ex& x, const GiNaC::ex& y) const;
  /// Generalized forces of a world force (fx, fy) acting at world (x, y) on `node`.
  void apply_force(int node, const GiNaC::ex& x, const GiNaC::ex& y, const GiNaC::ex& fx, const GiNaC::ex& fy,
                   const SourcePos& pos);
  void apply_torque(int node, const GiNaC::ex& tau, const SourcePos& pos);
  void add_constraint(int owner, const std::string& name, const GiNaC::ex& residual, const SourcePos& pos,
                      Constraint::Level level = Constraint::Level::Position, int explicit_coordinate = -1);
  /// A revolute or prismatic joint with a coordinate of its own (relative_joint.cpp): the
  /// rows that place the second body from the first and the joint coordinate, each
  /// explicit in one of that body's coordinates. False when the ends do not allow it
  /// (reported).
  bool add_relative_rows(int owner, const Element& e, const std::string& name, const std::string& what, const Located& p1,
                         const Located& p2, const GiNaC::ex& rel);
  struct Placement {  // a body placed by a joint with a coordinate
    int parent;
    std::string joint;
    SourcePos pos;
  };
  std::map<int, Placement> placed_;  // child body -> what places it
  void add_rotational(int owner, const Element& e, const std::string& name, const std::string& what);
  void add_rolling(int owner, const Element& e, const std::string& name, const std::string& what);
  void add_rolling_inside(int owner, const Element& e, const std::string& name, const std::string& what);
  void add_velocity_constraint(int owner, const std::string& name, const GiNaC::ex& residual, const SourcePos& pos);
  /// A blade on a rigid body (knife_edge.cpp): no velocity across it at its point.
  void add_knife_edge(int owner, const Element& e, const std::string& name, const std::string& what);

  Model& m_;
  Diagnostics& diags_;
  std::map<std::string, Point> points_;   // "crank.A", "ground.origin"
  std::map<std::string, Axis> axes_;      // "ground.x_axis", "rocker.slot"
  std::set<std::string> failed_;          // points and axes whose declaration failed
  bool failed(int owner, const std::string& path) const;
  /// " (as a point at 3:5)": what already holds the name `full`, for "declared twice".
  std::string first_declared(const std::string& full, const SourcePos& here) const;
  /// " (did you mean 'ground.origin'?)" for an unknown point or axis `path` written at
  /// `owner`: the names of the body it names, or every one when that body is unknown too.
  std::string suggest_element(int owner, const std::string& path, bool point) const;
  std::map<int, std::pair<GiNaC::ex, GiNaC::ex>> com_;  // rigid2d node -> mass centre in body coordinates
  int unnamed_ = 0;
};

}  // namespace mbsc::model
