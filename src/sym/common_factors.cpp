// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/sym/common_factors.hpp"

#include <cstddef>
#include <vector>

namespace mbsc::sym {

namespace {

using GiNaC::ex;
using GiNaC::numeric;

/// One factor base^power of a term (power a positive integer; any other factor is its
/// own base with power 1).
struct Factor {
  ex base;
  numeric power;
};

struct Term {
  numeric coef = 1;
  std::vector<Factor> factors;
};

Term split_term(const ex& t) {
  Term out;
  auto add = [&out](const ex& f) {
    if (GiNaC::is_exactly_a<numeric>(f)) {
      out.coef *= GiNaC::ex_to<numeric>(f);
    } else if (GiNaC::is_exactly_a<GiNaC::power>(f) && GiNaC::is_exactly_a<numeric>(f.op(1)) &&
               GiNaC::ex_to<numeric>(f.op(1)).is_pos_integer()) {
      out.factors.push_back({f.op(0), GiNaC::ex_to<numeric>(f.op(1))});
    } else {
      out.factors.push_back({f, 1});
    }
  };
  if (GiNaC::is_exactly_a<GiNaC::mul>(t)) {
    for (std::size_t i = 0; i < t.nops(); ++i) add(t.op(i));
  } else {
    add(t);
  }
  return out;
}

ex power_of(const ex& base, const numeric& k) { return k.is_equal(1) ? base : GiNaC::pow(base, k); }

/// The sum of `terms` (each already processed) with its common factors outside.
ex collect_sum(const std::vector<ex>& terms) {
  std::vector<Term> split;
  split.reserve(terms.size());
  for (const ex& t : terms) split.push_back(split_term(t));
  // Rational content: gcd of the numerators over lcm of the denominators.
  bool rational = true;
  numeric num = 0, den = 1;
  for (const Term& t : split) {
    rational = rational && t.coef.is_rational();
    if (!rational) break;
    num = GiNaC::gcd(num, t.coef.numer());
    den = GiNaC::lcm(den, t.coef.denom());
  }
  const numeric content = rational && !num.is_zero() ? GiNaC::abs(num) / den : numeric(1);
  // A factor is common when every term holds it (a sum may appear negated: the same
  // factor up to sign), at its smallest power. The first term's factors are the
  // candidates; which term is first only decides the sign a common sum is written with.
  std::vector<Factor> common;
  for (const Factor& f : split.front().factors) {
    const bool is_sum = GiNaC::is_exactly_a<GiNaC::add>(f.base);
    const ex negated = is_sum ? ex(-f.base) : ex();
    numeric lowest = f.power;
    bool everywhere = true;
    for (std::size_t t = 1; t < split.size() && everywhere; ++t) {
      bool found = false;
      for (const Factor& g : split[t].factors) {
        if (g.base.is_equal(f.base) || (is_sum && g.base.is_equal(negated))) {
          found = true;
          if (g.power < lowest) lowest = g.power;
          break;
        }
      }
      everywhere = found;
    }
    if (everywhere) common.push_back({f.base, lowest});
  }
  if (common.empty() && content.is_equal(1)) return GiNaC::add(terms);
  // Each term without the common part: a negated sum factor (-s)^k is (-1)^k s^k.
  std::vector<ex> rest;
  rest.reserve(split.size());
  for (const Term& t : split) {
    numeric coef = t.coef / content;
    std::vector<ex> factors;
    for (const Factor& g : t.factors) {
      numeric power = g.power;
      for (const Factor& c : common) {
        const bool same = g.base.is_equal(c.base);
        if (!same && !(GiNaC::is_exactly_a<GiNaC::add>(c.base) && g.base.is_equal(-c.base))) continue;
        if (!same && power.is_odd()) coef = -coef;
        power -= c.power;
        if (!power.is_zero()) factors.push_back(power_of(c.base, power));
        power = 0;
        break;
      }
      if (!power.is_zero()) factors.push_back(power_of(g.base, power));
    }
    factors.push_back(coef);
    rest.push_back(GiNaC::mul(factors));
  }
  std::vector<ex> outside;
  for (const Factor& c : common) outside.push_back(power_of(c.base, c.power));
  outside.push_back(content);
  outside.push_back(GiNaC::add(rest));
  return GiNaC::mul(outside);
}

}  // namespace

ex common_factors(const ex& e) {
  if (GiNaC::is_exactly_a<GiNaC::add>(e)) {
    std::vector<ex> terms;
    terms.reserve(e.nops());
    for (std::size_t i = 0; i < e.nops(); ++i) terms.push_back(common_factors(e.op(i)));
    return collect_sum(terms);
  }
  if (e.nops() == 0) return e;
  return e.map(common_factors);
}

}  // namespace mbsc::sym
