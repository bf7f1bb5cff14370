// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/sym/inline_recurrences.hpp"

#include <set>

#include "mbsc/model/exact_guard.hpp"
#include "mbsc/sym/tidy.hpp"

namespace mbsc::sym {

namespace {

// Adds the operations of e's subexpressions not yet in `seen` (a sum or product of k
// operands is k - 1 operations, a power or function call one): the count the back end's
// common-subexpression elimination would leave, roughly.
void add_operations(const GiNaC::ex& e, std::set<GiNaC::ex, GiNaC::ex_is_less>& seen, int& ops) {
  if (GiNaC::is_a<GiNaC::symbol>(e) || GiNaC::is_a<GiNaC::numeric>(e)) return;
  if (!seen.insert(e).second) return;
  const int n = static_cast<int>(e.nops());
  ops += GiNaC::is_a<GiNaC::add>(e) || GiNaC::is_a<GiNaC::mul>(e) ? n - 1 : 1;
  for (int i = 0; i < n; ++i) add_operations(e.op(static_cast<std::size_t>(i)), seen, ops);
}

}  // namespace

int shared_operations(const std::vector<GiNaC::ex>& exprs) {
  std::set<GiNaC::ex, GiNaC::ex_is_less> seen;
  int ops = 0;
  for (const GiNaC::ex& e : exprs) add_operations(e, seen, ops);
  return ops;
}

bool inline_small_recurrences(const std::vector<ir::Define>& named, std::size_t kept, GiNaC::matrix& h) {
  if (named.empty() || named.size() > kMaxInlinedRecurrences) return false;
  // The named form: every value once, then h as it reads them; `alone` leaves out the
  // kept values (the e_ rates), which a full-state rhs computes for its accelerations
  // whether h reads them or not.
  std::vector<GiNaC::ex> named_form, alone_form, inlined_form;
  GiNaC::exmap value_of;  // name -> its value, written without names
  for (std::size_t k = 0; k < named.size(); ++k) {
    named_form.push_back(named[k].value);
    if (k >= kept) alone_form.push_back(named[k].value);
    value_of[named[k].sym] = named[k].value.subs(value_of, GiNaC::subs_options::no_pattern);
  }
  GiNaC::matrix inlined(h.rows(), h.cols());
  for (unsigned i = 0; i < h.rows(); ++i) {
    named_form.push_back(h(i, 0));
    alone_form.push_back(h(i, 0));
    // expand_if_small leaves a sum with too many terms as it is: then the comparison
    // below keeps the names.
    const GiNaC::ex full = h(i, 0).subs(value_of, GiNaC::subs_options::no_pattern);
    inlined(i, 0) = tidy(pythagoras(model::expand_if_small(full)));
    inlined_form.push_back(inlined(i, 0));
  }
  // Inlining saves the kept values only where the state is minimal (derivation does not
  // know which build it serves): they count half, between the two builds' savings.
  // (Measured on the shipped models: counting them fully made heavy_top's minimal rhs
  // larger, not counting them left the two-link chain's cancellation out.)
  const int all = shared_operations(named_form), alone = shared_operations(alone_form);
  const int inlined_ops = shared_operations(inlined_form);
  if (2 * inlined_ops >= all + alone) return false;
  h = inlined;
  return true;
}

}  // namespace mbsc::sym
