// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Helpers of the print tests, independent of the simplifier under test: trigonometric
// equality by the tangent half-angle substitution (sin x = 2t/(1+t^2), cos x =
// (1-t^2)/(1+t^2) turns an identity of sines and cosines into one of rational
// functions, which GiNaC's normal() decides), and numeric evaluation.
#include <ginac/ginac.h>

#include <map>
#include <sstream>
#include <random>
#include <stdexcept>
#include <string>

namespace mbsc_test {

/// sin and cos of sums and integer multiples written with sin and cos of single symbols.
inline GiNaC::ex trig_expand(const GiNaC::ex& e) {
  if (GiNaC::is_a<GiNaC::symbol>(e) || GiNaC::is_a<GiNaC::numeric>(e)) return e;
  const bool s = GiNaC::is_the_function<GiNaC::sin_SERIAL>(e), c = GiNaC::is_the_function<GiNaC::cos_SERIAL>(e);
  if (s || c) {
    const GiNaC::ex arg = e.op(0).expand();
    GiNaC::ex first, rest;
    if (GiNaC::is_a<GiNaC::add>(arg)) {
      first = arg.op(0);
      rest = arg - first;
    } else if (GiNaC::is_a<GiNaC::mul>(arg) && GiNaC::is_a<GiNaC::numeric>(arg.op(arg.nops() - 1)) &&
               GiNaC::ex_to<GiNaC::numeric>(arg.op(arg.nops() - 1)).is_integer()) {
      const GiNaC::numeric n = GiNaC::ex_to<GiNaC::numeric>(arg.op(arg.nops() - 1));
      if (n.is_negative()) return s ? -trig_expand(GiNaC::sin(-arg)) : trig_expand(GiNaC::cos(-arg));
      first = arg / n;
      rest = arg - first;
    } else {
      return e;
    }
    const GiNaC::ex sa = trig_expand(GiNaC::sin(first)), ca = trig_expand(GiNaC::cos(first));
    const GiNaC::ex sb = trig_expand(GiNaC::sin(rest)), cb = trig_expand(GiNaC::cos(rest));
    return s ? sa * cb + ca * sb : ca * cb - sa * sb;
  }
  return e.map([](const GiNaC::ex& x) { return trig_expand(x); });
}

/// Whether a == b as functions of their symbols, sines and cosines of sums included.
inline bool trig_equal(const GiNaC::ex& a, const GiNaC::ex& b) {
  GiNaC::ex d = trig_expand(a - b);
  GiNaC::exset found;
  d.find(GiNaC::sin(GiNaC::wild()), found);
  d.find(GiNaC::cos(GiNaC::wild()), found);
  GiNaC::exmap half;
  std::map<std::string, GiNaC::symbol> t;
  for (const auto& f : found) {
    if (!GiNaC::is_a<GiNaC::symbol>(f.op(0))) throw std::runtime_error("trig_equal: an angle that is not a symbol");
    const std::string name = GiNaC::ex_to<GiNaC::symbol>(f.op(0)).get_name();
    if (!t.count(name)) t.emplace(name, GiNaC::symbol("t_" + name));
    const GiNaC::ex u = t.at(name);
    half[GiNaC::sin(f.op(0))] = 2 * u / (1 + u * u);
    half[GiNaC::cos(f.op(0))] = (1 - u * u) / (1 + u * u);
  }
  return d.subs(half).normal().is_zero();
}

/// e with numbers for its symbols, as a double (throws when a symbol is left).
inline double eval(const GiNaC::ex& e, const GiNaC::exmap& values) {
  const GiNaC::ex v = GiNaC::evalf(e.subs(values, GiNaC::subs_options::no_pattern));
  if (!GiNaC::is_a<GiNaC::numeric>(v)) {
    std::ostringstream s;
    s << v;
    throw std::runtime_error("eval: symbols left in " + s.str());
  }
  return GiNaC::ex_to<GiNaC::numeric>(v).to_double();
}

}  // namespace mbsc_test
