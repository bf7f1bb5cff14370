// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Private to src/parse: the parser entry point shared by parse_text and the include resolver.
#include <string>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/parse/ast.hpp"

namespace mbsc::parse {

/// Parses `text` into `out` (out.path = file). Statements that parsed cleanly are kept
/// even when errors were reported elsewhere, so a caller can go on (e.g. resolve the
/// includes) and report more. Returns true when this call reported no error.
bool parse_source(const std::string& text, const std::string& file, Diagnostics& diags, ast::File& out);

}  // namespace mbsc::parse
