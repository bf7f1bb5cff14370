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
  /// What the expression gives ("the mass of body 'b'"), naming it in the value bound's
  /// message; may be empty.
  std::string element;

  /// The expression as GiNaC's; nullopt when an error was reported. The whole
  /// expression's numbers and constant parts are values the generated code can compute
  /// with (model/value_bound.hpp), or an error at `e`.
  std::optional<GiNaC::ex> convert(const ast::Expr& e);

 private:
  int depth_ = 0;  // of convert's recursion: the value bound is checked at 0
  std::optional<GiNaC::ex> convert_node(const ast::Expr& e);
  /// A flat Sum or Product node.
  std::optional<GiNaC::ex> chain(const ast::Expr& e);
  /// Runs one GiNaC operation; its exceptions (log(0), tan(pi/2)) and constants folded
  /// beyond limits::kMaxExactBits or a double's range become errors at `pos`.
  std::optional<GiNaC::ex> apply(const SourcePos& pos, const std::string& what, const std::function<GiNaC::ex()>& op);
  /// base^exponent, refusing exact powers too large to compute (2^(2^40)).
  std::optional<GiNaC::ex> power(const GiNaC::ex& base, const GiNaC::ex& exponent, const SourcePos& pos);
  /// False (reported) when e's folded numeric coefficient is too large or out of double range.
  bool check_folded(const GiNaC::ex& e, const SourcePos& pos);
};

/// Exact rational for a decimal literal ("0.15" -> 3/20, "1e-3" -> 1/1000, "-2.5").
/// Throws std::invalid_argument / std::out_of_range on malformed text.
GiNaC::numeric parse_decimal(const std::string& text);

/// True (and the value) when `e` evaluates to a finite real number.
bool evaluate_number(const GiNaC::ex& e, double& value);

/// The exact rational of the shortest decimal text of v (9.81 -> 981/100).
GiNaC::numeric exact_decimal(double v);

}  // namespace mbsc::model
