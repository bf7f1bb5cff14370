// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/sym/tidy.hpp"

namespace mbsc::sym {
namespace {

/// True when e has at most `limit` nodes (counted with repetition, stops early).
bool small(const GiNaC::ex& e, int limit) {
  int count = 0;
  for (auto it = e.preorder_begin(); it != e.preorder_end(); ++it)
    if (++count > limit) return false;
  return true;
}

}  // namespace

GiNaC::ex tidy(const GiNaC::ex& e) {
  // GiNaC's common-factor collection is superlinear in the size of a sum: large
  // expressions are left to the back end's CSE.
  if (!small(e, 400)) return e;
  // Common factors first, so that c*(sin(u)^2 + cos(u)^2) appears as a whole sum.
  GiNaC::ex out = GiNaC::collect_common_factors(e);
  const GiNaC::ex u = GiNaC::wild(0);
  out = out.subs(GiNaC::pow(GiNaC::sin(u), 2) + GiNaC::pow(GiNaC::cos(u), 2) == 1);
  return out;
}

}  // namespace mbsc::sym
