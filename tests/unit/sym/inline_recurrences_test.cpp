// SPDX-License-Identifier: GPL-2.0-or-later
// inline_small_recurrences (sym/inline_recurrences.hpp): a triangular node's h written on
// named e_/r_ values is replaced by its substituted, expanded form only when that needs
// fewer operations. The two-link chain's recurrences (as derive names them) must fire and
// lose the cancelling centripetal terms; the value must stay the same at random points;
// a node without cancellations, or with too many named values, keeps its names; and the
// result is the same expression on every run.
#include <catch2/catch.hpp>

#include <random>
#include <string>
#include <vector>

#include "mbsc/sym/inline_recurrences.hpp"

namespace {

using mbsc::ir::Define;

struct Chain2 {
  GiNaC::symbol q0{"q0"}, q1{"q1"}, u0{"u0"}, u1{"u1"}, l{"l"}, m{"m"}, g{"g"};
  GiNaC::symbol e1v{"e_b1_v"}, e1u{"e_b1_u"}, e2v{"e_b2_v"}, e2u{"e_b2_u"};
  GiNaC::symbol r1u{"r_b1_u"}, r2v{"r_b2_v"}, r1v{"r_b1_v"};
  std::vector<Define> named;
  GiNaC::matrix h{2, 1};

  // The bobs' accelerations at zero independent accelerations (e, forward) and the
  // adjoint sums of h = C^T (hy - My e) (r, backward), as derive.cpp names them for
  // two point masses m on massless links l under gravity g.
  Chain2() {
    const GiNaC::ex s0 = GiNaC::sin(q0), c0 = GiNaC::cos(q0), s1 = GiNaC::sin(q1), c1 = GiNaC::cos(q1);
    named = {Define{e1v, u0 * u0 * l * c0, true}, Define{e1u, -s0 * u0 * u0 * l, true},
             Define{e2v, e1v + c1 * l * u1 * u1, true}, Define{e2u, e1u - s1 * l * u1 * u1, true},
             Define{r1u, -(e2u + e1u) * m, true}, Define{r2v, -(g + e2v) * m, true},
             Define{r1v, r2v - m * g - e1v * m, true}};
    h(0, 0) = (r1v * s0 + r1u * c0) * l;
    h(1, 0) = -(e2u * m * c1 - r2v * s1) * l;
  }

  // Every name replaced by its value, for evaluation.
  GiNaC::exmap values() const {
    GiNaC::exmap v;
    for (const Define& d : named) v[d.sym] = d.value.subs(v);
    return v;
  }
};

double at(const GiNaC::ex& e, const GiNaC::exmap& point) {
  return GiNaC::ex_to<GiNaC::numeric>(GiNaC::evalf(e.subs(point))).to_double();
}

}  // namespace

TEST_CASE("inline_small_recurrences: the two-link chain's centripetal terms cancel", "[sym][inline]") {
  Chain2 c;
  const GiNaC::matrix before = c.h;
  const GiNaC::exmap names = c.values();
  std::vector<GiNaC::ex> named_form;
  for (const Define& d : c.named) named_form.push_back(d.value);
  named_form.push_back(before(0, 0));
  named_form.push_back(before(1, 0));

  REQUIRE(mbsc::sym::inline_small_recurrences(c.named, 4, c.h));
  // No name is left, and fewer operations than the named form, even counting the e_ values
  // (which a minimal-state rhs need not compute any more).
  for (unsigned i = 0; i < 2; ++i)
    for (const Define& d : c.named) CHECK_FALSE(c.h(i, 0).has(d.sym));
  CHECK(mbsc::sym::shared_operations({c.h(0, 0), c.h(1, 0)}) < mbsc::sym::shared_operations(named_form));
  // The u0^2 sin q0 cos q0 terms are gone from the first row (they cancel between the bobs).
  const GiNaC::ex expanded = c.h(0, 0).expand();
  CHECK_FALSE(expanded.has(GiNaC::pow(c.u0, 2)));

  // The same value at random points.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> d(-2.0, 2.0);
  for (int k = 0; k < 20; ++k) {
    GiNaC::exmap point;
    for (const GiNaC::symbol& s : {c.q0, c.q1, c.u0, c.u1, c.l, c.m, c.g}) point[s] = d(rng);
    for (unsigned i = 0; i < 2; ++i) {
      const double want = at(before(i, 0).subs(names), point);
      CHECK(at(c.h(i, 0), point) == Approx(want).margin(1e-13).epsilon(1e-13));
    }
  }

  // Deterministic: the same expressions from a fresh derivation.
  Chain2 again;
  REQUIRE(mbsc::sym::inline_small_recurrences(again.named, 4, again.h));
  for (unsigned i = 0; i < 2; ++i) CHECK(again.h(i, 0).is_equal(c.h(i, 0).subs(GiNaC::exmap{
                                           {c.q0, again.q0}, {c.q1, again.q1}, {c.u0, again.u0}, {c.u1, again.u1},
                                           {c.l, again.l}, {c.m, again.m}, {c.g, again.g}})));
}

TEST_CASE("inline_small_recurrences keeps the names when nothing cancels or the node is long", "[sym][inline]") {
  // A shared product read by both rows, nothing to cancel: expanding only repeats it.
  const GiNaC::symbol a("a"), b("b"), c("c"), d("d"), r("r_x");
  std::vector<Define> named = {Define{r, (a + b) * (c + d) * (a - d), true}};
  GiNaC::matrix h(2, 1);
  h(0, 0) = r * a;
  h(1, 0) = r * b + c;
  const GiNaC::matrix before = h;
  CHECK_FALSE(mbsc::sym::inline_small_recurrences(named, 0, h));
  CHECK(h(0, 0).is_equal(before(0, 0)));
  CHECK(h(1, 0).is_equal(before(1, 0)));

  // More named values than kMaxInlinedRecurrences: left alone, whatever would cancel.
  std::vector<Define> many;
  GiNaC::ex prev = 0;
  for (std::size_t k = 0; k <= mbsc::sym::kMaxInlinedRecurrences; ++k) {
    const GiNaC::symbol e("e_" + std::to_string(k));
    many.push_back(Define{e, prev + a, true});
    prev = e;
  }
  GiNaC::matrix h2(1, 1);
  h2(0, 0) = prev - GiNaC::ex(static_cast<int>(many.size())) * a;  // would cancel to 0
  CHECK_FALSE(mbsc::sym::inline_small_recurrences(many, 0, h2));
  CHECK(h2(0, 0).has(GiNaC::ex_to<GiNaC::symbol>(prev)));
}
