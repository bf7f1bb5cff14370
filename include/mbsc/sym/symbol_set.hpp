// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The distinct symbols of an expression, collected in one traversal. Asking whether an
/// expression depends on each of n variables with has() (or differentiating it by each)
/// costs n traversals; with the set it costs one plus n lookups, which keeps the
/// Jacobian-like loops over all speeds of a big model linear in its size.
#include <ginac/ginac.h>

#include <unordered_set>

namespace mbsc::sym {

/// GiNaC's own hash of an expression, for unordered containers keyed by symbols or
/// expressions (with GiNaC::ex_is_equal as the equality).
struct ExHash {
  std::size_t operator()(const GiNaC::ex& e) const { return e.gethash(); }
};

class SymbolSet {
 public:
  explicit SymbolSet(const GiNaC::ex& e);
  bool contains(const GiNaC::ex& s) const { return symbols_.count(s) > 0; }
  /// e.diff(s), or 0 at once when s does not occur in e (what diff would return).
  GiNaC::ex diff(const GiNaC::ex& e, const GiNaC::symbol& s) const { return contains(s) ? e.diff(s) : GiNaC::ex(0); }
  /// The symbols themselves (in no particular order).
  const std::unordered_set<GiNaC::ex, ExHash, GiNaC::ex_is_equal>& symbols() const { return symbols_; }

 private:
  std::unordered_set<GiNaC::ex, ExHash, GiNaC::ex_is_equal> symbols_;
};

}  // namespace mbsc::sym
