// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Private to src/parse: repeated structure, expanded on the token stream before parsing.
///
///   for i = 1 to N {            # N: a loop variable, a number, or a parameter whose
///     body crank[i] : rigid2d   #    default is a number (--freeze N=6 overrides it)
///     joint revolute crank[i].A coupler[i-1].B
///   }
///
/// The body's tokens are repeated for i = first .. last (nothing when last < first); a
/// loop variable in an expression becomes its number, and `name[index]` anywhere becomes
/// the single name `name_<index>` (crank[2] -> crank_2). Indices and bounds are integer
/// expressions (+ - * / and parentheses) of numbers, loop variables and such parameters.
/// The parameters used this way are structural: they are reported so the model freezes
/// them at the value used (changing them means regenerating).
#include <map>
#include <string>
#include <vector>

#include "lexer.hpp"
#include "mbsc/diag/diagnostics.hpp"

namespace mbsc::parse {

/// Returns the expanded tokens. Mistakes (a bound that is not an integer, an unknown name
/// in an index, an unclosed loop or bracket) are reported at their token. `overrides`
/// replaces parameter defaults (the --freeze values); `structural` receives every
/// parameter a bound or index used, with the value used.
std::vector<Token> expand_loops(const std::vector<Token>& tokens, Diagnostics& diags,
                                const std::map<std::string, double>& overrides,
                                std::map<std::string, double>& structural);

}  // namespace mbsc::parse
