// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// `mbsc print`: the labelled matrices of one subsystem, as text or LaTeX.
#include <string>
#include <vector>

#include "mbsc/model/model.hpp"
#include "mbsc/sym/eom.hpp"

namespace mbsc::driver {

/// what: any of "rates", "A", "B", "C", "S", "f", "fbar", "M", "h".
/// Throws std::invalid_argument for an unknown item.
std::string print_node(const model::Model& m, const sym::Eom& eom, int node, const std::vector<std::string>& what, bool latex);

}  // namespace mbsc::driver
