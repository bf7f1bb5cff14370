// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/model/varying_part.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>

namespace mbsc::model {

namespace {

/// Every symbol e reads, looking through kinematic names into their values (each name
/// once: a deep chain's names share their parents', and the full expansion would repeat
/// them along every path).
using NameValues = std::map<GiNaC::ex, GiNaC::ex, GiNaC::ex_is_less>;

/// The model's names by symbol, built once per model (the checks of a build call
/// varying_part for every body: rebuilding it each time was quadratic in the names).
/// Recognised by its first and last name's symbols, which no other model shares.
const NameValues& name_values(const Model& m) {
  thread_local NameValues cached;
  thread_local GiNaC::ex first, last;
  thread_local std::size_t count = 0;
  const auto& names = m.kinematic_names;
  if (names.empty()) {
    static const NameValues none;
    return none;
  }
  if (count != names.size() || !first.is_equal(names.front().sym) || !last.is_equal(names.back().sym)) {
    cached.clear();
    for (const auto& k : names) cached.emplace(k.sym, k.value);
    first = names.front().sym;
    last = names.back().sym;
    count = names.size();
  }
  return cached;
}

GiNaC::exset symbols_read(const Model& m, const GiNaC::ex& e) {
  const NameValues& value_of = name_values(m);
  GiNaC::exset found;
  std::vector<GiNaC::ex> pending{e};
  while (!pending.empty()) {
    const GiNaC::ex next = pending.back();
    pending.pop_back();
    for (auto it = next.preorder_begin(); it != next.preorder_end(); ++it) {
      if (!GiNaC::is_a<GiNaC::symbol>(*it) || !found.insert(*it).second) continue;
      const auto name = value_of.find(*it);
      if (name != value_of.end()) pending.push_back(name->second);
    }
  }
  return found;
}

}  // namespace

std::string varying_part(const Model& m, const GiNaC::ex& named, const std::vector<int>& allowed_coords) {
  const GiNaC::exset read = symbols_read(m, named);
  for (std::size_t k = 0; k < m.coords.size(); ++k)
    if (std::find(allowed_coords.begin(), allowed_coords.end(), static_cast<int>(k)) == allowed_coords.end() &&
        read.count(m.coords[k].sym))
      return fmt::format("coordinate '{}'", m.coords[k].name);
  for (const auto& u : m.speeds)
    if (read.count(u.sym)) return fmt::format("speed '{}'", u.name);
  for (const auto& in : m.inputs)
    if (read.count(in.sym)) return fmt::format("input '{}'", in.name);
  if (read.count(m.time)) return "the time t";
  return "";
}

}  // namespace mbsc::model
