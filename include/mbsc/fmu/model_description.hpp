// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// modelDescription.xml of an exported FMU (FMI 2.0 or 3.0), and FMI 3.0's
/// sources/buildDescription.xml. Every variable is a real scalar; their value
/// references are FmuLayout's (include/mbsc/fmi/fmu_instance.hpp):
///
///   states x          local, continuous; initial exact where the model's `initial`
///                     fixes them or nothing is assembled, approx where assembly solves
///                     them from the constraints
///   der(x)            local, continuous, calculated; `derivative` names the state
///   inputs            input, continuous, start 0
///   parameters        parameter, fixed, exact, start the model's default
///   outputs           output, continuous, calculated
///   time              (FMI 3.0) the independent variable
///
/// ModelStructure lists the outputs, the derivatives and the initial unknowns (the
/// approx states, the derivatives, the outputs), each depending on everything (no
/// dependency lists). The text is a function of the arguments alone (no dates).
#include <string>
#include <vector>

namespace mbsc::fmu {

struct FmuDescription {
  int fmi_version = 2;  // 2 or 3
  bool model_exchange = true, co_simulation = true;
  std::string model_name;         // also the modelIdentifier
  std::string token;              // guid / instantiationToken
  std::string description;        // of the model (its file)
  std::string generation_tool;    // "mbsc 0.1.0"
  int nq = 0;                     // the states' first nq entries are coordinates, the rest speeds
  /// Whether the FMU assembles its start from the constraints (the full state of a model
  /// with constraints: FmuInstance's rule); else every state's start is exact.
  bool assembles = false;
  std::vector<std::string> states;
  std::vector<double> start;
  std::vector<bool> given;
  std::vector<std::string> inputs;
  std::vector<std::string> params;
  std::vector<double> param_defaults;
  std::vector<std::string> param_descriptions;  // "" for none
  std::vector<std::string> outputs;
  std::vector<std::string> source_files;        // compiled, in sources/
  double stop_time = 10.0, tolerance = 1e-6;    // DefaultExperiment
};

/// Whether every name is a structured name of the standard (identifiers with array
/// indices, joined by '.'); else the description says "flat".
bool structured_names(const FmuDescription& d);

/// The first name that appears twice among the variables (derivatives and FMI 3.0's
/// time included), or "".
std::string repeated_name(const FmuDescription& d);

std::string model_description_xml(const FmuDescription& d);
std::string build_description_xml(const FmuDescription& d);

}  // namespace mbsc::fmu
