// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Deterministic text and LaTeX of a GiNaC expression for `mbsc print`. GiNaC's own
/// printer follows its run-dependent term order; this one sorts the operands of sums
/// and products by their printed text, so the same expression prints the same way in
/// every run.
#include <ginac/ginac.h>

#include <string>

namespace mbsc::driver {

std::string canonical_text(const GiNaC::ex& e, bool latex);

}  // namespace mbsc::driver
