// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The validated, indexed subsystem tree. Immutable after build(). Every user
/// expression is already a GiNaC expression over the symbols of `symbols`.
#include <ginac/ginac.h>

#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include "mbsc/diag/diagnostics.hpp"

namespace mbsc::model {

/// Rigid2dNodal: a planar rigid body in nodal (natural) coordinates, thesis Ex 2.6 and
/// Mo2DPack: its points are its nodes, their world positions its coordinates
/// (planar_library.cpp builds its invariants, forces and energy).
/// Rigid3d: a rigid body in space (thesis Ex 2.1, 2.5): mass-centre position and an
/// attitude (unit quaternion or Euler angles), mass-centre velocity in space and angular
/// speeds in the body or the space frame (model/rigid3d.hpp holds its kinematics).
enum class LeafKind { Node, Particle2d, Particle3d, Rigid2d, Custom, Rigid2dNodal, Rigid3d };
const char* to_string(LeafKind kind);
/// Bodies (particle2d, particle3d, rigid2d, rigid2d_nodal) have a mass; all but the nodal
/// one get their inertia forces, gravity and energy from their absolute coordinates
/// automatically (the nodal one gets them from the library as explicit terms).
inline bool is_body(LeafKind kind) {
  return kind == LeafKind::Particle2d || kind == LeafKind::Particle3d || kind == LeafKind::Rigid2d ||
         kind == LeafKind::Rigid2dNodal || kind == LeafKind::Rigid3d;
}
inline bool is_rigid2d(LeafKind kind) { return kind == LeafKind::Rigid2d || kind == LeafKind::Rigid2dNodal; }

/// What a rigid3d leaf adds to its node. Coordinates: x, y, z (mass centre in space), then
/// e0..e3 (unit quaternion, e0 the scalar part) or the three Euler angles phi, theta, psi
/// (rotations about the sequence's first, second and third axis). Speeds: u, v, w (the
/// mass centre's velocity in space), then wx, wy, wz (the angular velocity's components
/// in the body frame, or in the space frame when `space_frame`).
struct Rigid3dData {
  /// "quaternion", the Euler axis sequence ("zyx", "zxz", ...), or "joint": the body is
  /// placed by a spatial joint with coordinates (`joint J : revolute P.a B.a coordinate
  /// q`; prismatic, cylindrical, universal and spherical alike): it has no attitude
  /// coordinates, its attitude is its parent's turned by the joint, R = R_parent Q(q)
  /// (docs/formulation.md "Joint coordinates in space"), and its angular speeds are in
  /// its body frame.
  std::string sequence;
  bool space_frame = false;  // angular speeds in the space frame (else the body frame)
  /// Body-to-space rotation matrix R (row-major 3x3) in the attitude coordinates: a
  /// vector with body components b has space components R b.
  std::vector<GiNaC::ex> rotation;
  /// Inertia tensor about the mass centre in body axes (row-major 3x3, symmetric).
  std::vector<GiNaC::ex> inertia;
  /// Where the mass centre is in the body frame of the points and axes (`com`; default
  /// the origin): a point p is at (x, y, z) + R (p - com).
  std::vector<GiNaC::ex> com{0, 0, 0};
  /// Points in body coordinates, by local name.
  std::map<std::string, std::vector<GiNaC::ex>> points;
  /// Axes: a point and a direction, both in body coordinates (6 entries), by local name.
  std::map<std::string, std::vector<GiNaC::ex>> axes;
  /// sequence "joint" only: the parent body (node index, or -1 for the ground) and the
  /// joint's motion Q(q), a slide then turns: the child's joint point is the parent's
  /// moved by s along `slide_axis`, and its attitude is the parent's turned by
  /// Q = Q_1(q_1) Q_2(q_2) ... about the turns' unit axes, each in the frame the turns
  /// before it leave (at q = 0 every frame is the parent's: the two bodies' frames
  /// coincide there). Axes are unit vectors in body coordinates.
  int joint_parent = -1;
  struct JointTurn {
    std::vector<GiNaC::ex> axis;
    GiNaC::ex angle, rate;  // the coordinate and its speed
  };
  std::vector<JointTurn> joint_turns;
  /// A spherical joint written with a quaternion (`coordinate e0, e1, e2, e3 quaternion`)
  /// has no turns: Q is the matrix of its quaternion e (scalar part first), and the
  /// child's angular velocity relative to its parent, in the child's frame, is the
  /// joint's three speeds; e' = 1/2 e o (0, w_rel). Empty for every other joint.
  std::vector<GiNaC::ex> joint_quaternion, joint_quaternion_speeds;
  std::vector<int> joint_quaternion_coords;  // e's indices in Model::coords
  std::vector<GiNaC::ex> slide_axis;  // empty: no slide
  GiNaC::ex slide, slide_rate;
  std::string joint_name;  // the placing joint, for messages
  /// `rotation` holds kinematic names (Model::kinematic_names), not expressions in the
  /// joint angles of the whole branch (docs/formulation.md, "Named body rotations").
  bool named_rotation = false;
  /// With a named rotation: a direction the joint does not turn (along a revolute axis) is
  /// read as the parent's, so that it carries no trace of this body's angle (a wheel's spin
  /// axis is its frame's). Only in small models: in a tree of many bodies each body's
  /// directions are its own names, so that the rows of the joints below it read its speeds
  /// and not its parent's (what the tree recursion needs).
  bool unturned_from_parent = false;
  bool placed() const { return sequence == "joint"; }
};

/// A generalized coordinate (q0) or quasi-velocity (q1).
struct Variable {
  std::string name;  // full dotted path: "left.upper.theta"
  int node = 0;      // owning node
  GiNaC::symbol sym;
  SourcePos pos;
};

/// A constraint invariant, stored as a residual g == 0.
///   Position: g(t, q0)          Velocity: g(t, q0, q1) (affine in q1 unless nonlinear)
struct Constraint {
  enum class Level { Position, Velocity };
  std::string name;  // label, or "<node>.<level>[k]"
  int node = 0;
  Level level = Level::Position;
  bool nonlinear = false;
  GiNaC::ex residual;
  SourcePos pos;
  /// A coordinate this position row gives explicitly (a joint with a coordinate places
  /// its second body: x_c, y_c, theta_c), taken first by --state minimal; -1 for none.
  int explicit_coordinate = -1;
};

/// A generalized effective force along a quasi-velocity. May contain the acceleration
/// symbols (q1dot) of custom leaves; body inertia and gravity are added by sym.
struct Force {
  int speed = 0;  // index into Model::speeds
  GiNaC::ex value;
  SourcePos pos;
};

/// Coulomb friction on a spatial prismatic joint (`friction mu`, docs/formulation.md
/// "Coulomb friction on a reaction"): the force `force` (a symbol the generated code
/// defines) acts along the slide on the second end, -force on the first; the law
/// force = -mu sign(slide_velocity) |N| closes it, N the reaction of the joint's rows
/// `row1`, `row2` (normal to the slide), |N|^2 = weight1 lambda1^2 + weight2 lambda2^2
/// (the rows' gradients are orthogonal, of squared lengths weight1, weight2).
struct Friction {
  std::string joint;  // the joint's name
  SourcePos pos;      // of the option word `friction`
  GiNaC::symbol force;
  GiNaC::ex mu, slide_velocity, weight1, weight2;
  std::string row1, row2;  // constraint names (Constraint::name)
};

/// A named kinematic intermediate (issue 25): a symbol that stands for `value` (an
/// expression of parameters, coordinates and earlier names) and whose time derivative
/// along the model's kinematics is `rate` (an expression of names, coordinates and
/// speeds). A joint-placed rigid3d body's rotation entries are such names,
/// R = R_parent Q(q), with R' = R [w]x, so that nothing expands into the angles of the
/// joints above it. The generated code defines each once, in this order, before
/// anything reads it (ir::Define, named). Partial derivatives with respect to the
/// coordinates do not see through a name: expand_kinematic_names first.
struct KinematicName {
  GiNaC::symbol sym;
  GiNaC::ex value;
  GiNaC::ex rate;
};

struct NamedExpr {
  std::string name;
  GiNaC::ex value;
  SourcePos pos;
};

/// A component instance's formal parameter: a symbol bound to the argument expression.
struct Formal {
  GiNaC::symbol sym;
  GiNaC::ex value;
};

/// One node of the subsystem tree.
struct Node {
  std::string name;  // dotted path; "" for the root
  SourcePos pos;
  int parent = -1;
  std::vector<int> children;
  LeafKind kind = LeafKind::Node;
  std::string component;      // component name when this node instantiates one, else ""
  int instance_of = -1;       // earlier node instantiating the same component, or -1
  std::vector<int> coords;    // own coordinates (leaf variables or extra ⊕ coordinates)
  std::vector<int> speeds;    // own quasi-velocities
  std::vector<int> constraints;  // constraints declared at this node (leaf or ⊕ invariants)
  std::vector<int> independent;  // chosen independent speeds (empty: automatic)
  SourcePos independent_pos;
  /// Other independent sets (`alternative` statements), for run-time re-selection:
  /// partition k > 0 of the model uses alternatives[k - 1] here when it exists.
  std::vector<std::vector<int>> alternatives;
  std::vector<SourcePos> alternative_pos;
  GiNaC::ex mass, inertia;    // bodies (either may be 0: sym/massless_check.hpp)
  SourcePos mass_pos, inertia_pos;
  GiNaC::ex kinetic, potential;  // user-given energy terms (0 when absent)
  bool has_kinetic = false;
  Rigid3dData rigid3d;  // rigid3d leaves only
};

/// The whole model. Arrays are index-aligned; nodes are stored in post-order
/// (children before parents, root last).
struct Model {
  std::string name;
  SourcePos name_pos;  // of NAME in `model NAME`
  /// Parameters that `for` bounds or indices used (parse::File::structural): derived
  /// and generated frozen at these values.
  std::map<std::string, double> structural;
  std::string source_text_hash;
  std::vector<Node> nodes;
  std::vector<Variable> coords;   // q0
  std::vector<Variable> speeds;   // q1
  std::vector<GiNaC::symbol> speed_dots;  // q1dot, aligned with speeds
  /// Explicit kinematic transformations: d/dt coords[i] = coord_rates[i](t, q0, q1).
  std::vector<GiNaC::ex> coord_rates;
  std::vector<Constraint> constraints;
  /// Kinematic names in definition order (each value reads only earlier ones).
  std::vector<KinematicName> kinematic_names;
  std::vector<Force> forces;
  std::vector<Friction> frictions;  // closed in the generated code, never an input
  std::vector<NamedExpr> outputs;
  bool output_energy = false;
  std::vector<Variable> params;
  std::vector<double> param_defaults;
  std::vector<Variable> inputs;
  GiNaC::symbol time{"t"};
  std::vector<GiNaC::ex> gravity;  // 2 or 3 components, empty when none
  SourcePos gravity_pos;           // of the `gravity` statement
  std::map<std::string, Formal> formals;  // by symbol name
  /// Symbols given with `latex NAME "..."` for `mbsc print --latex`: full dotted name of
  /// a parameter, input, coordinate or speed (or "t") -> its LaTeX text.
  std::map<std::string, std::string> latex_symbols;
  /// `initial PATH = expr`: starting values for `mbsc run` (full dotted name of a
  /// coordinate or speed -> a constant expression of the parameters), in source order.
  std::vector<NamedExpr> initial_values;
  /// `initial guess PATH = expr`: where assembly starts for a coordinate it solves for
  /// (which branch of a closed loop the run starts on), not a fixed value.
  std::vector<NamedExpr> initial_guesses;
  int root() const { return static_cast<int>(nodes.size()) - 1; }
  /// A node's name for messages: its dotted path; the root is the model itself, named
  /// as `model NAME` names it.
  std::string label(int n) const {
    if (!nodes[n].name.empty()) return nodes[n].name;
    return name.empty() ? "the model" : name;
  }
  /// Number of partitions (independent sets) the model declares: 1 + the most
  /// `alternative` statements at any node.
  int partition_count() const {
    std::size_t k = 0;
    for (const auto& n : nodes) k = std::max(k, n.alternatives.size());
    return static_cast<int>(k) + 1;
  }
};

/// e with every kinematic name replaced by its value, recursively (the fully expanded
/// form the old path wrote): the fallback for partial derivatives with respect to the
/// coordinates and for evaluators that do not bind the names.
GiNaC::ex expand_kinematic_names(const Model& m, const GiNaC::ex& e);
/// Every kinematic name -> its full expansion (what expand_kinematic_names substitutes),
/// for callers that expand many expressions.
GiNaC::exmap kinematic_name_values(const Model& m);

}  // namespace mbsc::model
