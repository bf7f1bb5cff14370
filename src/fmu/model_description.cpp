// SPDX-License-Identifier: GPL-2.0-or-later
// modelDescription.xml and buildDescription.xml (include/mbsc/fmu/model_description.hpp).
#include "mbsc/fmu/model_description.hpp"

#include <fmt/format.h>

#include <regex>
#include <set>

#include "mbsc/emit/generated_model.hpp"
#include "mbsc/fmi/fmu_instance.hpp"

namespace mbsc::fmu {

namespace {

std::string xml_escaped(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += (static_cast<unsigned char>(c) < 0x20) ? ' ' : c;
    }
  }
  return out;
}

std::string number(double v) { return emit::format_double(v); }

/// One variable of the model description, in the order it is listed.
struct Variable {
  std::string name;
  unsigned vr;
  std::string causality, variability, initial;  // initial "" for none
  bool has_start = false;
  double start = 0.0;
  int derivative_of = -1;  // the state's position among the variables (derivatives)
  std::string description;
};

std::vector<Variable> variables(const FmuDescription& d) {
  const fmi::FmuLayout L{static_cast<int>(d.states.size()), static_cast<int>(d.inputs.size()),
                         static_cast<int>(d.params.size()), static_cast<int>(d.outputs.size())};
  std::vector<Variable> v;
  if (d.fmi_version == 3)
    v.push_back({"time", L.time(), "independent", "continuous", "", false, 0.0, -1, "simulation time"});
  const int first_state = static_cast<int>(v.size());
  for (int i = 0; i < L.nx; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    const bool solved = d.assembles && !d.given[k];
    v.push_back({d.states[k], L.state(i), "local", "continuous", solved ? "approx" : "exact", true, d.start[k], -1,
                 std::string(i < d.nq ? "coordinate" : "speed") +
                     (solved ? " (solved from the constraints at the start)"
                             : d.given[k] ? " (the model's initial value)" : "")});
  }
  for (int i = 0; i < L.nx; ++i)
    v.push_back({"der(" + d.states[static_cast<std::size_t>(i)] + ")", L.derivative(i), "local", "continuous",
                 "calculated", false, 0.0, first_state + i, "rate of " + d.states[static_cast<std::size_t>(i)]});
  for (int i = 0; i < L.nin; ++i)
    v.push_back({d.inputs[static_cast<std::size_t>(i)], L.input(i), "input", "continuous", "", true, 0.0, -1, "input"});
  for (int i = 0; i < L.np; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    v.push_back({d.params[k], L.param(i), "parameter", "fixed", "exact", true, d.param_defaults[k], -1,
                 k < d.param_descriptions.size() && !d.param_descriptions[k].empty() ? d.param_descriptions[k]
                                                                                      : "parameter"});
  }
  for (int i = 0; i < L.ny; ++i)
    v.push_back({d.outputs[static_cast<std::size_t>(i)], L.output(i), "output", "continuous", "calculated", false, 0.0,
                 -1, "output"});
  return v;
}

void attribute(std::string& s, const char* name, const std::string& value) {
  s += fmt::format(" {}=\"{}\"", name, xml_escaped(value));
}

std::string fmi2_text(const FmuDescription& d, const std::vector<Variable>& vars) {
  std::string s = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<fmiModelDescription";
  attribute(s, "fmiVersion", "2.0");
  attribute(s, "modelName", d.model_name);
  attribute(s, "guid", d.token);
  attribute(s, "description", d.description);
  attribute(s, "generationTool", d.generation_tool);
  attribute(s, "variableNamingConvention", structured_names(d) ? "structured" : "flat");
  attribute(s, "numberOfEventIndicators", "0");
  s += ">\n";
  std::string files;
  for (const auto& f : d.source_files) files += fmt::format("      <File name=\"{}\"/>\n", xml_escaped(f));
  const std::string common = fmt::format(
      " modelIdentifier=\"{}\" canGetAndSetFMUstate=\"true\" canSerializeFMUstate=\"true\" "
      "canNotUseMemoryManagementFunctions=\"true\"",
      xml_escaped(d.model_name));
  if (d.model_exchange)
    s += "  <ModelExchange" + common + ">\n    <SourceFiles>\n" + files + "    </SourceFiles>\n  </ModelExchange>\n";
  if (d.co_simulation)
    s += "  <CoSimulation" + common + " canHandleVariableCommunicationStepSize=\"true\">\n    <SourceFiles>\n" + files +
         "    </SourceFiles>\n  </CoSimulation>\n";
  s += "  <LogCategories>\n    <Category name=\"logError\" description=\"errors\"/>\n"
       "    <Category name=\"logWarning\" description=\"warnings\"/>\n  </LogCategories>\n";
  s += fmt::format("  <DefaultExperiment startTime=\"0\" stopTime=\"{}\" tolerance=\"{}\"/>\n", number(d.stop_time),
                   number(d.tolerance));
  s += "  <ModelVariables>\n";
  for (std::size_t i = 0; i < vars.size(); ++i) {
    const Variable& v = vars[i];
    s += fmt::format("    <!-- index {} -->\n    <ScalarVariable", i + 1);
    attribute(s, "name", v.name);
    attribute(s, "valueReference", std::to_string(v.vr));
    attribute(s, "description", v.description);
    attribute(s, "causality", v.causality);
    attribute(s, "variability", v.variability);
    if (!v.initial.empty()) attribute(s, "initial", v.initial);
    s += ">\n      <Real";
    if (v.has_start) attribute(s, "start", number(v.start));
    if (v.derivative_of >= 0) attribute(s, "derivative", std::to_string(v.derivative_of + 1));
    s += "/>\n    </ScalarVariable>\n";
  }
  s += "  </ModelVariables>\n  <ModelStructure>\n";
  auto unknowns = [&](const char* element, auto take) {
    std::string list;
    for (std::size_t i = 0; i < vars.size(); ++i)
      if (take(vars[i])) list += fmt::format("      <Unknown index=\"{}\"/>\n", i + 1);
    s += list.empty() ? "" : fmt::format("    <{0}>\n{1}    </{0}>\n", element, list);
  };
  unknowns("Outputs", [](const Variable& v) { return v.causality == "output"; });
  unknowns("Derivatives", [](const Variable& v) { return v.derivative_of >= 0; });
  unknowns("InitialUnknowns", [](const Variable& v) {
    return v.causality == "output" || v.derivative_of >= 0 || v.initial == "approx";
  });
  s += "  </ModelStructure>\n</fmiModelDescription>\n";
  return s;
}

std::string fmi3_text(const FmuDescription& d, const std::vector<Variable>& vars) {
  std::string s = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<fmiModelDescription";
  attribute(s, "fmiVersion", "3.0");
  attribute(s, "modelName", d.model_name);
  attribute(s, "instantiationToken", d.token);
  attribute(s, "description", d.description);
  attribute(s, "generationTool", d.generation_tool);
  attribute(s, "variableNamingConvention", structured_names(d) ? "structured" : "flat");
  s += ">\n";
  const std::string common = fmt::format(
      " modelIdentifier=\"{}\" canGetAndSetFMUState=\"true\" canSerializeFMUState=\"true\"", xml_escaped(d.model_name));
  if (d.model_exchange) s += "  <ModelExchange" + common + " needsCompletedIntegratorStep=\"true\"/>\n";
  if (d.co_simulation)
    s += "  <CoSimulation" + common + " canHandleVariableCommunicationStepSize=\"true\" hasEventMode=\"false\"/>\n";
  s += "  <LogCategories>\n    <Category name=\"logError\" description=\"errors\"/>\n"
       "    <Category name=\"logWarning\" description=\"warnings\"/>\n  </LogCategories>\n";
  s += fmt::format("  <DefaultExperiment startTime=\"0\" stopTime=\"{}\" tolerance=\"{}\"/>\n", number(d.stop_time),
                   number(d.tolerance));
  s += "  <ModelVariables>\n";
  for (const Variable& v : vars) {
    s += "    <Float64";
    attribute(s, "name", v.name);
    attribute(s, "valueReference", std::to_string(v.vr));
    attribute(s, "description", v.description);
    attribute(s, "causality", v.causality);
    attribute(s, "variability", v.variability);
    if (!v.initial.empty()) attribute(s, "initial", v.initial);
    if (v.has_start) attribute(s, "start", number(v.start));
    if (v.derivative_of >= 0) attribute(s, "derivative", std::to_string(vars[static_cast<std::size_t>(v.derivative_of)].vr));
    s += "/>\n";
  }
  s += "  </ModelVariables>\n  <ModelStructure>\n";
  auto unknowns = [&](const char* element, auto take) {
    for (const Variable& v : vars)
      if (take(v)) s += fmt::format("    <{} valueReference=\"{}\"/>\n", element, v.vr);
  };
  unknowns("Output", [](const Variable& v) { return v.causality == "output"; });
  unknowns("ContinuousStateDerivative", [](const Variable& v) { return v.derivative_of >= 0; });
  unknowns("InitialUnknown", [](const Variable& v) {
    return v.causality == "output" || v.derivative_of >= 0 || v.initial == "approx";
  });
  s += "  </ModelStructure>\n</fmiModelDescription>\n";
  return s;
}

}  // namespace

bool structured_names(const FmuDescription& d) {
  static const std::regex name(
      R"([A-Za-z_][A-Za-z0-9_]*(\[[0-9]+(,[0-9]+)*\])?(\.[A-Za-z_][A-Za-z0-9_]*(\[[0-9]+(,[0-9]+)*\])?)*)");
  for (const auto* list : {&d.states, &d.inputs, &d.params, &d.outputs})
    for (const auto& n : *list)
      if (!std::regex_match(n, name)) return false;
  return true;
}

std::string repeated_name(const FmuDescription& d) {
  std::set<std::string> seen;
  for (const Variable& v : variables(d))
    if (!seen.insert(v.name).second) return v.name;
  return "";
}

std::string model_description_xml(const FmuDescription& d) {
  const auto vars = variables(d);
  return d.fmi_version == 3 ? fmi3_text(d, vars) : fmi2_text(d, vars);
}

std::string build_description_xml(const FmuDescription& d) {
  std::string s = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<fmiBuildDescription fmiVersion=\"3.0\">\n";
  s += fmt::format("  <BuildConfiguration modelIdentifier=\"{}\">\n    <SourceFileSet language=\"C++17\">\n",
                   xml_escaped(d.model_name));
  for (const auto& f : d.source_files) s += fmt::format("      <SourceFile name=\"{}\"/>\n", xml_escaped(f));
  s += "      <IncludeDirectory name=\".\"/>\n    </SourceFileSet>\n  </BuildConfiguration>\n</fmiBuildDescription>\n";
  return s;
}

}  // namespace mbsc::fmu
