// SPDX-License-Identifier: GPL-2.0-or-later
// libFuzzer target: any bytes as a model file, through the lexer, the loop expansion,
// the parser and the model builder; models small enough to derive quickly also go
// through the derivation and code generation. Whatever the input, nothing may crash,
// hang, leak or trip a sanitizer, and every error must come as a diagnostic.
//
// Build and run: scripts/fuzz.sh (docs/robustness.md).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "fuzz_budget.hpp"
#include "mbsc/diag/activity.hpp"
#include "mbsc/driver/pipeline.hpp"
#include "mbsc/emit/generated_model.hpp"
#include "mbsc/model/build.hpp"
#include "mbsc/parse/parse.hpp"
#include "mbsc/sym/eom.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // Long inputs only slow the search down; the limits on long inputs have their own tests.
  if (size > 16384) return -1;
  const std::string text(reinterpret_cast<const char*>(data), size);
  mbsc::Diagnostics diags;
  mbsc_fuzz::Budget budget(2.0);  // seconds of symbolic work per input, then BudgetExceeded
  try {
    auto file = mbsc::parse::parse_text(text, "fuzz.mbs", diags);
    if (!file) return 0;
    auto model = mbsc::model::build(*file, diags);
    if (!model || !mbsc::driver::check_model_name(*model, "", diags)) return 0;
    // Derive and generate small models only: a mutated model can be a legitimately
    // big one, and then the time goes to GiNaC, not to finding bugs.
    if (model->coords.size() + model->speeds.size() > 24 || model->constraints.size() > 12) return 0;
    mbsc::sym::Options options;
    auto eom = mbsc::sym::derive(*model, options, diags);
    if (!eom) return 0;
    for (int k = 1; k < model->partition_count(); ++k) {  // as `check` does: every alternative set
      options.partition = k;
      if (!mbsc::sym::derive(*model, options, diags)) return 0;
    }
    mbsc::driver::GenerateOptions generate_options;
    auto generated = mbsc::driver::generate(*model, *eom, generate_options, diags);
    if (!generated) return 0;
    (void)mbsc::emit::emit(*generated);
  } catch (const mbsc::BudgetExceeded&) {
    // The budget ran out at a checkpoint: the command line reports this as an error.
  }
  // The stages turn unexpected exceptions into "internal error" diagnostics (exit 2 in
  // the command line): for the fuzzer those are findings, like crashes.
  const std::string report = diags.format();
  if (report.find("internal error") != std::string::npos) {
    std::fprintf(stderr, "%s", report.c_str());
    std::abort();
  }
  return 0;
}
