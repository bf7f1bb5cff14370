// SPDX-License-Identifier: GPL-2.0-or-later
// The model text of an imported URDF (docs/urdf.md): a header saying where it came from
// and what of the file it does not use, a rigid3d body per welded group of links, a
// joint with its coordinate per moving joint (an input as its torque or force), mimic
// rows, and gravity along -z. Names are the URDF's, made into model identifiers.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "../parse/lexer.hpp"
#include "mbsc/import/urdf_import.hpp"
#include "urdf_tree.hpp"

namespace mbsc::import {

namespace {

/// Shortest text that reads back as x (no "-0").
std::string num(double x) {
  if (std::abs(x) < std::numeric_limits<double>::min()) return "0";  // no subnormals in the language
  return fmt::format("{}", x);
}

std::string vec(const Vec3& v) { return fmt::format("({}, {}, {})", num(v[0]), num(v[1]), num(v[2])); }

/// An angle as written, or as a multiple of pi/2 when it is one (frame_math's rule).
std::string angle(double a) {
  if (!is_quarter_turn(a)) return num(a);
  const long k = std::lround(a / (M_PI / 2));
  if (k == 0) return "0";
  if (k % 2 == 0) return k == 2 ? "pi" : k == -2 ? "-pi" : fmt::format("{}*pi", k / 2);
  return k == 1 ? "pi/2" : k == -1 ? "-pi/2" : fmt::format("{}*pi/2", k);
}

/// Model identifiers for URDF names: other characters become '_', a leading digit gets
/// one before it, keywords and names taken get a number after them.
class Names {
 public:
  Names() {
    for (const char* r : {"pi", "t", "ground", "g", "energy", "x", "y", "z", "sin", "cos", "tan", "exp", "log", "sqrt", "abs",
                          "sign", "asin", "acos", "atan", "atan2", "sinh", "cosh", "tanh", "pow", "min", "max"})
      taken_.insert(r);
  }
  /// A coordinate's name c such that c and its rate's c_dot are both free; claims both.
  std::string claim_coordinate(const std::string& wanted) {
    const std::string base = identifier(wanted);
    std::string name = base;
    for (int k = 2; !free(name) || !free(name + "_dot"); ++k) name = fmt::format("{}_{}", base, k);
    taken_.insert(name);
    taken_.insert(name + "_dot");
    return name;
  }

  std::string claim(const std::string& wanted) {
    const std::string s = identifier(wanted);
    std::string name = s;
    for (int k = 2; !free(name); ++k) name = fmt::format("{}_{}", s, k);
    taken_.insert(name);
    return name;
  }

 private:
  bool free(const std::string& name) const { return !taken_.count(name) && !parse::is_keyword(name); }

  static std::string identifier(const std::string& wanted) {
    std::string s;
    for (const char c : wanted) s += std::isalnum(static_cast<unsigned char>(c)) || c == '_' ? c : '_';
    if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0]))) s = "_" + s;
    return s;
  }

  std::set<std::string> taken_;
};

/// Two unit vectors that span the plane normal to the unit vector n, exactly for the
/// coordinate axes.
std::pair<Vec3, Vec3> plane_basis(const Vec3& n) {
  int k = 0;  // the coordinate axis least along n
  for (int i = 1; i < 3; ++i)
    if (std::abs(n[i]) < std::abs(n[k])) k = i;
  Vec3 e{0, 0, 0};
  e[k] = 1;
  Vec3 a = cross(n, e);
  a = scale(1 / std::sqrt(dot(a, a)), a);
  return {a, cross(n, a)};
}

std::string inertia_text(const Mat3& I) {
  return fmt::format("({}, {}, {}, {}, {}, {})", num(I[0][0]), num(I[1][1]), num(I[2][2]), num(I[0][1]), num(I[0][2]),
                     num(I[1][2]));
}

class Writer {
 public:
  Writer(const std::string& path, const UrdfDocument& doc, const RobotTree& tree, const UrdfImportOptions& options)
      : path_(path), doc_(doc), tree_(tree), options_(options) {}

  std::string text() {
    name_everything();
    header();
    out_ << fmt::format("model {}\n\nparameter g = 9.81\ngravity (0, 0, -g)\n", model_name_);
    std::vector<std::string> inputs;
    for (const auto& name : input_names_)
      if (!name.empty()) inputs.push_back(name);
    if (!inputs.empty()) {
      out_ << "\n# One input per actuated joint: a torque about a revolute joint's axis, a force along a\n"
              "# prismatic one's (M q'' = h + tau).\n";
      out_ << fmt::format("input {}\n", fmt::join(inputs, ", "));
    }
    ground();
    for (std::size_t b = 1; b < tree_.bodies.size(); ++b) body(b);
    if (tree_.bodies[0].free) body(0);
    joints();
    mimics();
    independent();
    initials();
    out_ << "\noutput energy\n";
    return out_.str();
  }

 private:
  const UrdfJoint& urdf(const RobotJoint& j) const { return doc_.joints[j.urdf]; }

  void name_everything() {
    model_name_ = names_.claim(doc_.robot_name);
    for (const auto& b : tree_.bodies) body_names_.push_back(b.ground ? "ground" : names_.claim(b.name));
    for (std::size_t k = 0; k < tree_.joints.size(); ++k) {
      const RobotJoint& j = tree_.joints[k];
      const UrdfJoint& u = urdf(j);
      joint_names_.push_back(names_.claim(u.name));
      std::vector<std::string> q;
      std::vector<std::string> parts;
      if (u.type == "planar") {
        for (const char* s : {"_a", "_b", "_turn"}) q.push_back(names_.claim_coordinate("q_" + u.name + s));
        for (const char* s : {"_slide1", "_slide2", "_a", "_b"}) parts.push_back(names_.claim(u.name + s));
      } else if (u.type != "floating") {
        q.push_back(names_.claim_coordinate("q_" + u.name));
      }
      coordinates_.push_back(q);
      planar_parts_.push_back(parts);
      input_names_.push_back(options_.joint_inputs && !j.mimics && has_one_coordinate(u.type) ? names_.claim("tau_" + u.name)
                                                                                               : "");
    }
  }

  void header() {
    out_ << fmt::format("# Robot '{}', imported from {} by `mbsc import` (docs/urdf.md).\n", printable(doc_.robot_name),
                        printable(std::filesystem::path(path_).filename().string()));
    out_ << "#\n# Each body is a link with the links welded to it by fixed joints merged in. Its axes are\n"
            "# the link's frame turned to the world's directions at the zero pose (every joint\n"
            "# coordinate 0): points, axes, mass centres and inertia tensors below are the URDF's turned\n"
            "# so, measured from the link's origin. Each moving joint's coordinate q_JOINT is URDF's\n"
            "# joint position (angle or slide from that pose).\n";
    // What the file holds that the model does not use.
    int visuals = 0, collisions = 0, limits = 0, friction = 0, safety = 0, calibration = 0;
    for (const auto& l : doc_.links) visuals += l.visuals, collisions += l.collisions;
    for (const auto& j : doc_.joints) {
      limits += !j.limit.empty();
      friction += j.friction > 0;
      safety += j.safety;
      calibration += j.calibration;
    }
    int damped = 0, undamped = 0;  // damping on the joints that take it; on fixed, floating, planar ones
    for (const auto& j : doc_.joints) (has_one_coordinate(j.type) ? damped : undamped) += j.damping > 0;
    std::vector<std::string> unused;
    auto count = [&](int n, const char* what) {
      if (n > 0) unused.push_back(fmt::format("{} {}", n, what));
    };
    count(visuals, "<visual> (meshes and shapes)");
    count(collisions, "<collision>");
    count(limits, "joint <limit> (listed at each joint)");
    count(friction, "joint Coulomb <friction> (mbsc's friction acts on spatial prismatic and cylindrical joints "
                    "without coordinates; listed at each joint)");
    count(undamped, "joint damping on fixed, floating or planar joints");
    count(safety, "<safety_controller>");
    count(calibration, "<calibration>");
    count(doc_.transmissions, "<transmission> (each moving joint has an input instead)");
    count(doc_.gazebo, "<gazebo>");
    count(doc_.materials, "<material>");
    for (const auto& e : doc_.other_elements) unused.push_back("<" + printable(e) + ">");
    if (!unused.empty()) {
      out_ << "#\n# Not used:\n";
      for (const auto& u : unused) out_ << "#   " << u << "\n";
    }
    if (damped > 0)
      out_ << fmt::format("# Joint damping ({} joint{}) acts as a torque or force -c q' on the joint.\n", damped,
                          damped == 1 ? "" : "s");
    const RobotBody& root = tree_.bodies[0];
    out_ << fmt::format("#\n# Root link '{}': {}.\n", printable(root.link),
                        root.free ? "a free body (the floating base), attitude a unit quaternion"
                                  : "fixed to the ground (import with --floating-base for a free base)");
    if (root.ground && root.has_inertial) out_ << "# Its inertia and that of the links welded to it do not move and are not used.\n";
    out_ << "\n";
  }

  void welded_comment(const RobotBody& b) {
    for (const std::size_t k : b.welded) {
      const UrdfJoint& j = doc_.joints[k];
      out_ << fmt::format("# + link '{}' (fixed joint '{}')\n", printable(j.child), printable(j.name));
    }
  }

  /// The axes statements of body b: its own joint's (at its origin) and its children's.
  std::string joint_axes(std::size_t b) const {
    std::string axes;
    for (std::size_t k = 0; k < tree_.joints.size(); ++k) {
      const RobotJoint& j = tree_.joints[k];
      const std::string& type = urdf(j).type;
      if (type == "floating") continue;
      // A planar joint's parent end slides along the plane's first direction.
      const Vec3 parent_direction = type == "planar" ? plane_basis(j.axis).first : j.axis;
      if (j.child == b) axes += fmt::format("  axis {} (0, 0, 0) {}\n", joint_names_[k], vec(j.axis));
      if (j.parent == b) axes += fmt::format("  axis {} {} {}\n", joint_names_[k], vec(j.point), vec(parent_direction));
    }
    return axes;
  }

  void ground() {
    const std::string axes = joint_axes(0);
    if (!tree_.bodies[0].ground || axes.empty()) return;
    out_ << fmt::format("\n# The root link '{}' is the ground.\n", printable(tree_.bodies[0].link));
    welded_comment(tree_.bodies[0]);
    out_ << "ground {\n" << axes << "}\n";
  }

  void body(std::size_t b) {
    const RobotBody& body = tree_.bodies[b];
    out_ << fmt::format("\n# link '{}'", printable(body.link));
    if (body.name != body.link) out_ << fmt::format(" (a massless anchor: the body is named after '{}')", printable(body.name));
    if (!body.rpy_path.empty()) out_ << fmt::format(" (axes turned by the rpy of joint{} {})", body.rpy_path.size() == 1 ? "" : "s",
                                                    printable(fmt::format("{}", fmt::join(body.rpy_path, ", "))));
    out_ << "\n";
    welded_comment(body);
    out_ << fmt::format("body {} : rigid3d {{\n", body_names_[b]);
    out_ << fmt::format("  mass {}\n", num(body.mass));
    out_ << fmt::format("  inertia {}\n", inertia_text(body.inertia));
    if (body.com != Vec3{0, 0, 0}) out_ << fmt::format("  com {}\n", vec(body.com));
    out_ << joint_axes(b) << "}\n";
    // A planar joint's child hangs from two massless carriages, one per slide.
    for (std::size_t k = 0; k < tree_.joints.size(); ++k) {
      const RobotJoint& j = tree_.joints[k];
      if (j.child != b || urdf(j).type != "planar") continue;
      const auto [a, c] = plane_basis(j.axis);
      const auto& parts = planar_parts_[k];
      out_ << fmt::format("body {} : rigid3d {{  # massless: carries the first slide\n  mass 0\n  inertia (0, 0, 0)\n"
                          "  axis in (0, 0, 0) {}\n  axis out (0, 0, 0) {}\n}}\n",
                          parts[0], vec(a), vec(c));
      out_ << fmt::format("body {} : rigid3d {{  # massless: carries the second slide\n  mass 0\n  inertia (0, 0, 0)\n"
                          "  axis in (0, 0, 0) {}\n  axis out (0, 0, 0) {}\n}}\n",
                          parts[1], vec(c), vec(j.axis));
    }
  }

  std::string actuator(std::size_t k) {
    const RobotJoint& j = tree_.joints[k];
    const UrdfJoint& u = urdf(j);
    std::string value = input_names_[k];
    if (u.damping > 0) value += fmt::format("{}{}*{}_dot", value.empty() ? "-" : " - ", num(u.damping), coordinates_[k][0]);
    if (value.empty()) return "";
    return fmt::format(" {} {}", u.type == "prismatic" ? "force" : "torque", value);
  }

  void joints() {
    out_ << "\n";
    for (std::size_t k = 0; k < tree_.joints.size(); ++k) {
      const RobotJoint& j = tree_.joints[k];
      const UrdfJoint& u = urdf(j);
      const std::string& p = body_names_[j.parent];
      const std::string& c = body_names_[j.child];
      const std::string& n = joint_names_[k];
      std::vector<std::string> notes;
      if (u.rpy != Vec3{0, 0, 0}) notes.push_back(fmt::format("rpy ({}, {}, {})", angle(u.rpy[0]), angle(u.rpy[1]), angle(u.rpy[2])));
      if (!u.limit.empty()) notes.push_back("limit: " + u.limit);
      if (u.friction > 0) notes.push_back(fmt::format("friction {} not modelled", num(u.friction)));
      if (!notes.empty()) out_ << fmt::format("# {}: {}\n", printable(u.name), fmt::join(notes, "; "));
      if (u.type == "floating") {
        out_ << fmt::format("# joint '{}' (floating): '{}' is a free body\n", printable(u.name), printable(u.child));
      } else if (u.type == "planar") {
        const auto& q = coordinates_[k];
        const auto& parts = planar_parts_[k];
        out_ << fmt::format("joint {} : prismatic {}.{} {}.in coordinate {}\n", parts[2], p, n, parts[0], q[0]);
        out_ << fmt::format("joint {} : prismatic {}.out {}.in coordinate {}\n", parts[3], parts[0], parts[1], q[1]);
        out_ << fmt::format("joint {} : revolute {}.out {}.{} coordinate {}\n", n, parts[1], c, n, q[2]);
      } else {
        const std::string kind = u.type == "prismatic" ? "prismatic" : "revolute";
        out_ << fmt::format("joint {} : {} {}.{} {}.{} coordinate {}{}\n", n, kind, p, n, c, n, coordinates_[k][0], actuator(k));
      }
    }
  }

  void mimics() {
    std::vector<std::string> rows;
    for (std::size_t k = 0; k < tree_.joints.size(); ++k) {
      const RobotJoint& j = tree_.joints[k];
      if (!j.mimics) continue;
      const UrdfMimic& m = *urdf(j).mimic;
      std::string rhs = m.multiplier == 1 ? coordinates_[*j.mimics][0]
                                          : fmt::format("{}*{}", num(m.multiplier), coordinates_[*j.mimics][0]);
      if (m.offset != 0) rhs += fmt::format(" {} {}", m.offset < 0 ? "-" : "+", num(std::abs(m.offset)));
      rows.push_back(fmt::format("  mimic_{}: {} = {}", joint_names_[k], coordinates_[k][0], rhs));
    }
    if (rows.empty()) return;
    out_ << "\n# <mimic> joints follow others: q = multiplier q_followed + offset.\nconstraint position {\n";
    for (const auto& r : rows) out_ << r << "\n";
    out_ << "}\n";
  }

  /// The robot's own speeds as the independent set: a free body's six and every joint's
  /// rate but a mimic joint's (it follows the joint it mimics).
  void independent() {
    std::vector<std::string> speeds;
    for (std::size_t b = 0; b < tree_.bodies.size(); ++b)
      if (tree_.bodies[b].free)
        for (const char* s : {"u", "v", "w", "wx", "wy", "wz"}) speeds.push_back(body_names_[b] + "." + s);
    for (std::size_t k = 0; k < tree_.joints.size(); ++k)
      if (!tree_.joints[k].mimics)
        for (const auto& q : coordinates_[k]) speeds.push_back(q + "_dot");
    if (speeds.empty()) return;
    const bool mimicking = std::any_of(tree_.joints.begin(), tree_.joints.end(), [](const RobotJoint& j) { return j.mimics.has_value(); });
    out_ << "\n# The robot's speeds: " << (tree_.bodies[0].free ? "the base's six and " : "")
         << "the joint rates" << (mimicking ? " (not the mimic joints')" : "") << ".\n";
    out_ << fmt::format("independent {}\n", fmt::join(speeds, ", "));
  }

  void initials() {
    for (std::size_t b = 0; b < tree_.bodies.size(); ++b) {
      const RobotBody& body = tree_.bodies[b];
      if (!body.free) continue;
      const Vec3 x = add(body.start.position, mul(body.start.rotation, body.com));
      const auto e = quaternion_of(body.start.rotation);
      const std::string& n = body_names_[b];
      out_ << fmt::format("\n# '{}' starts {}.\n", printable(body.link), b == 0 ? "at the origin, level" : "where its floating joint's origin puts it");
      out_ << fmt::format("initial {}.x = {}, {}.y = {}, {}.z = {}\n", n, num(x[0]), n, num(x[1]), n, num(x[2]));
      out_ << fmt::format("initial {}.e0 = {}, {}.e1 = {}, {}.e2 = {}, {}.e3 = {}\n", n, num(e[0]), n, num(e[1]), n, num(e[2]),
                          n, num(e[3]));
    }
  }

  const std::string& path_;
  const UrdfDocument& doc_;
  const RobotTree& tree_;
  const UrdfImportOptions& options_;
  std::ostringstream out_;
  Names names_;
  std::string model_name_;
  std::vector<std::string> body_names_, joint_names_;
  std::vector<std::vector<std::string>> coordinates_;
  std::vector<std::vector<std::string>> planar_parts_;  // a planar joint's carriages and slide joints
  std::vector<std::string> input_names_;  // per joint: its input, or "" (none)
};

}  // namespace

bool is_urdf_path(const std::string& path) {
  if (path.size() < 5) return false;
  std::string ext = path.substr(path.size() - 5);
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".urdf";
}

std::optional<std::string> urdf_to_model(const std::string& path, const std::string& text,
                                         const UrdfImportOptions& options, Diagnostics& diags) {
  const auto doc = read_urdf(path, text, diags);
  if (!doc) return std::nullopt;
  const auto tree = build_robot_tree(*doc, options.floating_base, diags);
  if (!tree) return std::nullopt;
  return Writer(path, *doc, *tree, options).text();
}

}  // namespace mbsc::import
