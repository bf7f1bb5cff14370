// SPDX-License-Identifier: GPL-2.0-or-later
// libFuzzer target: any bytes as the value of a command-line option (--set, --init,
// --input, --let, --prescribe), through the reader those options share
// (model/option_expression.hpp) and the C++ that --input compiles. Whatever the input,
// nothing may crash, hang, leak or trip a sanitizer; an accepted expression must have a
// C++ text, and a constant one a finite value or an error.
//
// Build and run: scripts/fuzz.sh (docs/robustness.md).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "mbsc/model/expr_convert.hpp"
#include "mbsc/model/option_expression.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 4096) return -1;  // the limits on long texts have their own tests
  const std::string text(reinterpret_cast<const char*>(data), size);
  static const GiNaC::symbol t("t"), m("m");
  // As --input reads it: t and parameters as symbols.
  const mbsc::model::OptionNames symbols = {{"t", t}, {"m", m}, {"arm.th", mbsc::model::exact_decimal(0.5)}};
  std::string error;
  if (const auto e = mbsc::model::read_option_expression(text, symbols, "t and the parameters", error)) {
    const std::string cpp = mbsc::model::option_expression_cpp(text, {{"t", "t"}, {"m", "p[0]"}, {"arm.th", "0.5"}});
    if (cpp.empty()) {
      std::fprintf(stderr, "accepted '%s' but wrote no C++\n", text.c_str());
      std::abort();
    }
  } else if (error.empty()) {
    std::fprintf(stderr, "refused '%s' without a message\n", text.c_str());
    std::abort();
  }
  // As --set reads it: a constant.
  double value = 0;
  error.clear();
  const mbsc::model::OptionNames constants = {{"l", mbsc::model::exact_decimal(1.5)}};
  if (mbsc::model::option_value(text, constants, "numbers and pi", value, error)) {
    if (!(value == value) || value - value != 0) {
      std::fprintf(stderr, "'%s' gave a value that is not finite\n", text.c_str());
      std::abort();
    }
  } else if (error.empty()) {
    std::fprintf(stderr, "refused '%s' without a message\n", text.c_str());
    std::abort();
  }
  return 0;
}
