// SPDX-License-Identifier: GPL-2.0-or-later
/// Rewrites of a sum's terms, applied by Dag::make_add before the sum is interned.
///
/// GiNaC already collects like terms and never sees sin^2 + cos^2 as 1 unless asked; the
/// equations reach the DAG with their Define'd symbols substituted, so new pairs meet here
/// (the four-bar's reduced mass matrix has m l^2/4 cos^2(q) + m l^2/4 sin^2(q)). Two
/// rewrites, both exact identities, both shrinking the sum:
///   * like terms: c1*F + c2*F -> (c1 + c2)*F, numbers being terms with F = 1;
///   * Pythagorean pairs: F*sin(u)^2 + F*cos(u)^2 -> F.
/// They run to a fixed point (a folded pair's F may be a like term of another term, or
/// half of a further pair). Every choice is made in an order of the terms that a sum and
/// its negation share (by each term without its coefficient), and like terms' coefficients
/// are summed so that negated ones give exactly the negated sum: so the result depends on
/// structure only, never on GiNaC's order, and the terms negated give exactly the negated
/// result (GiNaC hands a sum over with either sign, from run to run), even where the
/// bound on the rounds cuts the rewrites short (the determinism rule of canonical_dag.hpp).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <map>
#include <unordered_map>
#include <utility>

#include "canonical_dag.hpp"

namespace mbsc::ir {

namespace {

// The argument of sin(u)^2 or cos(u)^2 (`is_cos` tells which), else -1.
NodeId squared_trig_argument(const Dag& dag, NodeId f, bool& is_cos) {
  const Node& n = dag.node(f);
  if (n.kind != NodeKind::Pow) return -1;
  const Node& e = dag.node(dag.child(f, 1));
  if (e.kind != NodeKind::Number || e.value != 2.0) return -1;
  const NodeId base = dag.child(f, 0);
  const Node& b = dag.node(base);
  if (b.kind != NodeKind::Call) return -1;
  if (b.func != static_cast<std::uint8_t>(Func::Sin) && b.func != static_cast<std::uint8_t>(Func::Cos)) return -1;
  is_cos = b.func == static_cast<std::uint8_t>(Func::Cos);
  return dag.child(base, 0);
}

}  // namespace

double sign_symmetric_sum(std::vector<double> values) {
  // Positive and negative values apart, each from the smallest magnitude up: negating
  // every value swaps the two partial sums and negates each exactly, and a + b = b + a.
  std::sort(values.begin(), values.end(), [](double a, double b) { return std::fabs(a) < std::fabs(b); });
  double positive = 0.0, negative = 0.0;
  for (double v : values) (v > 0 ? positive : negative) += v;
  return positive + negative;
}

void Dag::flatten_factors(NodeId term, std::vector<NodeId>& factors, double& coef) const {
  const Node& n = node(term);
  if (n.kind == NodeKind::Number) {
    coef *= n.value;
  } else if (n.kind == NodeKind::Mul) {
    for (std::int32_t i = 0; i < n.nchild; ++i) flatten_factors(child(term, i), factors, coef);
  } else {
    factors.push_back(term);
  }
}

NodeId Dag::split_coefficient(NodeId term, double& coef) {
  coef = 1.0;
  const Node& n = node(term);
  if (n.kind == NodeKind::Number) {
    coef = n.value;
    return -1;
  }
  if (n.kind != NodeKind::Mul) return term;
  // Only a product holding a number (directly or in its invariant sub-product) has a
  // coefficient; the others are their own rest, without rebuilding anything.
  bool has_number = false;
  for (std::int32_t i = 0; i < n.nchild && !has_number; ++i) {
    const Node& c = node(child(term, i));
    if (c.kind == NodeKind::Number) has_number = true;
    if (c.kind != NodeKind::Mul) continue;
    for (std::int32_t k = 0; k < c.nchild; ++k) has_number = has_number || node(child(child(term, i), k)).kind == NodeKind::Number;
  }
  if (!has_number) return term;
  std::vector<NodeId> factors;
  flatten_factors(term, factors, coef);
  return make_mul(std::move(factors));
}

bool Dag::collect_like_terms(std::vector<NodeId>& terms) {
  std::vector<NodeId> rests(terms.size());
  std::vector<double> coefs(terms.size());
  std::unordered_map<NodeId, std::size_t> first;  // rest -> its first term (lookup only)
  std::vector<std::size_t> group(terms.size());
  bool any = false;
  for (std::size_t i = 0; i < terms.size(); ++i) {
    rests[i] = split_coefficient(terms[i], coefs[i]);
    const auto it = first.emplace(rests[i], i).first;
    group[i] = it->second;
    any = any || it->second != i;
  }
  if (!any) return false;
  // Each group's coefficients, summed so that the negated terms give exactly the negated
  // sum (sign_symmetric_sum), into the group's first term.
  std::vector<std::vector<double>> members(terms.size());
  for (std::size_t i = 0; i < terms.size(); ++i) members[group[i]].push_back(coefs[i]);
  std::vector<NodeId> out;
  for (std::size_t i = 0; i < terms.size(); ++i) {
    if (group[i] != i) continue;
    if (members[i].size() == 1) {
      out.push_back(terms[i]);
      continue;
    }
    const double sum = sign_symmetric_sum(std::move(members[i]));
    if (sum != 0.0) out.push_back(rests[i] < 0 ? make_number(sum) : make_mul({rests[i], make_number(sum)}));
  }
  terms = std::move(out);
  return true;
}

bool Dag::fold_pythagorean_pairs(std::vector<NodeId>& terms) {
  // Squared sines and cosines per argument, found without building anything.
  struct Square {
    std::size_t term;
    NodeId factor;
    NodeId arg;
    bool is_cos;
  };
  std::vector<Square> squares;
  for (std::size_t i = 0; i < terms.size(); ++i) {
    const Node& n = node(terms[i]);
    bool is_cos = false;
    if (n.kind == NodeKind::Pow) {
      const NodeId arg = squared_trig_argument(*this, terms[i], is_cos);
      if (arg >= 0) squares.push_back({i, terms[i], arg, is_cos});
      continue;
    }
    if (n.kind != NodeKind::Mul) continue;
    std::vector<NodeId> factors;
    double unused = 1.0;
    flatten_factors(terms[i], factors, unused);
    for (NodeId f : factors) {
      const NodeId arg = squared_trig_argument(*this, f, is_cos);
      if (arg >= 0) squares.push_back({i, f, arg, is_cos});
    }
  }
  if (squares.size() < 2) return false;
  // Arguments that have both a sin^2 and a cos^2 somewhere in the sum.
  std::map<NodeId, int> seen;  // arg -> bit 1: sin^2, bit 2: cos^2 (lookup only)
  for (const Square& s : squares) seen[s.arg] |= s.is_cos ? 2 : 1;
  // The rest of each candidate term (the term without that square), and the pairs.
  std::map<std::pair<NodeId, NodeId>, std::vector<std::size_t>> cos_terms;  // (arg, rest) -> terms (lookup only)
  std::vector<std::pair<std::size_t, NodeId>> sin_terms;                     // (term, key rest) in order
  std::vector<NodeId> sin_args;
  for (const Square& s : squares) {
    if (seen[s.arg] != 3) continue;
    std::vector<NodeId> factors;
    double coef = 1.0;
    flatten_factors(terms[s.term], factors, coef);
    factors.erase(std::find(factors.begin(), factors.end(), s.factor));
    if (coef != 1.0) factors.push_back(make_number(coef));
    const NodeId rest = make_mul(std::move(factors));
    if (s.is_cos) {
      cos_terms[{s.arg, rest}].push_back(s.term);
    } else {
      sin_terms.emplace_back(s.term, rest);
      sin_args.push_back(s.arg);
    }
  }
  std::vector<char> used(terms.size(), 0);
  bool any = false;
  for (std::size_t k = 0; k < sin_terms.size(); ++k) {
    const std::size_t i = sin_terms[k].first;
    if (used[i]) continue;
    const auto it = cos_terms.find({sin_args[k], sin_terms[k].second});
    if (it == cos_terms.end()) continue;
    for (std::size_t j : it->second) {
      if (used[j] || j == i) continue;
      used[i] = used[j] = 1;
      terms[i] = sin_terms[k].second;  // F sin^2 + F cos^2 = F
      terms[j] = -1;
      any = true;
      break;
    }
  }
  if (any) terms.erase(std::remove(terms.begin(), terms.end(), NodeId{-1}), terms.end());
  return any;
}

NodeId Dag::make_product_merging_powers(const std::vector<NodeId>& factors, double coef) {
  // (base, integer exponent) in the factors' order; other powers stay as they are.
  std::vector<std::pair<NodeId, double>> powers;
  std::vector<NodeId> out;
  for (NodeId f : factors) {
    NodeId base = f;
    double e = 1.0;
    if (node(f).kind == NodeKind::Pow && node(child(f, 1)).kind == NodeKind::Number) {
      e = node(child(f, 1)).value;
      base = child(f, 0);
      if (e != std::floor(e)) {
        out.push_back(f);
        continue;
      }
    }
    const auto it = std::find_if(powers.begin(), powers.end(), [base](const auto& p) { return p.first == base; });
    if (it == powers.end()) {
      powers.emplace_back(base, e);
    } else {
      it->second += e;
    }
  }
  for (const auto& [base, e] : powers) {
    if (e == 0.0) continue;
    out.push_back(e == 1.0 ? base : make_pow(base, make_number(e)));
  }
  if (coef != 1.0) out.push_back(make_number(coef));
  return make_mul(std::move(out));
}

bool Dag::distribute_into_like_terms(std::vector<NodeId>& terms) {
  // Wide sums are left alone: the search below is quadratic in the number of terms.
  constexpr std::size_t kMaxTerms = 64;
  constexpr std::int32_t kMaxFactorTerms = 8;
  const std::size_t n = terms.size();
  if (n < 2 || n > kMaxTerms) return false;
  const auto base_of = [this](NodeId f) {
    return node(f).kind == NodeKind::Pow && node(child(f, 1)).kind == NodeKind::Number ? child(f, 0) : f;
  };
  // Every term's factors and coefficient, and the sorted bases of its factors (node ids:
  // used only to test inclusion, never to order anything that is printed).
  std::vector<std::vector<NodeId>> factors(n), bases(n);
  std::vector<double> coefs(n, 1.0);
  for (std::size_t i = 0; i < n; ++i) {
    flatten_factors(terms[i], factors[i], coefs[i]);
    for (NodeId f : factors[i]) bases[i].push_back(base_of(f));
    std::sort(bases[i].begin(), bases[i].end());
  }
  std::vector<NodeId> rests(n, -2);  // split_coefficient of each term, made when first asked
  const auto rest_of = [&](std::size_t j) {
    if (rests[j] == -2) {
      double unused = 1.0;
      rests[j] = split_coefficient(terms[j], unused);
    }
    return rests[j];
  };
  // Term i distributed over its factor `sum` (factors[i][s]), when that merges or cancels
  // all but at most one of the new terms.
  const auto distribute = [&](std::size_t i, std::size_t s) {
    const NodeId sum = factors[i][s];
    std::vector<NodeId> others(factors[i].begin(), factors[i].begin() + static_cast<std::ptrdiff_t>(s));
    others.insert(others.end(), factors[i].begin() + static_cast<std::ptrdiff_t>(s) + 1, factors[i].end());
    // Cheap filter: a like term of c*a_k*G holds at least every base of G.
    std::vector<NodeId> g_bases;
    for (NodeId f : others) g_bases.push_back(base_of(f));
    std::sort(g_bases.begin(), g_bases.end());
    g_bases.erase(std::unique(g_bases.begin(), g_bases.end()), g_bases.end());
    bool candidate = false;
    for (std::size_t j = 0; j < n && !candidate; ++j) {
      if (j == i) continue;
      candidate = std::includes(bases[j].begin(), bases[j].end(), g_bases.begin(), g_bases.end());
    }
    if (!candidate) return false;
    std::vector<NodeId> expanded;
    int unmatched = 0;
    for (std::int32_t k = 0; k < node(sum).nchild && unmatched <= 1; ++k) {
      std::vector<NodeId> f = others;
      double c = coefs[i];
      flatten_factors(child(sum, k), f, c);
      const NodeId e = make_product_merging_powers(f, c);
      double unused = 1.0;
      const NodeId r = split_coefficient(e, unused);
      bool match = false;
      for (std::size_t j = 0; j < n && !match; ++j) match = j != i && rest_of(j) == r;
      unmatched += match ? 0 : 1;
      expanded.push_back(e);
    }
    if (unmatched > 1) return false;
    terms[i] = expanded[0];
    terms.insert(terms.end(), expanded.begin() + 1, expanded.end());
    return true;
  };
  for (std::size_t i = 0; i < n; ++i) {
    if (node(terms[i]).kind != NodeKind::Mul) continue;
    // Every sum factor in turn (in canonical order), not only the first: a*(c - 1) beside
    // -a*c distributes over c - 1 whichever of the two sums sorts first, so that the
    // forms GiNaC may hand over for one expression meet in one node.
    for (std::size_t s = 0; s < factors[i].size(); ++s) {
      const Node& f = node(factors[i][s]);
      if (f.kind == NodeKind::Add && f.nchild <= kMaxFactorTerms && distribute(i, s)) return true;
    }
  }
  return false;
}

void Dag::order_terms_sign_blind(std::vector<NodeId>& terms) {
  // Key: the term without its coefficient (a number's is -1, first), then the
  // coefficient's magnitude, then its sign. Only like terms share a rest, and
  // collect_like_terms and its sum do not depend on their order among themselves.
  struct Keyed {
    NodeId term, rest;
    double coef;
  };
  std::vector<Keyed> keyed;
  keyed.reserve(terms.size());
  for (NodeId t : terms) {
    double coef = 1.0;
    const NodeId rest = split_coefficient(t, coef);
    keyed.push_back({t, rest, coef});
  }
  std::sort(keyed.begin(), keyed.end(), [this](const Keyed& a, const Keyed& b) {
    if (a.rest != b.rest) {
      if (a.rest < 0 || b.rest < 0) return a.rest < 0;
      return less(a.rest, b.rest);
    }
    if (std::fabs(a.coef) != std::fabs(b.coef)) return std::fabs(a.coef) < std::fabs(b.coef);
    return a.coef > b.coef;
  });
  for (std::size_t i = 0; i < terms.size(); ++i) terms[i] = keyed[i].term;
}

void Dag::simplify_sum_terms(std::vector<NodeId>& terms) {
  // Each round shrinks the sum or removes a sum factor by distributing it (two rounds per
  // distribution: it, then the collection of what it made). The bound is far above what
  // a sum needs and only guards against a cycle nobody has met; were it reached, the
  // rounds are sign-equivariant (below), so the result would still not depend on the
  // sign GiNaC gave the sum.
  const std::size_t max_rounds = sum_round_limit_ > 0 ? sum_round_limit_ : 16 + 2 * terms.size();
  const auto by_structure = [this](NodeId a, NodeId b) { return less(a, b); };
  bool changed = true;
  for (std::size_t round = 0; changed && terms.size() >= 2 && round < max_rounds; ++round) {
    // Every choice of a round is made in an order that a sum and its negation share.
    order_terms_sign_blind(terms);
    changed = collect_like_terms(terms);
    changed = fold_pythagorean_pairs(terms) || changed;
    if (!changed) changed = distribute_into_like_terms(terms);
    terms.erase(std::remove_if(terms.begin(), terms.end(),
                               [this](NodeId c) { return node(c).kind == NodeKind::Number && node(c).value == 0.0; }),
                terms.end());
  }
  std::sort(terms.begin(), terms.end(), by_structure);
}

}  // namespace mbsc::ir
