// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Deterministic text and LaTeX of a GiNaC expression for `mbsc print`. GiNaC's own
/// printer follows its run-dependent term order; this one sorts the operands of sums
/// and products by their printed text, so the same expression prints the same way in
/// every run.
#include <ginac/ginac.h>

#include <map>
#include <string>

namespace mbsc::print {

/// In LaTeX, a symbol prints as latex_names.hpp maps its name, or as the innermost
/// LatexSymbolScope of this thread gives it.
std::string canonical_text(const GiNaC::ex& e, bool latex);

/// While alive, the LaTeX of canonical_text (on this thread) prints the names in `symbols`
/// (the model's `latex NAME "..."` statements) as they say: `mbsc print` opens one for
/// the whole print. `symbols` must outlive the scope.
class LatexSymbolScope {
 public:
  explicit LatexSymbolScope(const std::map<std::string, std::string>& symbols);
  ~LatexSymbolScope();
  LatexSymbolScope(const LatexSymbolScope&) = delete;
  LatexSymbolScope& operator=(const LatexSymbolScope&) = delete;
  /// The symbols in effect (none outside every scope).
  static const std::map<std::string, std::string>& current();

 private:
  const std::map<std::string, std::string>* outer_;
};

}  // namespace mbsc::print
