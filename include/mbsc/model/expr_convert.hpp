// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// ast::Expr -> GiNaC::ex. Names are resolved through a callback (the caller knows the
/// scopes); numbers become exact rationals; unknown functions and wrong arities are
/// diagnostics at the exact column.
#include <ginac/ginac.h>

#include <functional>
#include <optional>
#include <string>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/parse/ast.hpp"

namespace mbsc::model {

struct ExprConverter {
  explicit ExprConverter(Diagnostics& d) : diags(d) {}
  Diagnostics& diags;
  /// Resolves a dotted name; `primed` when written x'. Reports its own errors.
  std::function<std::optional<GiNaC::ex>(const std::string& path, const SourcePos& pos, bool primed)> lookup;

  std::optional<GiNaC::ex> convert(const ast::Expr& e);
};

/// Exact rational for a decimal literal ("0.15" -> 3/20, "1e-3" -> 1/1000, "-2.5").
GiNaC::numeric parse_decimal(const std::string& text);

/// True (and the value) when `e` evaluates to a finite real number.
bool evaluate_number(const GiNaC::ex& e, double& value);

/// The exact rational of the shortest decimal text of v (9.81 -> 981/100).
GiNaC::numeric exact_decimal(double v);

}  // namespace mbsc::model
