// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// URDF in: a robot description read into a model of mbsc's own language
/// (docs/urdf.md). `mbsc import` writes the text; every other command reads a .urdf
/// through it (parse_file), so a robot is checked, printed, generated and run as written.
#include <optional>
#include <string>

#include "mbsc/diag/diagnostics.hpp"

namespace mbsc::import {

struct UrdfImportOptions {
  /// The root link as a free body (quaternion attitude, six speeds) instead of fixed to
  /// the ground: legged robots and humanoids.
  bool floating_base = false;
  /// An input per actuated joint (`tau_JOINT`: a torque about a revolute joint's axis, a
  /// force along a prismatic one's), so that M q'' = h + tau as robot tools write it.
  bool joint_inputs = true;
};

/// True for a path that names a URDF file (extension .urdf, any case).
bool is_urdf_path(const std::string& path);

/// The model text for the URDF `text` read from `path` (positions in errors refer to it),
/// or nullopt with every problem reported as `path:line:col: error: ...`.
std::optional<std::string> urdf_to_model(const std::string& path, const std::string& text,
                                         const UrdfImportOptions& options, Diagnostics& diags);

}  // namespace mbsc::import
