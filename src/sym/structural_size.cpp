// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/sym/structural_size.hpp"

namespace mbsc::sym {

namespace {

std::size_t weight(const GiNaC::ex& e) {
  if (GiNaC::is_exactly_a<GiNaC::numeric>(e)) return 0;
  if (!GiNaC::is_exactly_a<GiNaC::mul>(e)) return 1;
  std::size_t factors = 0;
  for (std::size_t i = 0; i < e.nops(); ++i) factors += GiNaC::is_exactly_a<GiNaC::numeric>(e.op(i)) ? 0 : 1;
  return factors >= 2 ? 1 : 0;
}

}  // namespace

std::size_t structural_size(const GiNaC::ex& e, std::size_t limit) {
  std::size_t n = 0;
  for (auto it = e.preorder_begin(); it != e.preorder_end(); ++it)
    if ((n += weight(*it)) > limit) return limit + 1;
  return n;
}

}  // namespace mbsc::sym
