// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/sym/symbol_set.hpp"

namespace mbsc::sym {

SymbolSet::SymbolSet(const GiNaC::ex& e) {
  for (GiNaC::const_preorder_iterator it = e.preorder_begin(); it != e.preorder_end(); ++it)
    if (GiNaC::is_a<GiNaC::symbol>(*it)) symbols_.insert(*it);
}

}  // namespace mbsc::sym
