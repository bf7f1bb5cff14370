// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/model/exact_guard.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "mbsc/diag/limits.hpp"

namespace mbsc::model {

namespace {

constexpr double kLimit = static_cast<double>(limits::kMaxExactBits);

/// |x| of a real number as a double, saturating (the exponents here may be huge).
double magnitude(const GiNaC::numeric& x) { return x.is_real() ? std::fabs(approx_double(x)) : 0.0; }

std::string too_large(double bits) {
  return fmt::format("its exact value would need about {:.3g} bits (at most {})", bits, limits::kMaxExactBits);
}

}  // namespace

std::size_t exact_bits(const GiNaC::numeric& n) {
  std::size_t bits = 0;
  for (const GiNaC::numeric& part : {n.real(), n.imag()}) {
    if (!part.is_rational()) continue;
    bits = std::max<std::size_t>(bits, static_cast<std::size_t>(part.numer().int_length()));
    bits = std::max<std::size_t>(bits, static_cast<std::size_t>(part.denom().int_length()));
  }
  return bits;
}

long binary_exponent(const GiNaC::numeric& n) {
  if (!n.is_rational()) return 0;
  return static_cast<long>(n.numer().int_length()) - static_cast<long>(n.denom().int_length());
}

double approx_double(const GiNaC::numeric& n) {
  const GiNaC::numeric x = n.real();
  if (binary_exponent(x) > 1100) return x.is_negative() ? -HUGE_VAL : HUGE_VAL;
  if (binary_exponent(x) < -1100) return 0.0;
  try {
    return x.to_double();
  } catch (const std::exception&) {
    return x.is_negative() ? -HUGE_VAL : HUGE_VAL;
  }
}

GiNaC::ex subs_present(const GiNaC::ex& e, const GiNaC::exmap& values) {
  GiNaC::exmap used;
  for (GiNaC::const_preorder_iterator it = e.preorder_begin(); it != e.preorder_end(); ++it) {
    if (!GiNaC::is_a<GiNaC::symbol>(*it)) continue;
    const auto v = values.find(*it);
    if (v != values.end()) used.insert(*v);
  }
  return used.empty() ? e : e.subs(used, GiNaC::subs_options::no_pattern);
}

double growth_bits(const GiNaC::ex& e) {
  if (GiNaC::is_a<GiNaC::numeric>(e)) {
    const auto& n = GiNaC::ex_to<GiNaC::numeric>(e);
    // 0 and +-1 stay small under any power.
    if (n.is_zero() || n.is_equal(GiNaC::numeric(1)) || n.is_equal(GiNaC::numeric(-1))) return 0.0;
    return static_cast<double>(std::max<std::size_t>(exact_bits(n), 1));
  }
  if (GiNaC::is_a<GiNaC::power>(e) && GiNaC::is_a<GiNaC::numeric>(e.op(0)) && GiNaC::is_a<GiNaC::numeric>(e.op(1)))
    return growth_bits(e.op(0)) * magnitude(GiNaC::ex_to<GiNaC::numeric>(e.op(1)));
  if (GiNaC::is_a<GiNaC::mul>(e)) {
    double bits = 0.0;
    for (std::size_t i = 0; i < e.nops(); ++i) bits += growth_bits(e.op(i));
    return bits;
  }
  return 0.0;
}

std::string power_problem(const GiNaC::ex& base, const GiNaC::ex& exponent) {
  if (!GiNaC::is_a<GiNaC::numeric>(exponent)) return "";
  const double bits = growth_bits(base) * magnitude(GiNaC::ex_to<GiNaC::numeric>(exponent));
  return bits > kLimit ? too_large(bits) : "";
}

std::string product_problem(const GiNaC::exvector& factors) {
  // Every factor's numbers multiply into the product's coefficient (a divisor x^-1 was
  // already turned into its numbers' reciprocals by GiNaC).
  double bits = 0.0;
  for (const auto& f : factors) bits += growth_bits(f);
  return bits > kLimit ? too_large(bits) : "";
}

std::string sum_problem(const GiNaC::exvector& terms) {
  // Terms with a common denominator add cheaply (0.1 + 0.2 + ...); many different ones
  // multiply into the common denominator: bound it by their product.
  std::vector<GiNaC::numeric> denominators;
  double numerator_bits = 0.0;
  for (const auto& t : terms) {
    GiNaC::numeric c = 1;
    if (GiNaC::is_a<GiNaC::numeric>(t)) c = GiNaC::ex_to<GiNaC::numeric>(t);
    else if (GiNaC::is_a<GiNaC::mul>(t) && GiNaC::is_a<GiNaC::numeric>(t.op(t.nops() - 1)))
      c = GiNaC::ex_to<GiNaC::numeric>(t.op(t.nops() - 1));
    if (!c.is_rational()) continue;
    numerator_bits = std::max(numerator_bits, static_cast<double>(c.numer().int_length()));
    if (!c.denom().is_equal(GiNaC::numeric(1))) denominators.push_back(c.denom());
  }
  std::sort(denominators.begin(), denominators.end(),
            [](const GiNaC::numeric& a, const GiNaC::numeric& b) { return a < b; });
  denominators.erase(std::unique(denominators.begin(), denominators.end(),
                                 [](const GiNaC::numeric& a, const GiNaC::numeric& b) { return a.is_equal(b); }),
                     denominators.end());
  double bits = numerator_bits + std::log2(static_cast<double>(terms.size()) + 1.0);
  for (const auto& d : denominators) bits += static_cast<double>(d.int_length());
  return bits > kLimit ? too_large(bits) : "";
}

namespace {

/// The rebuilding walk of guarded_subs.
class GuardedSubs : public GiNaC::map_function {
 public:
  explicit GuardedSubs(const GiNaC::exmap& values) : values_(values) {}
  std::string why;

  GiNaC::ex operator()(const GiNaC::ex& e) override {
    if (!why.empty()) return e;
    if (GiNaC::is_a<GiNaC::symbol>(e)) {
      const auto it = values_.find(e);
      return it == values_.end() ? e : it->second;
    }
    if (GiNaC::is_a<GiNaC::numeric>(e) || GiNaC::is_a<GiNaC::constant>(e)) return e;
    if (GiNaC::is_a<GiNaC::power>(e)) {
      const GiNaC::ex base = (*this)(e.op(0)), exponent = (*this)(e.op(1));
      if (!why.empty()) return e;
      why = power_problem(base, exponent);
      return why.empty() ? GiNaC::pow(base, exponent) : e;
    }
    if (GiNaC::is_a<GiNaC::mul>(e) || GiNaC::is_a<GiNaC::add>(e)) {
      GiNaC::exvector ops;
      ops.reserve(e.nops());
      for (std::size_t i = 0; i < e.nops(); ++i) ops.push_back((*this)(e.op(i)));
      if (!why.empty()) return e;
      const bool product = GiNaC::is_a<GiNaC::mul>(e);
      why = product ? product_problem(ops) : sum_problem(ops);
      if (!why.empty()) return e;
      return product ? GiNaC::ex(GiNaC::mul(ops)) : GiNaC::ex(GiNaC::add(ops));
    }
    return e.map(*this);  // functions and the rest: their arguments, then GiNaC's eval
  }

 private:
  const GiNaC::exmap& values_;
};

}  // namespace

std::optional<GiNaC::ex> guarded_subs(const GiNaC::ex& e, const GiNaC::exmap& values, std::string& why) {
  GuardedSubs walk(values);
  GiNaC::ex out;
  try {
    out = walk(e);
  } catch (const std::exception& ex) {
    why = ex.what();
    return std::nullopt;
  }
  if (!walk.why.empty()) {
    why = walk.why;
    return std::nullopt;
  }
  return out;
}

double expanded_terms(const GiNaC::ex& e) {
  constexpr double kCap = 1e18;
  if (GiNaC::is_a<GiNaC::add>(e)) {
    double terms = 0.0;
    for (std::size_t i = 0; i < e.nops(); ++i) terms = std::min(kCap, terms + expanded_terms(e.op(i)));
    return terms;
  }
  if (GiNaC::is_a<GiNaC::mul>(e)) {
    double terms = 1.0;
    for (std::size_t i = 0; i < e.nops(); ++i) terms = std::min(kCap, terms * expanded_terms(e.op(i)));
    return terms;
  }
  if (GiNaC::is_a<GiNaC::power>(e) && GiNaC::is_a<GiNaC::numeric>(e.op(1))) {
    // normal() expands a denominator too: count |n| either way.
    const double n = magnitude(GiNaC::ex_to<GiNaC::numeric>(e.op(1)));
    const double base = expanded_terms(e.op(0));
    if (base <= 1.0) return 1.0;
    return std::min(kCap, std::pow(base, std::min(n, 64.0)));
  }
  return 1.0;
}

GiNaC::ex expand_if_small(const GiNaC::ex& e) {
  return expanded_terms(e) <= limits::kMaxExpandedTerms ? e.expand() : e;
}

GiNaC::ex normal_if_small(const GiNaC::ex& e) {
  return expanded_terms(e) <= limits::kMaxExpandedTerms ? e.normal() : e;
}

}  // namespace mbsc::model
