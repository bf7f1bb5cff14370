// SPDX-License-Identifier: GPL-2.0-or-later
// NAME_fmu.cpp of an exported FMU (include/mbsc/emit/fmu_glue.hpp).
#include "mbsc/emit/fmu_glue.hpp"

#include "renderer.hpp"
#include "text_blocks.hpp"

namespace mbsc::emit {

namespace {

/// "{a, b, c}", eight entries a line (an empty list: one placeholder entry).
std::string brace_list(const std::vector<std::string>& items) {
  if (items.empty()) return "{0}";
  std::string s = "{";
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (i > 0) s += (i % 8 == 0) ? ",\n    " : ", ";
    s += items[i];
  }
  return s + "}";
}

}  // namespace

std::string emit_fmu_glue(const GeneratedModel& m, const FmuGlue& glue) {
  std::vector<std::string> start, given;
  for (double v : glue.start) start.push_back(format_double(v));
  for (bool g : glue.given) given.push_back(g ? "1" : "0");
  Fragments f;
  f["banner"] = comment_block(banner_text(m), "//");
  f["name"] = m.name;
  f["fmi_version"] = glue.fmi_version == 3 ? "3.0" : "2.0";
  f["fmi_major"] = glue.fmi_version == 3 ? "3" : "2";
  f["kinds"] = glue.model_exchange && glue.co_simulation ? "model exchange and co-simulation"
               : glue.model_exchange                     ? "model exchange"
                                                         : "co-simulation";
  f["start"] = brace_list(start);
  f["given"] = brace_list(given);
  f["table"] = glue.multipliers ? "MBSC_MODEL_TABLE_MULTIPLIERS" : "MBSC_MODEL_TABLE";
  f["token"] = glue.token;
  f["model_exchange"] = glue.model_exchange ? "1" : "0";
  f["co_simulation"] = glue.co_simulation ? "1" : "0";
  return render("fmu_glue.cpp.in", template_text("fmu_glue.cpp.in"), f);
}

}  // namespace mbsc::emit
