// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Canonical, hash-consed expression DAG (private to src/ir).
///
/// Nodes are identified by an index (NodeId). Indices follow creation order, which follows
/// GiNaC's run-dependent operand order, so an index must never decide anything that reaches
/// the output: only the structural hash and structural comparison do. Every node is created
/// after its children, so increasing index order is a topological order (children first).
#include <cstddef>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

namespace mbsc::ir {

using NodeId = std::int32_t;

enum class NodeKind : std::uint8_t {
  Number,  // a double constant
  Input,   // a binding's C++ text ("x[3]")
  Sym,     // the result X(i, j) of a numeric Solve step
  Add,     // n-ary sum, operands in canonical order
  Mul,     // n-ary product, operands in canonical order
  Pow,     // base ^ exponent
  Call,    // function call, arguments in given order
};

/// The functions a Call node may name (fixed table: its order is part of the canonical order).
/// Sign: GiNaC's csgn of a real argument, -1, 0 or 1 (a Coulomb friction's direction).
enum class Func : std::uint8_t { Sin, Cos, Tan, Exp, Log, Sqrt, Abs, Atan2, Asin, Acos, Atan, Sinh, Cosh, Tanh, Sign };

/// GiNaC name of a function ("sin") and its C++ spelling ("std::sin").
const char* func_name(Func f);
const char* func_cpp(Func f);
int func_arity(Func f);

struct Node {
  std::uint64_t hash = 0;    // structural hash (kind, payload, children's hashes)
  NodeKind kind = NodeKind::Number;
  std::uint8_t func = 0;     // Call: Func
  std::int32_t nchild = 0;
  std::int32_t child_begin = 0;  // index into Dag::children()
  double value = 0.0;        // Number
  std::int32_t ref = 0;      // Input: text id; Sym: step index
  std::int32_t elem = 0;     // Sym: flat index i*k+j of X
  std::int32_t max_step = -1;  // largest Solve step index this node reads (-1: none)
  bool invariant = false;    // built from numbers and invariant inputs only (parameters)
};

/// The sum of `values` such that the negated values give exactly the negated sum (the
/// positive and the negative values summed apart): the coefficient of collected like
/// terms, which must not depend on the sign the sum was handed with.
double sign_symmetric_sum(std::vector<double> values);

/// Hash-consing node store. make_* return the existing node when an identical one exists.
class Dag {
 public:
  Dag();

  NodeId make_number(double v);
  /// `invariant`: the input has the same value in every call (a parameter). The flag
  /// belongs to the text: every make_input of one text must pass the same value.
  NodeId make_input(const std::string& text, bool invariant = false);
  NodeId make_sym(int step, int elem);
  /// Operands are sorted canonically; a single operand is returned as is.
  NodeId make_add(std::vector<NodeId> ops);
  /// As make_add; numeric factors are folded into one coefficient (dropped when it is 1).
  /// Two or more invariant factors next to varying ones become one invariant sub-product,
  /// so that CSE shares it between products (m*l^2 in every mass matrix entry).
  NodeId make_mul(std::vector<NodeId> ops);
  NodeId make_pow(NodeId base, NodeId exponent);
  NodeId make_call(Func f, const std::vector<NodeId>& args);

  /// -e as a node: numbers and coefficients change sign (a coefficient -1 disappears),
  /// sums negate every term (a term that is a sum gets a coefficient -1, and loses it),
  /// anything else gets a coefficient -1. A function of structure (never of the order of
  /// the calls), and an involution on every node except -1*s for a sum s, whose negation
  /// is s while s's is the sum of the negated terms: canonical_sign handles that form.
  NodeId negate(NodeId id);
  /// Of a sum and its negation, the one that sorts first; `flipped` tells which it was.
  /// Makes a sum's sign independent of GiNaC's run-dependent choice (see from_ginac.cpp).
  /// The same node for s, negate(s) and -1*s (and -1*negate(s)).
  NodeId canonical_sign(NodeId sum, bool& flipped);
  /// s when `id` is -1*s with s a sum, else -1.
  NodeId negated_sum(NodeId id) const;

  /// Tests only: stop the rewrites of every sum after `rounds` rounds (0: the default
  /// bound), to check that what a cut leaves still does not depend on the sign GiNaC gave.
  void limit_sum_rounds(std::size_t rounds) { sum_round_limit_ = rounds; }

  const Node& node(NodeId id) const { return nodes_[static_cast<std::size_t>(id)]; }
  const NodeId* children(NodeId id) const { return children_.data() + node(id).child_begin; }
  NodeId child(NodeId id, int i) const { return children_[static_cast<std::size_t>(node(id).child_begin + i)]; }
  std::size_t size() const { return nodes_.size(); }
  const std::string& input_text(int text_id) const { return texts_[static_cast<std::size_t>(text_id)]; }

  /// Total order on nodes that depends only on structure: hash first, then a full
  /// structural comparison on ties. Returns <0, 0, >0.
  int compare(NodeId a, NodeId b) const;
  /// True when `a` sorts before `b` in the canonical order.
  bool less(NodeId a, NodeId b) const { return a != b && compare(a, b) < 0; }

 private:
  NodeId intern(Node n, const NodeId* kids, std::int32_t nkids);
  bool same(const Node& n, const NodeId* kids, std::int32_t nkids, NodeId existing) const;
  void grow_table();
  NodeId make_invariant_product(std::vector<NodeId> factors);
  NodeId make_flat_mul(std::vector<NodeId> ops);
  /// An Add node from terms already in final form (no rewrites; sorted here).
  NodeId make_flat_add(std::vector<NodeId> ops);

  // Rewrites of a sum's terms before the sum is made (sum_rewrites.cpp).
  /// Applies the rewrites below until none fires; leaves `terms` sorted canonically.
  /// Sign-equivariant: the terms negated give exactly the negated terms, whatever the
  /// round bound cuts short (the sign GiNaC gives a sum varies from run to run).
  void simplify_sum_terms(std::vector<NodeId>& terms);
  /// Sorts a sum's terms by their rest (the term without its coefficient), then the
  /// coefficient's magnitude: an order the sum's negation shares, which the rewrites'
  /// choices follow (the canonical order would not: -t and t sort apart).
  void order_terms_sign_blind(std::vector<NodeId>& terms);
  /// c1*F + c2*F -> (c1 + c2)*F (numbers are terms with F = 1); true when one fired.
  bool collect_like_terms(std::vector<NodeId>& terms);
  /// F*sin(u)^2 + F*cos(u)^2 -> F; true when one fired.
  bool fold_pythagorean_pairs(std::vector<NodeId>& terms);
  /// c*(a1 + ... + am)*G -> c*a1*G + ... + c*am*G when all but at most one of those
  /// terms are like terms of others in the sum (so they merge or cancel): the first term
  /// (in the order of `terms`), over its first sum factor (canonical order) for which
  /// that holds; true when fired.
  bool distribute_into_like_terms(std::vector<NodeId>& terms);
  /// The product of `factors` (no numbers among them) times `coef`, with equal bases
  /// merged into one power (x * x^2 -> x^3).
  NodeId make_product_merging_powers(const std::vector<NodeId>& factors, double coef);
  /// A term's numeric coefficient and the rest of it (-1 for a plain number).
  NodeId split_coefficient(NodeId term, double& coef);
  /// Appends the non-numeric factors of a product (nested products flattened) to
  /// `factors` and multiplies its numbers into `coef`.
  void flatten_factors(NodeId term, std::vector<NodeId>& factors, double& coef) const;

  std::vector<Node> nodes_;
  std::vector<NodeId> children_;
  std::vector<std::string> texts_;        // Input texts by id
  std::vector<std::uint64_t> text_hash_;  // FNV-1a of each text
  std::unordered_map<std::string, std::int32_t> text_ids_;  // lookup only, never iterated
  std::unordered_map<NodeId, NodeId> negated_;               // lookup only, never iterated
  struct Slot {
    std::uint64_t hash;
    NodeId id;  // -1 = empty
  };
  std::vector<Slot> table_;  // open addressing on the structural hash
  std::size_t sum_round_limit_ = 0;  // limit_sum_rounds
};

}  // namespace mbsc::ir
