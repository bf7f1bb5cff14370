// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/print/canonical_text.hpp"

#include <algorithm>
#include <utility>
#include <sstream>
#include <vector>

#include "mbsc/print/latex_names.hpp"

namespace mbsc::print {
namespace {

// Binding strength, to decide parentheses: sum < product < power < atom.
enum Prec { kSum = 1, kProduct = 2, kPower = 3, kAtom = 4 };

struct Printed {
  std::string text;
  Prec prec;
  bool negative = false;  // text is "-..." (a sum prints it as " - ...")
  // Sums only: the text of the sum with its sign normalised (first term positive) and
  // whether that is the negated sum. GiNaC may hold either -(a - b) or (b - a).
  std::string normal_text{};
  bool normal_negated = false;
};

std::string symbol_text(const std::string& name, bool latex) {
  return latex ? latex_symbol(name, LatexSymbolScope::current()) : name;
}

std::string number_text(const GiNaC::numeric& n, bool latex) {
  auto str = [](const GiNaC::numeric& v) {
    std::ostringstream s;
    s << v;
    return s.str();
  };
  if (n.is_integer()) return str(n);
  if (n.is_rational()) {
    const std::string num = str(n.numer()), den = str(n.denom());
    return latex ? "\\frac{" + num + "}{" + den + "}" : num + "/" + den;
  }
  std::ostringstream s;
  s.precision(17);
  s << n.to_double();
  const std::string text = s.str();
  const auto e = text.find('e');
  if (!latex || e == std::string::npos) return text;
  // 1.5e-05 is 1.5 \cdot 10^{-5} in a formula.
  const int exponent = std::stoi(text.substr(e + 1));
  return text.substr(0, e) + " \\cdot 10^{" + std::to_string(exponent) + "}";
}

std::string wrap(const Printed& p, Prec need, bool latex) {
  if (p.prec >= need) return p.text;
  return latex ? "\\left(" + p.text + "\\right)" : "(" + p.text + ")";
}

Printed print(const GiNaC::ex& e, bool latex);
Printed print_product_plain(const GiNaC::ex& e, bool latex);

Printed print_sum(const GiNaC::ex& e, bool latex) {
  std::vector<Printed> terms;
  for (size_t i = 0; i < e.nops(); ++i) terms.push_back(print(e.op(i), latex));
  // Sort by the text without its sign, so a sum prints the same whatever GiNaC's order.
  auto key = [](const Printed& p) { return p.negative ? p.text.substr(1) : p.text; };
  std::sort(terms.begin(), terms.end(), [&](const Printed& a, const Printed& b) {
    return key(a) != key(b) ? key(a) < key(b) : a.negative < b.negative;
  });
  auto join = [&](bool flip) {
    std::string out;
    for (size_t i = 0; i < terms.size(); ++i) {
      const bool neg = terms[i].negative != flip;
      const std::string body = key(terms[i]);
      if (i == 0) out += neg ? "-" + body : body;
      else out += (neg ? " - " : " + ") + body;
    }
    return out;
  };
  Printed p{join(false), kSum, false};
  p.normal_negated = !terms.empty() && terms[0].negative;
  p.normal_text = join(p.normal_negated);
  return p;
}

Printed print_product_plain(const GiNaC::ex& e, bool latex) {
  GiNaC::numeric coeff(1);
  // Factors as a person orders them: sums first, then symbols and their powers, then
  // functions ((m1 + m2)*l1^2, l1*l2*m2*cos(th1 - th2)); by text within each group.
  std::vector<std::pair<int, std::string>> num, den;
  std::string lone_den;
  auto rank = [](const GiNaC::ex& f) {
    const GiNaC::ex b = GiNaC::is_a<GiNaC::power>(f) ? f.op(0) : f;
    return GiNaC::is_a<GiNaC::add>(b) ? 0 : GiNaC::is_a<GiNaC::function>(b) ? 2 : 1;
  };
  for (size_t i = 0; i < e.nops(); ++i) {
    const GiNaC::ex f = e.op(i);
    if (GiNaC::is_a<GiNaC::numeric>(f)) {
      coeff *= GiNaC::ex_to<GiNaC::numeric>(f);
    } else if (GiNaC::is_a<GiNaC::power>(f) && GiNaC::is_a<GiNaC::numeric>(f.op(1)) &&
               GiNaC::ex_to<GiNaC::numeric>(f.op(1)).is_negative()) {
      Printed d = print(GiNaC::pow(f.op(0), -f.op(1)), latex);
      if (d.negative && !d.text.empty() && d.text[0] == '-' && d.prec != kSum) {  // 1/(-sin(b - a))^3, 1/(b - a)^3
        coeff = -coeff;
        d = {d.text.substr(1), kPower};
      } else if (d.prec == kSum) {  // 1/(b - a): the sum sign-normalised, its sign to the coefficient
        if (d.normal_negated) coeff = -coeff;
        d.text = d.normal_text;
      }
      den.push_back({rank(f), wrap(d, kProduct, latex)});
      lone_den = d.text;  // a \frac's only denominator needs no parentheses
    } else {
      Printed pf = print(f, latex);
      // A sum factor is printed sign-normalised; its sign moves to the coefficient.
      if (GiNaC::is_a<GiNaC::add>(f)) {
        if (pf.normal_negated) coeff = -coeff;
        pf.text = pf.normal_text;
      } else if (GiNaC::is_a<GiNaC::power>(f) && GiNaC::is_a<GiNaC::add>(f.op(0)) && GiNaC::is_a<GiNaC::numeric>(f.op(1)) &&
                 GiNaC::ex_to<GiNaC::numeric>(f.op(1)).is_integer()) {
        Printed base = print(f.op(0), latex);
        const auto& k = GiNaC::ex_to<GiNaC::numeric>(f.op(1));
        if (base.normal_negated && k.is_odd()) coeff = -coeff;
        base.text = base.normal_text;
        const std::string expo = print(f.op(1), latex).text;
        pf.text = wrap(base, kAtom, latex) + (latex ? "^{" + expo + "}" : "^" + expo);
        pf.prec = kPower;
      } else if (pf.negative && !pf.text.empty() && pf.text[0] == '-') {
        // An odd function of a sign-normalised argument, -sin(b - a): the sign joins the coefficient.
        coeff = -coeff;
        pf.text = pf.text.substr(1);
        pf.negative = false;
        pf.prec = kAtom;
      }
      num.push_back({rank(f), wrap(pf, kProduct, latex)});
    }
  }
  std::sort(num.begin(), num.end());
  std::sort(den.begin(), den.end());
  const bool negative = coeff.is_negative();
  coeff = GiNaC::abs(coeff);
  const std::string times = latex ? " " : "*";
  std::string top;
  if (!coeff.is_equal(1) || num.empty()) top = number_text(coeff, latex);
  for (const auto& n : num) top += (top.empty() ? "" : times) + n.second;
  std::string out = top;
  if (!den.empty()) {
    std::string bottom;
    for (const auto& d : den) bottom += (bottom.empty() ? "" : times) + d.second;
    if (latex && den.size() == 1) bottom = lone_den;
    out = latex ? "\\frac{" + top + "}{" + bottom + "}" : top + "/" + (den.size() > 1 ? "(" + bottom + ")" : bottom);
  }
  return {negative ? "-" + out : out, kProduct, negative};
}

/// GiNaC keeps a product's numbers outside its sums, 1/3*(3*m2 + m1)*l^2; a person
/// writes (1/3*m1 + m2)*l^2. The number goes inside the one sum when that prints shorter.
Printed print_product(const GiNaC::ex& e, bool latex) {
  Printed plain = print_product_plain(e, latex);
  GiNaC::numeric c(1);
  GiNaC::ex sum;
  GiNaC::exvector others;
  int sums = 0;
  for (size_t i = 0; i < e.nops(); ++i) {
    const GiNaC::ex f = e.op(i);
    if (GiNaC::is_a<GiNaC::numeric>(f)) c *= GiNaC::ex_to<GiNaC::numeric>(f);
    else if (GiNaC::is_a<GiNaC::add>(f) && ++sums == 1) sum = f;
    else others.push_back(f);
  }
  if (sums != 1 || !c.is_rational() || c.is_equal(GiNaC::numeric(1)) || c.is_equal(GiNaC::numeric(-1))) return plain;
  const GiNaC::ex inside = (c * sum).expand();  // a number times a sum: GiNaC distributes it
  if (!GiNaC::is_a<GiNaC::add>(inside)) return plain;
  const Printed in = print(inside, latex);
  std::string text = (latex ? "\\left(" : "(") + in.normal_text + (latex ? "\\right)" : ")");
  bool negative = in.normal_negated;
  if (!others.empty()) {
    Printed rest = print(GiNaC::mul(others), latex);
    // Its sign joins the product's (1/(b - a) prints as -1/(a - b): the sign of a sum
    // inside is GiNaC's run-dependent choice).
    if (rest.negative && !rest.text.empty() && rest.text[0] == '-') {
      rest.text = rest.text.substr(1);
      negative = !negative;
    }
    text += (latex ? " " : "*") + wrap(rest, kProduct, latex);
  }
  if (text.size() >= (plain.negative ? plain.text.size() - 1 : plain.text.size())) return plain;
  return {negative ? "-" + text : text, kProduct, negative};
}

Printed print(const GiNaC::ex& e, bool latex) {
  if (GiNaC::is_a<GiNaC::numeric>(e)) {
    const auto& n = GiNaC::ex_to<GiNaC::numeric>(e);
    const std::string t = number_text(GiNaC::abs(n), latex);
    return {n.is_negative() ? "-" + t : t, n.is_negative() ? kProduct : kAtom, n.is_negative()};
  }
  if (GiNaC::is_a<GiNaC::symbol>(e)) return {symbol_text(GiNaC::ex_to<GiNaC::symbol>(e).get_name(), latex), kAtom};
  if (GiNaC::is_a<GiNaC::add>(e)) return print_sum(e, latex);
  if (GiNaC::is_a<GiNaC::mul>(e)) return print_product(e, latex);
  if (GiNaC::is_a<GiNaC::power>(e)) {
    if (GiNaC::is_a<GiNaC::numeric>(e.op(1)) && GiNaC::ex_to<GiNaC::numeric>(e.op(1)).is_negative())
    {
      Printed inv = print(GiNaC::pow(e.op(0), -e.op(1)), latex);
      bool negative = inv.negative && inv.prec != kSum && !inv.text.empty() && inv.text[0] == '-';
      if (negative) inv = {inv.text.substr(1), kPower};  // 1/(-sin(b - a))^3 = -1/sin(a - b)^3
      if (inv.prec == kSum) {  // 1/(b - a): the sum sign-normalised (see the powers below)
        negative = inv.normal_negated;
        inv.text = inv.normal_text;
      }
      const std::string t = latex ? "\\frac{1}{" + inv.text + "}" : "1/" + wrap(inv, kPower, latex);
      return {negative ? "-" + t : t, kProduct, negative};
    }
    if (latex && e.op(1).is_equal(GiNaC::numeric(1, 2))) return {"\\sqrt{" + print(e.op(0), latex).text + "}", kAtom};
    Printed b = print(e.op(0), latex);
    const bool integer = GiNaC::is_a<GiNaC::numeric>(e.op(1)) && GiNaC::ex_to<GiNaC::numeric>(e.op(1)).is_integer();
    bool negative = false;
    if (GiNaC::is_a<GiNaC::add>(e.op(0)) && integer) {
      // An integer power of a sum, (a - b)^n: GiNaC keeps either sign of the sum inside,
      // by its run-dependent term order. The sum is printed sign-normalised, and an odd
      // power takes the sign out.
      negative = b.normal_negated && GiNaC::ex_to<GiNaC::numeric>(e.op(1)).is_odd();
      b.text = b.normal_text;
    } else if (b.negative && GiNaC::is_a<GiNaC::function>(e.op(0)) && integer) {
      // (-sin(b - a))^n: an odd function of a sign-normalised argument; the sign leaves the power.
      b = {b.text.substr(1), kAtom};
      negative = GiNaC::ex_to<GiNaC::numeric>(e.op(1)).is_odd();
    }
    const std::string base = wrap(b, kAtom, latex);
    const std::string expo = print(e.op(1), latex).text;
    const std::string t = latex ? base + "^{" + expo + "}" : base + "^" + (expo.size() > 1 ? "(" + expo + ")" : expo);
    if (negative) return {"-" + t, kProduct, true};
    return {t, kPower};
  }
  if (GiNaC::is_a<GiNaC::function>(e)) {
    const std::string name = GiNaC::ex_to<GiNaC::function>(e).get_name();
    // f(a - b) or f(b - a)? Use the sign-normalised argument; odd functions move the sign out.
    if (e.nops() == 1 && GiNaC::is_a<GiNaC::add>(e.op(0))) {
      const Printed arg = print(e.op(0), latex);
      const bool even = name == "cos" || name == "cosh" || name == "abs";
      const bool odd = name == "sin" || name == "tan" || name == "sinh" || name == "tanh" || name == "asin" || name == "atan";
      if (arg.normal_negated && (even || odd)) {
        const std::string t = latex ? latex_call(name, arg.normal_text) : name + "(" + arg.normal_text + ")";
        if (even) return {t, kAtom};
        return {"-" + t, kProduct, true};
      }
    }
    std::string args;
    for (size_t i = 0; i < e.nops(); ++i) args += (i ? ", " : "") + print(e.op(i), latex).text;
    if (latex) return {latex_call(name, args), kAtom};
    return {name + "(" + args + ")", kAtom};
  }
  if (e.is_equal(GiNaC::Pi)) return {latex ? "\\pi" : "pi", kAtom};
  std::ostringstream s;
  s << e;
  return {s.str(), kAtom};
}

}  // namespace

std::string canonical_text(const GiNaC::ex& e, bool latex) { return print(e, latex).text; }

namespace {
thread_local const std::map<std::string, std::string>* latex_scope = nullptr;  // the innermost LatexSymbolScope's
}  // namespace

LatexSymbolScope::LatexSymbolScope(const std::map<std::string, std::string>& symbols) : outer_(latex_scope) {
  latex_scope = &symbols;
}

LatexSymbolScope::~LatexSymbolScope() { latex_scope = outer_; }

const std::map<std::string, std::string>& LatexSymbolScope::current() {
  static const std::map<std::string, std::string> none;
  return latex_scope ? *latex_scope : none;
}

}  // namespace mbsc::print
