// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/print/display_simplify.hpp"

#include <algorithm>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "mbsc/model/exact_guard.hpp"
#include "mbsc/print/canonical_text.hpp"
#include "mbsc/sym/common_factors.hpp"
#include "mbsc/sym/structural_size.hpp"
#include "mbsc/sym/tidy.hpp"

namespace mbsc::print {
namespace {

/// Thrown when one expression's work budget is spent: it is simplified part by part.
struct Abandon {};
/// Thrown when the whole call's budget is spent: the caller prints the plain form.
struct AbandonAll {};
/// The whole call may do this many times the work of one expression.
constexpr std::size_t kTotalWorkFactor = 8;

/// Largest integer multiple of an angle written out (sin(3*x) is expanded, sin(20*x) is an angle of its own).
constexpr int kMaxMultiple = 8;

bool is_trig(const GiNaC::ex& e) { return GiNaC::is_the_function<GiNaC::sin_SERIAL>(e) || GiNaC::is_the_function<GiNaC::cos_SERIAL>(e); }

/// The text of e, of -e for a sum whose text starts with a minus: the same for a sum
/// that GiNaC holds with either sign (inside a product, by its run-dependent term order).
std::string sign_free_text(const GiNaC::ex& e) {
  std::string text = canonical_text(e, false);
  if (GiNaC::is_a<GiNaC::add>(e) && text.front() == '-') text = canonical_text(-e, false);
  return text;
}

/// The terms of a sum or the factors of a product (e itself otherwise) in the order of
/// their text. The simplifier spends its budgets as it goes, so what it simplifies before
/// a budget runs out depends on the order it visits the parts in: GiNaC's order changes
/// from run to run, the text's does not.
GiNaC::exvector parts_by_text(const GiNaC::ex& e) {
  const bool split = GiNaC::is_a<GiNaC::add>(e) || GiNaC::is_a<GiNaC::mul>(e);
  std::vector<std::pair<std::string, GiNaC::ex>> parts;
  for (std::size_t i = 0; i < (split ? e.nops() : 1); ++i) {
    const GiNaC::ex p = split ? e.op(i) : e;
    parts.push_back({sign_free_text(p), p});
  }
  std::stable_sort(parts.begin(), parts.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  GiNaC::exvector out;
  for (auto& p : parts) out.push_back(std::move(p.second));
  return out;
}

}  // namespace

std::size_t node_count(const GiNaC::ex& e, std::size_t limit) { return sym::structural_size(e, limit); }

namespace {

/// An angle argument as integer multiples of atoms: x - 2*y -> {(x, 1), (y, -2)}.
std::vector<std::pair<GiNaC::ex, int>> split_angle(const GiNaC::ex& arg) {
  std::vector<std::pair<GiNaC::ex, int>> out;
  const GiNaC::ex a = arg.expand();
  const std::size_t n = GiNaC::is_a<GiNaC::add>(a) ? a.nops() : 1;
  for (std::size_t i = 0; i < n; ++i) {
    const GiNaC::ex t = GiNaC::is_a<GiNaC::add>(a) ? a.op(i) : a;
    GiNaC::numeric c(1);
    if (GiNaC::is_a<GiNaC::numeric>(t)) c = GiNaC::ex_to<GiNaC::numeric>(t);
    else if (GiNaC::is_a<GiNaC::mul>(t))
      for (std::size_t j = 0; j < t.nops(); ++j)
        if (GiNaC::is_a<GiNaC::numeric>(t.op(j))) c *= GiNaC::ex_to<GiNaC::numeric>(t.op(j));
    if (c.is_integer() && GiNaC::abs(c) <= kMaxMultiple && !c.is_zero()) out.push_back({t / c, c.to_int()});
    else if (c.is_negative()) out.push_back({-t, -1});
    else out.push_back({t, 1});
  }
  return out;
}

/// A wave is cos(k.theta) or sin(k.theta) over the atoms theta; a series sums them
/// with exact coefficients. Keys are normalised: the first nonzero k is positive.
using WaveKey = std::pair<std::vector<int>, bool>;  // (k, is sine)
using Series = std::map<WaveKey, GiNaC::numeric>;

void add_wave(Series& s, std::vector<int> k, bool sine, GiNaC::numeric c) {
  auto first = std::find_if(k.begin(), k.end(), [](int v) { return v != 0; });
  if (first == k.end()) {
    if (sine) return;  // sin(0)
  } else if (*first < 0) {
    for (int& v : k) v = -v;
    if (sine) c = -c;
  }
  GiNaC::numeric& slot = s[{k, sine}];
  slot += c;
  if (slot.is_zero()) s.erase({k, sine});
}

/// The product of two series by cos a cos b = (cos(a-b) + cos(a+b))/2 and its siblings.
Series multiply(const Series& a, const Series& b, std::size_t& work, std::size_t& total, std::size_t budget) {
  work += a.size() * b.size();
  total += a.size() * b.size();
  if (total > kTotalWorkFactor * budget) throw AbandonAll{};
  if (work > budget) throw Abandon{};
  Series out;
  const GiNaC::numeric half(1, 2);
  for (const auto& [ka, ca] : a)
    for (const auto& [kb, cb] : b) {
      std::vector<int> sum(ka.first.size()), diff(ka.first.size());
      for (std::size_t i = 0; i < sum.size(); ++i) {
        sum[i] = ka.first[i] + kb.first[i];
        diff[i] = ka.first[i] - kb.first[i];
      }
      const GiNaC::numeric c = ca * cb * half;
      const bool sa = ka.second, sb = kb.second;
      if (!sa && !sb) {
        add_wave(out, diff, false, c);
        add_wave(out, sum, false, c);
      } else if (sa && sb) {
        add_wave(out, diff, false, c);
        add_wave(out, sum, false, -c);
      } else if (sa) {  // sin a cos b
        add_wave(out, sum, true, c);
        add_wave(out, diff, true, c);
      } else {  // cos a sin b
        add_wave(out, sum, true, c);
        add_wave(out, diff, true, -c);
      }
    }
  return out;
}

class Simplifier {
 public:
  explicit Simplifier(const DisplayLimits& limits) : lim_(limits) {}

  /// `either_sign`: e is a factor of a product or the base of a power, which GiNaC holds
  /// with either sign by its run-dependent term order when it is a sum. Such a sum is
  /// simplified with its sign normalised (its text's first term positive): the texts of a
  /// sum and of its negation differ in length, and that decides between the candidates.
  GiNaC::ex run(const GiNaC::ex& e, bool either_sign = false) {
    // Nothing to simplify (and nothing charged to the budgets: a key's sign, below, is a
    // number that one run has and another not).
    if (GiNaC::is_a<GiNaC::numeric>(e) || GiNaC::is_a<GiNaC::symbol>(e)) return e;
    if (node_count(e, lim_.max_nodes) > lim_.max_nodes) return sym::tidy(e);
    if (either_sign && GiNaC::is_a<GiNaC::add>(e) && canonical_text(e, false).front() == '-') return -simplify(-e);
    return simplify(e);
  }

 private:
  GiNaC::ex simplify(const GiNaC::ex& e) {
    const GiNaC::ex in = inner(e);
    if (model::expanded_terms(in) > lim_.max_expanded_terms) return piecewise(in);
    const GiNaC::ex x = in.expand();
    std::vector<GiNaC::ex> candidates;
    work_ = 0;
    try {
      candidates.push_back(fourier_form(x));
    } catch (const Abandon&) {
      return piecewise(in);
    }
    candidates.push_back(sym::common_factors(candidates.back()));
    candidates.push_back(squares_form(x));
    candidates.push_back(sym::tidy(in));
    candidates.push_back(sym::tidy(sym::common_factors(x)));
    // A product or power of sums, simplified factor by factor, keeps its shape.
    if (!GiNaC::is_a<GiNaC::add>(in)) candidates.push_back(piecewise(in));
    // A sum, its terms grouped by what they hold besides sines, cosines and symbols.
    if (GiNaC::is_a<GiNaC::add>(in) && grouping_) {
      const std::size_t total_before = total_;
      try {
        const GiNaC::ex g = grouped(in);
        if (!g.is_zero() || in.is_zero()) candidates.push_back(g);
      } catch (const AbandonAll&) {
        // Grouping spent the call's budget: drop it (once; the rest goes on without it).
        total_ = total_before;
        grouping_ = false;
      }
    }
    GiNaC::ex best = candidates.front();
    std::size_t best_size = measured_size(best);
    for (std::size_t i = 1; i < candidates.size(); ++i) {
      const std::size_t s = measured_size(candidates[i]);
      if (s < best_size) {
        best = candidates[i];
        best_size = s;
      }
    }
    return best;
  }

  /// An expression too large to expand as a whole: its parts one by one, the bases of
  /// powers included ((1 + sin(x)^2 + cos(x)^2 + ...)^9 still loses its sin^2 + cos^2).
  GiNaC::ex piecewise(const GiNaC::ex& e) {
    if (GiNaC::is_a<GiNaC::power>(e)) return GiNaC::pow(run(e.op(0), true), e.op(1));
    if (GiNaC::is_a<GiNaC::add>(e) || GiNaC::is_a<GiNaC::mul>(e)) {
      GiNaC::exvector ops;
      for (const auto& op : parts_by_text(e)) ops.push_back(run(op, GiNaC::is_a<GiNaC::mul>(e)));
      return sym::tidy(GiNaC::is_a<GiNaC::add>(e) ? GiNaC::ex(GiNaC::add(ops)) : GiNaC::ex(GiNaC::mul(ops)));
    }
    return sym::tidy(e);
  }

  /// A factor the expansion handles term by term: a number, a symbol, a sine or cosine,
  /// or a positive integer power of one.
  static bool plain_factor(const GiNaC::ex& f) {
    if (GiNaC::is_a<GiNaC::numeric>(f) || GiNaC::is_a<GiNaC::symbol>(f) || is_trig(f)) return true;
    return GiNaC::is_a<GiNaC::power>(f) && (GiNaC::is_a<GiNaC::symbol>(f.op(0)) || is_trig(f.op(0))) &&
           GiNaC::is_a<GiNaC::numeric>(f.op(1)) && GiNaC::ex_to<GiNaC::numeric>(f.op(1)).is_pos_integer();
  }

  /// The sum `in` with its terms grouped by their other factors (a power of a sum, a
  /// denominator, a function): each group is key * (sum of plain cofactors), the key
  /// simplified factor by factor and the cofactors' sum as a whole (sin^2 + cos^2 = 1
  /// and the folding of products into sums of angles within the group), without
  /// expanding the keys. Zero when grouping changes nothing (all terms plain).
  GiNaC::ex grouped(const GiNaC::ex& in) {
    struct Group {
      GiNaC::ex key, sum;
    };
    std::map<std::string, Group> groups;  // by the key's text: the same order in every run
    for (std::size_t i = 0; i < in.nops(); ++i) {
      const GiNaC::ex t = in.op(i);
      GiNaC::ex key = 1, cof = 1;
      const std::size_t nf = GiNaC::is_a<GiNaC::mul>(t) ? t.nops() : 1;
      for (std::size_t j = 0; j < nf; ++j) {
        const GiNaC::ex f = nf == 1 ? t : t.op(j);
        if (plain_factor(f)) cof *= f;
        else key *= f;
      }
      // A key whose text starts with a minus is negated (the signs of the sums in it are
      // GiNaC's run-dependent choice), so that groups are keyed and ordered alike.
      if (canonical_text(key, false).front() == '-') {
        key = -key;
        cof = -cof;
      }
      Group& g = groups[canonical_text(key, false)];
      g.key = key;
      g.sum += cof;
    }
    if (groups.size() == 1 && groups.begin()->second.key.is_equal(1)) return 0;
    GiNaC::exvector terms;
    for (const auto& [text, g] : groups) {
      (void)text;
      const GiNaC::ex sum = GiNaC::is_a<GiNaC::add>(g.sum) ? run(g.sum) : g.sum;
      terms.push_back(g.key.is_equal(1) ? sum : piecewise(g.key) * sum);
    }
    return sym::tidy(GiNaC::add(terms));
  }

  /// Simplifies what the expansion treats as opaque: the bases of negative or
  /// fractional powers and the arguments of functions other than sin and cos.
  GiNaC::ex inner(const GiNaC::ex& e) {
    if (GiNaC::is_a<GiNaC::power>(e)) {
      const GiNaC::ex n = e.op(1);
      if (GiNaC::is_a<GiNaC::numeric>(n) && GiNaC::ex_to<GiNaC::numeric>(n).is_pos_integer())
        return GiNaC::pow(inner(e.op(0)), n);
      if (GiNaC::is_a<GiNaC::symbol>(e.op(0))) return e;
      return GiNaC::pow(run(e.op(0), true), run(n));
    }
    if (GiNaC::is_a<GiNaC::function>(e)) {
      if (is_trig(e)) return e;
      GiNaC::exvector args;
      for (std::size_t i = 0; i < e.nops(); ++i) args.push_back(run(e.op(i)));
      GiNaC::ex out = e;
      for (std::size_t i = 0; i < args.size(); ++i) out.let_op(i) = args[i];
      return out;
    }
    if (GiNaC::is_a<GiNaC::add>(e) || GiNaC::is_a<GiNaC::mul>(e)) {
      GiNaC::exvector ops;
      for (const auto& op : parts_by_text(e)) ops.push_back(inner(op));
      return GiNaC::is_a<GiNaC::add>(e) ? GiNaC::ex(GiNaC::add(ops)) : GiNaC::ex(GiNaC::mul(ops));
    }
    return e;
  }

  /// cos(u)^n written as cos(u)^(n mod 2) (1 - sin(u)^2)^(n/2) in the expanded x, or
  /// the sine squares as cosines: sin^2 + cos^2 = 1 without folding products of sines
  /// and cosines into sums of angles. Angle by angle (in the order of their text), the
  /// shortest of the three (as is, to sines, to cosines) is kept.
  GiNaC::ex squares_form(const GiNaC::ex& x) {
    std::vector<std::pair<std::string, GiNaC::ex>> args;
    for (auto it = x.preorder_begin(); it != x.preorder_end(); ++it) {
      if (!GiNaC::is_a<GiNaC::power>(*it) || !is_trig(it->op(0))) continue;
      const GiNaC::ex u = it->op(0).op(0);
      if (std::none_of(args.begin(), args.end(), [&](const auto& a) { return a.second.is_equal(u); }))
        args.push_back({canonical_text(u, false), u});
    }
    std::stable_sort(args.begin(), args.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    GiNaC::ex best = x;
    std::size_t best_size = measured_size(sym::common_factors(x));
    for (const auto& [text, u] : args) {
      (void)text;
      GiNaC::ex round_best = best;
      for (bool to_sine : {true, false}) {
        const GiNaC::ex from = to_sine ? GiNaC::cos(u) : GiNaC::sin(u), to = to_sine ? GiNaC::sin(u) : GiNaC::cos(u);
        GiNaC::exvector terms;
        const std::size_t n = GiNaC::is_a<GiNaC::add>(best) ? best.nops() : 1;
        for (std::size_t i = 0; i < n; ++i) terms.push_back(reduce_power(n == 1 ? best : best.op(i), from, to));
        const GiNaC::ex y = GiNaC::add(terms);
        if (model::expanded_terms(y) > lim_.max_expanded_terms) continue;
        const GiNaC::ex candidate = sym::common_factors(y.expand());
        const std::size_t size = measured_size(candidate);
        if (size < best_size) {
          round_best = candidate.expand();
          best_size = size;
        }
      }
      best = round_best;
    }
    return sym::common_factors(best);
  }

  /// In one term (or factor): from^n -> from^(n mod 2) (1 - to^2)^(n/2).
  static GiNaC::ex reduce_power(const GiNaC::ex& t, const GiNaC::ex& from, const GiNaC::ex& to) {
    if (GiNaC::is_a<GiNaC::power>(t) && t.op(0).is_equal(from) && GiNaC::is_a<GiNaC::numeric>(t.op(1)) &&
        GiNaC::ex_to<GiNaC::numeric>(t.op(1)).is_pos_integer()) {
      const int n = GiNaC::ex_to<GiNaC::numeric>(t.op(1)).to_int();
      return GiNaC::pow(from, n % 2) * GiNaC::pow(1 - GiNaC::pow(to, 2), n / 2);
    }
    if (!GiNaC::is_a<GiNaC::mul>(t)) return t;
    GiNaC::exvector factors;
    for (std::size_t i = 0; i < t.nops(); ++i) factors.push_back(reduce_power(t.op(i), from, to));
    return GiNaC::mul(factors);
  }

  /// The atoms of the angles in x, in the order of their text (so that a wave's sign
  /// normalisation, and hence the output, is the same in every run).
  void collect_atoms(const GiNaC::ex& x) {
    atoms_.clear();
    std::vector<std::pair<std::string, GiNaC::ex>> found;
    for (auto it = x.preorder_begin(); it != x.preorder_end(); ++it) {
      if (!is_trig(*it)) continue;
      for (const auto& part : split_angle(it->op(0))) {
        const GiNaC::ex& atom = part.first;  // (a lambda cannot capture a structured binding in C++17)
        const bool seen = std::any_of(found.begin(), found.end(), [&](const auto& f) { return f.second.is_equal(atom); });
        if (!seen) found.push_back({canonical_text(atom, false), atom});
      }
    }
    std::stable_sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& f : found) atoms_.push_back(f.second);
  }

  Series wave_of(const GiNaC::ex& trig) const {
    std::vector<int> k(atoms_.size(), 0);
    for (const auto& [atom, n] : split_angle(trig.op(0)))
      for (std::size_t i = 0; i < atoms_.size(); ++i)
        if (atoms_[i].is_equal(atom)) k[i] += n;
    Series s;
    add_wave(s, k, GiNaC::is_the_function<GiNaC::sin_SERIAL>(trig), 1);
    return s;
  }

  /// x (expanded) as a sum of coefficient * wave, coefficients expanded.
  std::map<WaveKey, GiNaC::ex> waves(const GiNaC::ex& x) {
    collect_atoms(x);
    std::map<WaveKey, GiNaC::ex> out;
    // Terms and factors in text order: the work they cost is charged as they come.
    for (const GiNaC::ex& term : GiNaC::is_a<GiNaC::add>(x) ? parts_by_text(x) : GiNaC::exvector{x}) {
      Series s;
      add_wave(s, std::vector<int>(atoms_.size(), 0), false, 1);
      GiNaC::ex coeff = 1;
      int degree = 0;
      for (const GiNaC::ex& f : parts_by_text(term)) {
        int times = 0;
        GiNaC::ex base;
        if (is_trig(f)) {
          times = 1;
          base = f;
        } else if (GiNaC::is_a<GiNaC::power>(f) && is_trig(f.op(0)) && GiNaC::is_a<GiNaC::numeric>(f.op(1)) &&
                   GiNaC::ex_to<GiNaC::numeric>(f.op(1)).is_pos_integer() &&
                   GiNaC::ex_to<GiNaC::numeric>(f.op(1)) <= lim_.max_trig_degree) {
          times = GiNaC::ex_to<GiNaC::numeric>(f.op(1)).to_int();
          base = f.op(0);
        }
        if (times == 0) {
          coeff *= f;
          continue;
        }
        degree += times;
        if (degree > lim_.max_trig_degree) throw Abandon{};
        const Series w = wave_of(base);
        for (int r = 0; r < times; ++r) s = multiply(s, w, work_, total_, lim_.max_wave_terms);
      }
      for (const auto& [key, c] : s) out[key] += coeff * c;
    }
    return out;
  }

  GiNaC::ex angle(const std::vector<int>& k) const {
    GiNaC::ex a = 0;
    for (std::size_t i = 0; i < k.size(); ++i) a += k[i] * atoms_[i];
    return a;
  }

  static GiNaC::ex tidy_coeff(const GiNaC::ex& c) { return sym::common_factors(c.expand()); }

  /// A sum of waves, with extra terms (squares standing for double angles).
  GiNaC::ex rebuild(const std::map<WaveKey, GiNaC::ex>& w, const GiNaC::exvector& extra) const {
    GiNaC::exvector terms;
    for (const auto& [key, c] : w) {
      const GiNaC::ex coeff = tidy_coeff(c);
      if (coeff.is_zero()) continue;
      const bool zero = std::all_of(key.first.begin(), key.first.end(), [](int v) { return v == 0; });
      if (zero) terms.push_back(coeff);
      else terms.push_back(coeff * (key.second ? GiNaC::sin(angle(key.first)) : GiNaC::cos(angle(key.first))));
    }
    for (const auto& e : extra) terms.push_back(e);
    return GiNaC::add(terms);
  }

  /// The Fourier form, then, atom by atom, cos(2u) written as 1 - 2 sin(u)^2 or
  /// 2 cos(u)^2 - 1 and sin(2u) as 2 sin(u) cos(u) where that is shorter.
  GiNaC::ex fourier_form(const GiNaC::ex& x) {
    auto w = waves(x);
    GiNaC::exvector extra;
    GiNaC::ex best = rebuild(w, extra);
    std::size_t best_size = measured_size(best);
    const std::vector<int> zero(atoms_.size(), 0);
    // The double angles present, in key order: k with every entry even.
    std::vector<std::vector<int>> doubles;
    for (const auto& [key, c] : w) {
      (void)c;
      const bool even = std::all_of(key.first.begin(), key.first.end(), [](int v) { return v % 2 == 0; });
      if (even && key.first != zero && (doubles.empty() || doubles.back() != key.first)) doubles.push_back(key.first);
    }
    for (const auto& k2 : doubles) {
      std::vector<int> k1 = k2;
      for (int& v : k1) v /= 2;
      const GiNaC::ex u = angle(k1);
      // Each variant: the wave replaced, the constant it leaves per unit coefficient, the square.
      struct Variant {
        bool sine;
        int constant;
        GiNaC::ex square;
      };
      const Variant variants[] = {{false, 1, -2 * GiNaC::pow(GiNaC::sin(u), 2)},
                                  {false, -1, 2 * GiNaC::pow(GiNaC::cos(u), 2)},
                                  {true, 0, 2 * GiNaC::sin(u) * GiNaC::cos(u)}};
      // The best of the variants for this angle, kept when it beats what is there.
      std::map<WaveKey, GiNaC::ex> keep_w;
      GiNaC::exvector keep_extra;
      bool improved = false;
      for (const auto& v : variants) {
        auto it = w.find({k2, v.sine});
        if (it == w.end()) continue;
        auto trial = w;
        const GiNaC::ex c = it->second;
        trial.erase({k2, v.sine});
        if (v.constant != 0) trial[{zero, false}] += v.constant * c;
        GiNaC::exvector trial_extra = extra;
        trial_extra.push_back(tidy_coeff(c) * v.square);
        const GiNaC::ex candidate = rebuild(trial, trial_extra);
        const std::size_t s = measured_size(candidate);
        if (s < best_size) {
          best = candidate;
          best_size = s;
          keep_w = std::move(trial);
          keep_extra = std::move(trial_extra);
          improved = true;
        }
      }
      if (improved) {
        w = std::move(keep_w);
        extra = std::move(keep_extra);
      }
    }
    return best;
  }

  /// display_size, with the characters printed charged to the whole call: comparing
  /// candidates prints them, and on a big expression the printing itself is the cost.
  std::size_t measured_size(const GiNaC::ex& e) {
    const std::size_t n = display_size(e);
    printed_ += n;
    if (printed_ > lim_.max_printed_chars) throw AbandonAll{};
    return n;
  }

  const DisplayLimits& lim_;
  std::vector<GiNaC::ex> atoms_;
  std::size_t work_ = 0;   // this expression's products of waves
  std::size_t total_ = 0;  // the whole call's
  bool grouping_ = true;   // false once grouping ran out of budget
  std::size_t printed_ = 0;  // characters printed to compare candidates, the whole call
};

}  // namespace

std::size_t display_size(const GiNaC::ex& e) { return canonical_text(e, false).size(); }

GiNaC::ex display_simplify(const GiNaC::ex& e, const DisplayLimits& limits) {
  try {
    Simplifier s(limits);
    return s.run(e);
  } catch (const AbandonAll&) {
  } catch (const Abandon&) {
  } catch (const std::exception&) {
    // GiNaC refuses something (a pole while evaluating): the plain form is still right.
  }
  return sym::tidy(e);
}

}  // namespace mbsc::print
