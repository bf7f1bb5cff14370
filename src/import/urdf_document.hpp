// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// A URDF file as read (urdf_reader.cpp): links, joints and what the import leaves out,
// each element with its position for errors. No interpretation beyond the schema.
#include <optional>
#include <string>
#include <vector>

#include "frame_math.hpp"
#include "mbsc/diag/diagnostics.hpp"

namespace mbsc::import {

struct UrdfInertial {
  double mass = 0;
  Pose origin;  // the mass centre and the inertia's axes in the link frame
  double ixx = 0, ixy = 0, ixz = 0, iyy = 0, iyz = 0, izz = 0;  // tensor entries about the mass centre
  SourcePos pos;
};

struct UrdfLink {
  std::string name;
  SourcePos pos;
  std::optional<UrdfInertial> inertial;
  int visuals = 0, collisions = 0;
};

struct UrdfMimic {
  std::string joint;
  double multiplier = 1, offset = 0;
  SourcePos pos, joint_pos;
};

struct UrdfJoint {
  std::string name, type, parent, child;
  SourcePos pos, type_pos, parent_pos, child_pos, axis_pos;
  Pose origin;   // the child link's frame at q = 0, in the parent link's
  Vec3 rpy{0, 0, 0};  // as written, for the comments
  Vec3 axis{1, 0, 0};  // in the child link's frame (URDF's default x)
  std::string limit;  // the <limit> attributes as written, "" when none
  double damping = 0, friction = 0;
  SourcePos dynamics_pos;
  std::optional<UrdfMimic> mimic;
  bool safety = false, calibration = false;
};

/// The joint types with one coordinate of their own (revolute, continuous, prismatic):
/// those that take an input, damping and a mimic.
inline bool has_one_coordinate(const std::string& type) {
  return type == "revolute" || type == "continuous" || type == "prismatic";
}

struct UrdfDocument {
  std::string robot_name;
  SourcePos robot_pos;
  std::vector<UrdfLink> links;
  std::vector<UrdfJoint> joints;
  int transmissions = 0, gazebo = 0, materials = 0;
  std::vector<std::string> other_elements;  // other children of <robot>, by name, once each
};

/// Reads `text` (the contents of `path`). Every problem is an error at its element or
/// attribute; nullopt when there was one.
std::optional<UrdfDocument> read_urdf(const std::string& path, const std::string& text, Diagnostics& diags);

}  // namespace mbsc::import
