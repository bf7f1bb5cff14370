// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/sym/linear_gradient.hpp"

#include <unordered_map>

#include "mbsc/sym/symbol_set.hpp"

namespace mbsc::sym {
namespace {

/// The one symbol of `index` that t holds, -1 when none, -2 when several (or t is not
/// of the shape v * rest with v to the first power and nowhere else in t).
int linear_in(const GiNaC::ex& t, const std::unordered_map<GiNaC::ex, int, ExHash, GiNaC::ex_is_equal>& index) {
  int found = -1;
  for (GiNaC::const_preorder_iterator it = t.preorder_begin(); it != t.preorder_end(); ++it) {
    if (!GiNaC::is_a<GiNaC::symbol>(*it)) continue;
    const auto hit = index.find(*it);
    if (hit == index.end()) continue;
    if (found >= 0) return -2;  // twice, or two of them
    found = hit->second;
  }
  if (found < 0) return -1;
  if (GiNaC::is_a<GiNaC::symbol>(t)) return found;
  if (!GiNaC::is_a<GiNaC::mul>(t)) return -2;
  for (std::size_t i = 0; i < t.nops(); ++i) {
    const auto hit = index.find(t.op(i));
    if (hit != index.end() && hit->second == found) return found;
  }
  return -2;  // inside a power, a function or a nested sum
}

}  // namespace

std::vector<GiNaC::ex> linear_gradient(const GiNaC::ex& e, const std::vector<GiNaC::symbol>& by) {
  std::vector<GiNaC::ex> out(by.size());
  if (!GiNaC::is_a<GiNaC::add>(e)) {
    const SymbolSet in_e(e);
    for (std::size_t j = 0; j < by.size(); ++j) out[j] = in_e.diff(e, by[j]);
    return out;
  }
  std::unordered_map<GiNaC::ex, int, ExHash, GiNaC::ex_is_equal> index;
  for (std::size_t j = 0; j < by.size(); ++j) index.emplace(by[j], static_cast<int>(j));
  std::vector<GiNaC::exvector> terms(by.size());
  std::vector<bool> whole(by.size(), false);  // differentiate e itself by these
  for (std::size_t i = 0; i < e.nops(); ++i) {
    const GiNaC::ex t = e.op(i);
    const int j = linear_in(t, index);
    if (j == -1) continue;
    if (j >= 0) {
      // d(v * rest)/dv = rest: dividing by v cancels its factor (GiNaC's mul is canonical).
      terms[static_cast<std::size_t>(j)].push_back(t / by[static_cast<std::size_t>(j)]);
      continue;
    }
    const SymbolSet in_t(t);
    for (std::size_t k = 0; k < by.size(); ++k)
      if (in_t.contains(by[k])) whole[k] = true;
  }
  for (std::size_t j = 0; j < by.size(); ++j) {
    if (whole[j]) out[j] = e.diff(by[j]);
    else if (terms[j].empty()) out[j] = 0;
    else if (terms[j].size() == 1) out[j] = terms[j].front();
    else out[j] = GiNaC::add(terms[j]);
  }
  return out;
}

}  // namespace mbsc::sym
