// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Lexer + recursive-descent parser for the model language (docs/language.md).
#include <map>
#include <optional>
#include <string>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/parse/ast.hpp"

namespace mbsc::parse {

/// Parses model text. `file` is only used in positions. Include statements are kept
/// as they are (not resolved). Returns nullopt when any syntax error was reported.
/// `overrides`: parameter values for loop bounds and indices (--freeze), see
/// docs/language.md "Repeated structure".
std::optional<ast::File> parse_text(const std::string& text, const std::string& file, Diagnostics& diags,
                                    const std::map<std::string, double>& overrides = {});

/// Parses `text` as one expression of the model language (a command-line option's
/// value), with the same limits as in a model file (length, nesting, operands); positions
/// are columns of `text`, with `origin` as the file name. Null when an error was reported.
ast::ExprPtr parse_expression(const std::string& text, const std::string& origin, Diagnostics& diags);

/// Why a number literal (digits, '.', exponent, no sign) is outside what a double holds
/// ("is too large for a double ..."), or nullptr. The lexer's rule, shared by --freeze.
const char* literal_out_of_double_range(const std::string& literal);

/// Reads and parses a file, splicing top-level `include "x.mbs"` statements in place
/// (paths relative to the including file). A missing file or a cyclic include is an
/// error at the include statement. Returns nullopt on any error.
std::optional<ast::File> parse_file(const std::string& path, Diagnostics& diags,
                                    const std::map<std::string, double>& overrides = {});

}  // namespace mbsc::parse
