// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/sym/tidy.hpp"
#include "mbsc/model/exact_guard.hpp"
#include "mbsc/sym/common_factors.hpp"
#include "mbsc/sym/structural_size.hpp"

#include <algorithm>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace mbsc::sym {
namespace {

/// The structural size of e: the same in every run (a size decides what is kept).
std::size_t size_of(const GiNaC::ex& e) { return structural_size(e, std::numeric_limits<std::size_t>::max() - 1); }

bool small(const GiNaC::ex& e, std::size_t limit) { return structural_size(e, limit) <= limit; }

}  // namespace

GiNaC::ex pythagoras(const GiNaC::ex& e) {
  if (!small(e, 400)) return e;
  GiNaC::exset found;
  e.find(GiNaC::pow(GiNaC::cos(GiNaC::wild(0)), 2), found);
  // In the order of the angles' names: GiNaC orders an exset by hashes that change from
  // run to run, and the rewrites kept depend on the order they are tried in. Only plain
  // symbols (coordinates) are taken, whose names are stable.
  std::vector<std::pair<std::string, GiNaC::ex>> squares;
  for (const auto& sq : found)
    if (GiNaC::is_a<GiNaC::symbol>(sq.op(0).op(0))) squares.push_back({GiNaC::ex_to<GiNaC::symbol>(sq.op(0).op(0)).get_name(), sq});
  std::sort(squares.begin(), squares.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  GiNaC::ex best = e;
  std::size_t best_size = size_of(e);
  for (const auto& [name, sq] : squares) {
    const GiNaC::ex u = sq.op(0).op(0);
    if (!best.has(GiNaC::pow(GiNaC::sin(u), 2))) continue;
    const GiNaC::ex candidate =
        common_factors(model::expand_if_small(best.subs(sq == 1 - GiNaC::pow(GiNaC::sin(u), 2))));
    const std::size_t size = size_of(candidate);
    if (size < best_size) {
      best = candidate;
      best_size = size;
    }
  }
  return best;
}

GiNaC::ex tidy(const GiNaC::ex& e) {
  if (GiNaC::is_a<GiNaC::numeric>(e) || GiNaC::is_a<GiNaC::symbol>(e)) return e;  // nothing to tidy
  // Common-factor collection is quadratic in the size of a sum: large
  // expressions are left to the back end's CSE.
  if (!small(e, 400)) return e;
  // Common factors first, so that c*(sin(u)^2 + cos(u)^2) appears as a whole sum (by
  // structure: GiNaC's collect_common_factors depends on its term order).
  GiNaC::ex out = common_factors(e);
  const GiNaC::ex u = GiNaC::wild(0);
  out = out.subs(GiNaC::pow(GiNaC::sin(u), 2) + GiNaC::pow(GiNaC::cos(u), 2) == 1);
  return out;
}

}  // namespace mbsc::sym
