// SPDX-License-Identifier: GPL-2.0-or-later
// The rewrites make_add applies to a sum's terms (src/ir/sum_rewrites.cpp): like terms
// collected, F sin^2(u) + F cos^2(u) folded to F. Each case checks that the rewrite fires
// (the sum's shape) and that the value is kept at random points.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "../../../src/ir/canonical_dag.hpp"

using mbsc::ir::Dag;
using mbsc::ir::Func;
using mbsc::ir::NodeId;
using mbsc::ir::NodeKind;

namespace {

// Value of a node with the inputs taken from `in` (by their text).
double eval(const Dag& d, NodeId id, const std::map<std::string, double>& in) {
  const auto& n = d.node(id);
  switch (n.kind) {
    case NodeKind::Number:
      return n.value;
    case NodeKind::Input:
      return in.at(d.input_text(n.ref));
    case NodeKind::Add: {
      double s = 0.0;
      for (int i = 0; i < n.nchild; ++i) s += eval(d, d.child(id, i), in);
      return s;
    }
    case NodeKind::Mul: {
      double p = 1.0;
      for (int i = 0; i < n.nchild; ++i) p *= eval(d, d.child(id, i), in);
      return p;
    }
    case NodeKind::Pow:
      return std::pow(eval(d, d.child(id, 0), in), eval(d, d.child(id, 1), in));
    case NodeKind::Call: {
      const double a = eval(d, d.child(id, 0), in);
      if (n.func == static_cast<std::uint8_t>(Func::Sin)) return std::sin(a);
      if (n.func == static_cast<std::uint8_t>(Func::Cos)) return std::cos(a);
      break;
    }
    default:
      break;
  }
  FAIL("unexpected node in the test evaluator");
  return 0.0;
}

// Random values for the inputs the tests use.
std::vector<std::map<std::string, double>> random_points(int count) {
  std::mt19937 rng(20261202);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  std::vector<std::map<std::string, double>> pts;
  for (int i = 0; i < count; ++i) {
    std::map<std::string, double> m;
    for (const char* name : {"x[0]", "x[1]", "x[2]", "p[0]", "p[1]"}) m[name] = u(rng);
    pts.push_back(m);
  }
  return pts;
}

struct Fixture {
  Dag d;
  NodeId x0 = d.make_input("x[0]");
  NodeId x1 = d.make_input("x[1]");
  NodeId x2 = d.make_input("x[2]");
  NodeId p0 = d.make_input("p[0]", true);
  NodeId p1 = d.make_input("p[1]", true);
  NodeId two = d.make_number(2.0);
  NodeId sq(Func f, NodeId arg) { return d.make_pow(d.make_call(f, {arg}), two); }
};

}  // namespace

TEST_CASE("sum rewrites: F sin^2 + F cos^2 folds to F, value kept", "[ir][sum_rewrites]") {
  Fixture f;
  Dag& d = f.d;
  // 0.25 p0^2 p1 x2 sin^2(x0) + 0.25 p0^2 p1 x2 cos^2(x0) + x1: the four-bar's pair, with
  // the invariant sub-product and the coefficient inside it.
  const NodeId p0sq = d.make_pow(f.p0, f.two);
  const NodeId a = d.make_mul({d.make_number(0.25), p0sq, f.p1, f.x2, f.sq(Func::Sin, f.x0)});
  const NodeId b = d.make_mul({f.sq(Func::Cos, f.x0), f.p1, d.make_number(0.25), f.x2, p0sq});
  const NodeId sum = d.make_add({a, f.x1, b});
  const NodeId expect = d.make_add({d.make_mul({d.make_number(0.25), p0sq, f.p1, f.x2}), f.x1});
  CHECK(sum == expect);
  CHECK(d.node(sum).nchild == 2);
  for (const auto& pt : random_points(20)) {
    const double direct = 0.25 * pt.at("p[0]") * pt.at("p[0]") * pt.at("p[1]") * pt.at("x[2]") + pt.at("x[1]");
    CHECK(eval(d, sum, pt) == Approx(direct).epsilon(1e-14).margin(1e-14));
  }
  // Bare squares and negated pairs.
  CHECK(d.make_add({f.sq(Func::Sin, f.x0), f.sq(Func::Cos, f.x0)}) == d.make_number(1.0));
  CHECK(d.make_add({d.negate(a), d.negate(b)}) == d.negate(d.make_mul({d.make_number(0.25), p0sq, f.p1, f.x2})));
}

TEST_CASE("sum rewrites: nested pairs fold to a fixed point", "[ir][sum_rewrites]") {
  Fixture f;
  Dag& d = f.d;
  const NodeId s0 = f.sq(Func::Sin, f.x0), c0 = f.sq(Func::Cos, f.x0);
  const NodeId s1 = f.sq(Func::Sin, f.x1), c1 = f.sq(Func::Cos, f.x1);
  // p0 (s0 s1 + s0 c1 + c0 s1 + c0 c1) - p0 = 0
  const NodeId sum = d.make_add({d.make_mul({f.p0, s0, s1}), d.make_mul({f.p0, s0, c1}), d.make_mul({f.p0, c0, s1}),
                                 d.make_mul({f.p0, c0, c1}), d.negate(f.p0)});
  CHECK(sum == d.make_number(0.0));
}

TEST_CASE("sum rewrites: no fold without a matching partner", "[ir][sum_rewrites]") {
  Fixture f;
  Dag& d = f.d;
  // Different rest, different argument, same function twice: all stay.
  const NodeId a = d.make_add({d.make_mul({f.p0, f.sq(Func::Sin, f.x0)}), d.make_mul({f.p1, f.sq(Func::Cos, f.x0)})});
  CHECK(d.node(a).kind == NodeKind::Add);
  CHECK(d.node(a).nchild == 2);
  const NodeId b = d.make_add({f.sq(Func::Sin, f.x0), f.sq(Func::Cos, f.x1)});
  CHECK(d.node(b).nchild == 2);
  const NodeId c = d.make_add({f.sq(Func::Sin, f.x0), d.make_mul({f.x1, f.sq(Func::Sin, f.x0)})});
  CHECK(d.node(c).nchild == 2);
  // sin^3 and cos^2 are not a pair.
  const NodeId cube = d.make_pow(d.make_call(Func::Sin, {f.x0}), d.make_number(3.0));
  CHECK(d.node(d.make_add({cube, f.sq(Func::Cos, f.x0)})).nchild == 2);
}

TEST_CASE("sum rewrites: like terms are collected, value kept", "[ir][sum_rewrites]") {
  Fixture f;
  Dag& d = f.d;
  const NodeId core = d.make_mul({f.p0, f.p1, f.x0});
  // 0.25 p0 p1 x0 + p0 p1 x0 / 12 -> p0 p1 x0 / 3 (the coefficients sit in the invariant
  // sub-product, with the sign outside)
  const NodeId sum = d.make_add({d.make_mul({d.make_number(0.25), core}), d.make_mul({d.make_number(1.0 / 12.0), core}), f.x1});
  CHECK(d.node(sum).nchild == 2);
  for (const auto& pt : random_points(20)) {
    const double direct = pt.at("p[0]") * pt.at("p[1]") * pt.at("x[0]") / 3.0 + pt.at("x[1]");
    CHECK(eval(d, sum, pt) == Approx(direct).epsilon(1e-14).margin(1e-14));
  }
  // Numbers add up; a term and its negation cancel; -F + 3F = 2F.
  CHECK(d.make_add({d.make_number(2.0), f.x0, d.make_number(3.0)}) == d.make_add({f.x0, d.make_number(5.0)}));
  CHECK(d.make_add({f.x0, d.negate(f.x0)}) == d.make_number(0.0));
  CHECK(d.make_add({d.negate(core), d.make_mul({d.make_number(3.0), core})}) == d.make_mul({d.make_number(2.0), core}));
}

TEST_CASE("sum rewrites: the result does not depend on construction order", "[ir][sum_rewrites]") {
  // Two pairs that could each take the same partner: the canonical order decides.
  Fixture f1, f2;
  const auto build = [](Fixture& f, bool reversed) {
    Dag& d = f.d;
    std::vector<NodeId> terms = {d.make_mul({f.x1, f.sq(Func::Sin, f.x0)}), d.make_mul({f.x1, f.sq(Func::Cos, f.x0)}),
                                 d.make_mul({f.x1, f.sq(Func::Cos, f.x0), d.make_number(2.0)}), f.x2};
    if (reversed) std::reverse(terms.begin(), terms.end());
    return d.make_add(terms);
  };
  const NodeId a = build(f1, false);
  const NodeId b = build(f2, true);
  CHECK(f1.d.node(a).hash == f2.d.node(b).hash);
}

TEST_CASE("sum rewrites: a sum factor is distributed when its terms cancel others", "[ir][sum_rewrites]") {
  Fixture f;
  Dag& d = f.d;
  const NodeId s = d.make_call(Func::Sin, {f.x0}), c = d.make_call(Func::Cos, {f.x0});
  const NodeId x2sq = d.make_pow(f.x2, f.two);
  // p0 c (p0 p1 s x2^2 - 2 x1)/4 - p0^2 p1 s c x2^2/4 = -p0 c x1/2 (the four-bar's forcing):
  // distributed, the first product is p0*p0*... and must meet p0^2 to cancel.
  const NodeId inner = d.make_add({d.make_mul({f.p0, f.p1, s, x2sq}), d.make_mul({d.make_number(-2.0), f.x1})});
  const NodeId t1 = d.make_mul({d.make_number(0.25), f.p0, c, inner});
  const NodeId t2 = d.make_mul({d.make_number(-0.25), d.make_pow(f.p0, f.two), f.p1, s, c, x2sq});
  const NodeId sum = d.make_add({t1, t2});
  CHECK(sum == d.make_mul({d.make_number(-0.5), f.p0, c, f.x1}));
  for (const auto& pt : random_points(20)) {
    const double direct = -0.5 * pt.at("p[0]") * std::cos(pt.at("x[0]")) * pt.at("x[1]");
    CHECK(eval(d, sum, pt) == Approx(direct).epsilon(1e-13).margin(1e-13));
  }
  // Only one of three distributed terms would merge: the product stays factored.
  const NodeId inner3 = d.make_add({d.make_mul({f.p0, f.p1, s, x2sq}), f.x1, f.x2});
  const NodeId kept = d.make_add({d.make_mul({d.make_number(0.25), f.p0, c, inner3}), t2});
  CHECK(d.node(kept).nchild == 2);
}

TEST_CASE("sum rewrites: distributed over whichever sum factor cancels", "[ir][sum_rewrites]") {
  // a*(c - 1) - a*c = -a with a a sum too (the flyball governor's rates, as one run of
  // GiNaC hands them over): it must fold whether a or c - 1 sorts first. Several a, so
  // that both orders occur.
  for (int k = 1; k <= 8; ++k) {
    Fixture f;
    Dag& d = f.d;
    const NodeId c = d.make_call(Func::Cos, {f.x0});
    const NodeId cm1 = d.make_add({c, d.make_number(-1.0)});
    const NodeId a = d.make_add({f.x1, d.make_mul({d.make_number(-k), f.x2})});
    const NodeId sum = d.make_add({d.make_mul({a, cm1}), d.make_mul({d.make_number(-1.0), a, c})});
    INFO("a = x1 - " << k << "*x2, a sorts " << (d.less(a, cm1) ? "before" : "after") << " c - 1");
    CHECK(sum == d.make_mul({d.make_number(-1.0), a}));
  }
}

namespace {

// The position of a planar chain's last centre of mass over links 1..m, as the
// derivation hands it over: -(l_k - c_k) cos(q_k) - c_k cos(q_k) for every link before
// the last, -c cos(q) for the last; each -(l_k - c_k) cos(q_k) distributes and cancels
// -c_k cos(q_k) (two rounds each), leaving -l_k cos(q_k). `sign` -1 hands the sum over
// negated, as GiNaC does in some runs; the inner sums l_k - c_k carry the sign the
// converter gives them (Dag::canonical_sign).
NodeId chain_sum(Dag& d, int m, double sign) {
  std::vector<NodeId> terms;
  const auto cos_q = [&](int k) { return d.make_call(Func::Cos, {d.make_input("x[" + std::to_string(k) + "]")}); };
  const auto param = [&](const std::string& name) { return d.make_input(name, true); };
  for (int k = 0; k < m; ++k) {
    const NodeId l = param("p[" + std::to_string(2 * k) + "]"), c = param("p[" + std::to_string(2 * k + 1) + "]");
    bool flipped = false;
    const NodeId inner = d.canonical_sign(d.make_add({l, d.negate(c)}), flipped);
    terms.push_back(d.make_mul({inner, cos_q(k), d.make_number(flipped ? sign : -sign)}));
    terms.push_back(d.make_mul({c, cos_q(k), d.make_number(-sign)}));
  }
  terms.push_back(d.make_mul({param("p[" + std::to_string(2 * m) + "]"), cos_q(m), d.make_number(-sign)}));
  return d.make_add(terms);
}

}  // namespace

TEST_CASE("sum rewrites: a sum handed over negated gives the negated result, also cut short", "[ir][sum_rewrites]") {
  // Ten distributions: more than the sixteen rounds the rewrites were once bounded by.
  // Cut short, a sum was left half rewritten, and the half depended on the sign GiNaC
  // gave it (the order of the rewrites followed the terms' canonical order, which -t
  // and t do not share); canonical_sign then compared two different halves, and a
  // planar chain of ten links generated different code from run to run.
  constexpr int m = 10;
  {
    Dag d;
    const NodeId sum = chain_sum(d, m, 1.0);
    std::vector<NodeId> expect;
    for (int k = 0; k < m; ++k)
      expect.push_back(d.make_mul({d.make_input("p[" + std::to_string(2 * k) + "]", true),
                                   d.make_call(Func::Cos, {d.make_input("x[" + std::to_string(k) + "]")}),
                                   d.make_number(-1.0)}));
    expect.push_back(d.make_mul({d.make_input("p[" + std::to_string(2 * m) + "]", true),
                                 d.make_call(Func::Cos, {d.make_input("x[" + std::to_string(m) + "]")}),
                                 d.make_number(-1.0)}));
    CHECK(sum == d.make_add(expect));  // rewritten to the end
  }
  // Every cut (and none): the sum and its negation, each in a DAG of its own, are each
  // other's negation, and canonical_sign makes one node of them.
  for (std::size_t rounds : {0, 1, 2, 3, 4, 7, 10, 16, 19}) {
    INFO("rounds " << rounds);
    Dag d1, d2;
    d1.limit_sum_rounds(rounds);
    d2.limit_sum_rounds(rounds);
    const NodeId plus = chain_sum(d1, m, 1.0), minus = chain_sum(d2, m, -1.0);
    CHECK(d1.node(d1.negate(plus)).hash == d2.node(minus).hash);
    CHECK(d2.node(d2.negate(minus)).hash == d1.node(plus).hash);
    bool f1 = false, f2 = false;
    CHECK(d1.node(d1.canonical_sign(plus, f1)).hash == d2.node(d2.canonical_sign(minus, f2)).hash);
    CHECK(f1 != f2);
  }
}

TEST_CASE("sum rewrites: like terms' coefficients sum alike in any order, and negated when negated", "[ir][sum_rewrites]") {
  // The rewrites meet a group of like terms in an order that puts t before -t in a sum
  // and in its negation alike, so a plain sum in that order would not be negated exactly:
  // (a + x) - x in one, (-a + x) - x in the other.
  const std::vector<std::vector<double>> cases = {{0.1, 0.7, -0.7},
                                                  {1e16, 1.0, -1e16, 1.0},
                                                  {0.7, -0.1, 0.25, -1.0 / 3.0, 1e-9},
                                                  {2.0, -2.0},
                                                  {-5.0},
                                                  {0.3, -0.1, -0.2, 0.1, 1.0 / 7.0}};
  for (const auto& values : cases) {
    std::vector<double> negated = values, permuted = values;
    for (double& v : negated) v = -v;
    const double s = mbsc::ir::sign_symmetric_sum(values);
    CHECK(mbsc::ir::sign_symmetric_sum(negated) == -s);
    std::sort(permuted.begin(), permuted.end());
    do {
      CHECK(mbsc::ir::sign_symmetric_sum(permuted) == s);
    } while (std::next_permutation(permuted.begin(), permuted.end()));
  }
  CHECK(mbsc::ir::sign_symmetric_sum({2.0, -2.0}) == 0.0);
}
