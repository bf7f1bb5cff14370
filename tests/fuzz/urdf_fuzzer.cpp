// SPDX-License-Identifier: GPL-2.0-or-later
// libFuzzer target: any bytes as a URDF file, through `mbsc import` (tinyxml2, the tree
// and its checks, the model text) and the written model back through the parser and the
// model builder, as the import command reads it back. Whatever the input, nothing may
// crash, hang, leak or trip a sanitizer; an import that succeeds must read back without
// errors (a failure there would be mbsc writing a model it refuses).
//
// Build and run: scripts/fuzz.sh (docs/robustness.md).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "fuzz_budget.hpp"
#include "mbsc/import/urdf_import.hpp"
#include "mbsc/model/build.hpp"
#include "mbsc/parse/parse.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 16384) return -1;
  const std::string text(reinterpret_cast<const char*>(data), size);
  mbsc::Diagnostics diags;
  mbsc_fuzz::Budget budget(2.0);
  try {
    for (const bool floating : {false, true}) {
      mbsc::import::UrdfImportOptions options;
      options.floating_base = floating;
      const auto model = mbsc::import::urdf_to_model("fuzz.urdf", text, options, diags);
      if (!model) return 0;
      mbsc::Diagnostics back;
      auto file = mbsc::parse::parse_text(*model, "fuzz.mbs", back);
      if (file) mbsc::model::build(*file, back);
      if (!file || back.has_errors()) {
        std::fprintf(stderr, "the imported model does not read back:\n%s\n%s", back.format().c_str(), model->c_str());
        std::abort();
      }
    }
  } catch (const mbsc::BudgetExceeded&) {
  }
  return 0;
}
