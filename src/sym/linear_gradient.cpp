// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/sym/linear_gradient.hpp"

#include <map>
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

/// The gradient of an expression that is linear in the symbols of `index` but nests them
/// (a dependent rate from back substitution: sums of products whose factors are sums
/// again, sharing subexpressions). Each distinct subexpression is visited once, where
/// GiNaC's diff, which knows nothing of sharing, revisits a shared one on every path to
/// it (exponential in the nesting of a chain). Shapes that are not linear (a symbol
/// inside a power or a function, two factors holding symbols) go to diff.
class SharedGradient {
 public:
  using Sparse = std::map<int, GiNaC::ex>;
  SharedGradient(const std::unordered_map<GiNaC::ex, int, ExHash, GiNaC::ex_is_equal>& index,
                 const std::vector<GiNaC::symbol>& by)
      : index_(index), by_(by) {}

  const Sparse& of(const GiNaC::ex& t) {
    const auto* key = &GiNaC::ex_to<GiNaC::basic>(t);
    if (const auto hit = memo_.find(key); hit != memo_.end()) return hit->second.second;
    Sparse g;
    if (GiNaC::is_a<GiNaC::symbol>(t)) {
      if (const auto hit = index_.find(t); hit != index_.end()) g[hit->second] = 1;
    } else if (!holds(t)) {
    } else if (GiNaC::is_a<GiNaC::add>(t)) {
      std::map<int, GiNaC::exvector> terms;
      for (std::size_t i = 0; i < t.nops(); ++i)
        for (const auto& [j, a] : of(t.op(i))) terms[j].push_back(a);
      for (auto& [j, list] : terms) g[j] = list.size() == 1 ? list.front() : GiNaC::ex(GiNaC::add(list));
    } else if (GiNaC::is_a<GiNaC::mul>(t) && holding_factors(t) == 1) {
      std::size_t k = 0;
      while (!holds(t.op(k))) ++k;
      GiNaC::exvector rest;
      for (std::size_t i = 0; i < t.nops(); ++i)
        if (i != k) rest.push_back(t.op(i));
      const GiNaC::ex others = GiNaC::mul(rest);
      for (const auto& [j, a] : of(t.op(k))) g[j] = others * a;
    } else {
      for (std::size_t j = 0; j < by_.size(); ++j) {
        const GiNaC::ex d = t.diff(by_[j]);
        if (!d.is_zero()) g[static_cast<int>(j)] = d;
      }
    }
    return memo_.emplace(key, std::make_pair(t, std::move(g))).first->second.second;
  }

 private:
  bool holds(const GiNaC::ex& t) {
    if (GiNaC::is_a<GiNaC::symbol>(t)) return index_.count(t) > 0;
    if (t.nops() == 0) return false;
    const auto* key = &GiNaC::ex_to<GiNaC::basic>(t);
    if (const auto hit = holds_.find(key); hit != holds_.end()) return hit->second.second;
    bool any = false;
    for (std::size_t i = 0; i < t.nops() && !any; ++i) any = holds(t.op(i));
    holds_.emplace(key, std::make_pair(t, any));
    return any;
  }

  int holding_factors(const GiNaC::ex& t) {
    int n = 0;
    for (std::size_t i = 0; i < t.nops(); ++i) n += holds(t.op(i)) ? 1 : 0;
    return n;
  }

  const std::unordered_map<GiNaC::ex, int, ExHash, GiNaC::ex_is_equal>& index_;
  const std::vector<GiNaC::symbol>& by_;
  // Keyed by the object; the ex is kept so that the object outlives the key.
  std::map<const GiNaC::basic*, std::pair<GiNaC::ex, Sparse>> memo_;
  std::map<const GiNaC::basic*, std::pair<GiNaC::ex, bool>> holds_;
};

}  // namespace

std::vector<GiNaC::ex> linear_gradient(const GiNaC::ex& e, const std::vector<GiNaC::symbol>& by) {
  std::vector<GiNaC::ex> out(by.size(), GiNaC::ex(0));
  std::unordered_map<GiNaC::ex, int, ExHash, GiNaC::ex_is_equal> index;
  for (std::size_t j = 0; j < by.size(); ++j) index.emplace(by[j], static_cast<int>(j));
  SharedGradient shared(index, by);
  if (!GiNaC::is_a<GiNaC::add>(e)) {
    for (const auto& [j, a] : shared.of(e)) out[static_cast<std::size_t>(j)] = a;
    return out;
  }
  std::vector<GiNaC::exvector> terms(by.size());
  for (std::size_t i = 0; i < e.nops(); ++i) {
    const GiNaC::ex t = e.op(i);
    const int j = linear_in(t, index);
    if (j == -1) continue;
    if (j >= 0) {
      // d(v * rest)/dv = rest: dividing by v cancels its factor (GiNaC's mul is canonical).
      terms[static_cast<std::size_t>(j)].push_back(t / by[static_cast<std::size_t>(j)]);
      continue;
    }
    for (const auto& [k, a] : shared.of(t)) terms[static_cast<std::size_t>(k)].push_back(a);
  }
  for (std::size_t j = 0; j < by.size(); ++j) {
    if (terms[j].size() == 1) out[j] = terms[j].front();
    else if (terms[j].size() > 1) out[j] = GiNaC::add(terms[j]);
  }
  return out;
}

}  // namespace mbsc::sym
