// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// `mbsc import ROBOT.urdf [-o ROBOT.mbs]`: a URDF robot as a model file (docs/urdf.md).
#include <ostream>
#include <string>

#include "mbsc/import/urdf_import.hpp"

namespace mbsc::driver {

struct ImportArgs {
  std::string urdf;
  std::string output;  // "" = standard output
  bool force = false;  // replace an existing output file
  import::UrdfImportOptions options;
};

/// 0 on success; 1 with the errors on `err` (file:line:col), nothing written.
int run_import(const ImportArgs& a, std::ostream& out, std::ostream& err);

}  // namespace mbsc::driver
