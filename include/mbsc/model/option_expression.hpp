// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Expressions given on the command line (--set, --init, --input, --let, --prescribe,
/// --symbolic's references): read by the model language's own parser and converted with
/// the same guards as a model file's expressions (length, nesting depth and operand
/// count; exact constants too large to fold, such as 2^(2^40); functions undefined at
/// constants), so an option can no more crash or stall mbsc than a model file can. The
/// syntax and functions are the model language's (docs/language_syntax.md).
#include <ginac/ginac.h>

#include <map>
#include <optional>
#include <string>

namespace mbsc::model {

/// What an option's expression may name: each name (as written, dotted names included)
/// and what it stands for (a symbol or an exact value). `pi` is always known.
using OptionNames = std::map<std::string, GiNaC::ex>;

/// Reads `text`; nullopt with `error` ("'TEXT': column C: MESSAGE"), for the caller to
/// prefix with its option and name. `what_names` describes the names allowed, for the
/// message about an unknown one (e.g. "t and the model's parameters").
std::optional<GiNaC::ex> read_option_expression(const std::string& text, const OptionNames& names,
                                                const std::string& what_names, std::string& error);

/// A constant expression's value as a finite double; false with `error` when it does not
/// read, names something else, or is not a finite real number.
bool option_value(const std::string& text, const OptionNames& names, const std::string& what_names, double& value,
                  std::string& error);

/// C++ for an expression that read_option_expression accepted, written from the text's
/// own tree (so the same text always gives the same code, whatever GiNaC's term order):
/// names through `cpp_names` (e.g. "t" -> "t", "m1" -> "p[0]"), numbers as double
/// literals, functions from <cmath>.
std::string option_expression_cpp(const std::string& text, const std::map<std::string, std::string>& cpp_names);

}  // namespace mbsc::model
