// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// C++ spelling of double constants (private; used by src/ir and src/emit).
#include <string>

namespace mbsc::emit {

/// format_double made a valid double literal: "3" -> "3.0", "-0" -> "-0.0"; "0.1", "1e-300",
/// "6.02e23" unchanged. Throws std::runtime_error for infinities and NaN.
std::string cpp_double_literal(double v);

}  // namespace mbsc::emit
