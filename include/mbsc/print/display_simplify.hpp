// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The simplifier of `mbsc print` (never of code generation, where operation counts
/// rule): equations in the form a person writes them. It applies sin^2 + cos^2 = 1 in
/// every form, folds products of sines and cosines into sin/cos of sums and differences
/// of angles (cos(th1)*cos(th2) + sin(th1)*sin(th2) -> cos(th1 - th2)), and collects
/// common factors ((m1 + m2)*l1^2). Only identities are used, so the value never changes.
///
/// How: the trigonometric part of the expanded expression is rewritten in a canonical
/// basis, the Fourier basis cos(k.theta), sin(k.theta) over the angles it holds (every
/// identity between such polynomials holds there term by term); from that basis a few
/// candidate forms are built (the basis itself, squares instead of double angles, the
/// plain input, squares reduced without folding, and for a sum its terms grouped by
/// their factors other than numbers, symbols, sines and cosines, each group simplified
/// as a whole and each such factor on its own) and the shortest printed one is kept.
/// The work is bounded: an expression over the limits below is simplified part by part,
/// or comes back in its plain form.
#include <ginac/ginac.h>

#include <cstddef>

namespace mbsc::print {

struct DisplayLimits {
  std::size_t max_nodes = 4000;       // nodes of the input (counted with repetition)
  double max_expanded_terms = 3000;   // terms of its expansion (model::expanded_terms)
  std::size_t max_wave_terms = 20000; // products of sines and cosines written out for one
                                      // expression (past it: part by part); the whole call
                                      // may do 8 times as many (past it: the plain form)
  int max_trig_degree = 12;           // sines and cosines multiplied in one term
  std::size_t max_printed_chars = 5000000;  // characters printed to compare candidates, the
                                            // whole call (past it: the plain form)
};

/// e in the shortest form found (or e tidied, when it is over the limits).
GiNaC::ex display_simplify(const GiNaC::ex& e, const DisplayLimits& limits = {});

/// The size measure the simplifier minimises: characters of the canonical text.
std::size_t display_size(const GiNaC::ex& e);

/// The size of e (sym::structural_size: the same in every run), counted up to limit + 1 at most.
std::size_t node_count(const GiNaC::ex& e, std::size_t limit);

}  // namespace mbsc::print
