// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// AST -> validated Model: resolves names (innermost subsystem outwards, then
/// parameters, inputs and t), expands component instances, attaches leaf kinds'
/// variables, solves the quasi-velocity definitions for coordinate rates, and checks
/// everything that can be checked without deriving the equations.
#include <map>
#include <optional>
#include <string>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/model/model.hpp"
#include "mbsc/parse/ast.hpp"

namespace mbsc::model {

/// Returns nullopt when any error was reported. `frozen` (--freeze values) stand in for
/// the parameters' defaults where values are checked (positive masses and inertias).
std::optional<Model> build(const ast::File& file, Diagnostics& diags, const std::map<std::string, double>& frozen = {});

}  // namespace mbsc::model
