// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The C++ glue of an exported FMU (templates/fmu_glue.cpp.in): NAME_fmu.cpp, which
/// hands the generated model, its start values and its token to the FMI functions of
/// include/mbsc/fmi/fmi2_exports.hpp or fmi3_exports.hpp.
#include <string>
#include <vector>

#include "mbsc/emit/generated_model.hpp"

namespace mbsc::emit {

struct FmuGlue {
  int fmi_version = 2;             // 2 or 3
  bool model_exchange = true;      // the kinds the FMU exports
  bool co_simulation = true;
  bool multipliers = false;        // --formulation multipliers (its table macro)
  std::vector<double> start;       // kNx start values
  std::vector<bool> given;         // kNx: fixed by the model's `initial` statements
  std::string token;               // guid / instantiationToken
};

std::string emit_fmu_glue(const GeneratedModel& model, const FmuGlue& glue);

}  // namespace mbsc::emit
