// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// A URDF document as mbsc bodies and joints (urdf_tree.cpp): links welded by fixed
// joints merged into one body, every body's axes chosen parallel to the world's at the
// zero pose (so that a joint's coordinate measures the child from the frame it shares
// with its parent there, as mbsc's joints with coordinates do), inertias combined and
// turned into those axes. docs/urdf.md, "From links to bodies".
#include <optional>
#include <string>
#include <vector>

#include "urdf_document.hpp"

namespace mbsc::import {

struct RobotBody {
  std::string link;                  // the link at the top of the welded group
  std::string name;                  // the link the body is named after: its top link, but for a free
                                     // base whose top is a massless anchor ("world"), the first with mass
  std::vector<std::size_t> welded;   // the fixed joints merged into it (indices into UrdfDocument::joints)
  bool ground = false;               // the root group of a fixed-base robot
  bool free = false;                 // a free body: the floating base, or the child of a floating joint
  Mat3 axes = identity();            // W: a vector v in the top link's frame is W v in the body's axes
  std::vector<std::string> rpy_path; // how W came about, for the comment (the joints' rpy that turned it)
  double mass = 0;
  bool has_inertial = false;
  Vec3 com{0, 0, 0};                 // in the body's axes, from the top link's origin
  Mat3 inertia{};                    // about the mass centre, in the body's axes
  Pose start;                        // a free body's link frame at t = 0 in the world (from a floating joint's origin)
  SourcePos pos;
};

struct RobotJoint {
  std::size_t urdf = 0;              // index into UrdfDocument::joints
  std::size_t parent = 0, child = 0; // bodies
  Vec3 point{0, 0, 0};               // the joint's origin in the parent body's axes
  Vec3 axis{0, 0, 1};                // its unit axis, in both bodies' axes (they coincide at q = 0)
  std::optional<std::size_t> mimics; // the RobotJoint this one follows (<mimic>)
};

struct RobotTree {
  std::vector<RobotBody> bodies;     // bodies[0] is the root group (ground or the floating base); parents before children
  std::vector<RobotJoint> joints;    // the moving joints, parents before children
};

/// Checks the document's structure (names, one tree, axes, inertials, mimics) and builds
/// the bodies; nullopt with errors at the elements otherwise.
std::optional<RobotTree> build_robot_tree(const UrdfDocument& doc, bool floating_base, Diagnostics& diags);

}  // namespace mbsc::import
