// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/model/varying_part.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace mbsc::model {

std::string varying_part(const Model& m, const GiNaC::ex& named, const std::vector<int>& allowed_coords) {
  const GiNaC::ex e = expand_kinematic_names(m, named);
  for (std::size_t k = 0; k < m.coords.size(); ++k)
    if (std::find(allowed_coords.begin(), allowed_coords.end(), static_cast<int>(k)) == allowed_coords.end() &&
        e.has(m.coords[k].sym))
      return fmt::format("coordinate '{}'", m.coords[k].name);
  for (const auto& u : m.speeds)
    if (e.has(u.sym)) return fmt::format("speed '{}'", u.name);
  for (const auto& in : m.inputs)
    if (e.has(in.sym)) return fmt::format("input '{}'", in.name);
  if (e.has(m.time)) return "the time t";
  return "";
}

}  // namespace mbsc::model
