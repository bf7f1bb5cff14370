// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// AST -> validated Model: resolves names (innermost subsystem outwards, then
/// parameters, inputs and t), expands component instances, attaches leaf kinds'
/// variables, solves the quasi-velocity definitions for coordinate rates, and checks
/// everything that can be checked without deriving the equations.
#include <optional>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/model/model.hpp"
#include "mbsc/parse/ast.hpp"

namespace mbsc::model {

/// Returns nullopt when any error was reported.
std::optional<Model> build(const ast::File& file, Diagnostics& diags);

}  // namespace mbsc::model
