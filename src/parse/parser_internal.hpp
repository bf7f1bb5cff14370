// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Private to src/parse: the parser entry point shared by parse_text and the include resolver.
#include <map>
#include <string>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/parse/ast.hpp"

namespace mbsc::parse {

/// Parses `text` into `out` (out.path = file). Statements that parsed cleanly are kept
/// even when errors were reported elsewhere, so a caller can go on (e.g. resolve the
/// includes) and report more. Returns true when this call reported no error.
/// Lexes, expands `for` loops and indices (loop_expansion.hpp, with `overrides` for
/// parameter values; out.structural gets the parameters they used), then parses.
bool parse_source(const std::string& text, const std::string& file, Diagnostics& diags, ast::File& out,
                  const std::map<std::string, double>& overrides = {});

}  // namespace mbsc::parse
