// SPDX-License-Identifier: GPL-2.0-or-later
#include "canonical_dag.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "hash.hpp"

namespace mbsc::ir {

namespace {

struct FuncInfo {
  const char* name;
  const char* cpp;
  int arity;
};

// Fixed table, indexed by Func.
constexpr FuncInfo kFuncs[] = {
    {"sin", "std::sin", 1},     {"cos", "std::cos", 1},     {"tan", "std::tan", 1},   {"exp", "std::exp", 1},
    {"log", "std::log", 1},     {"sqrt", "std::sqrt", 1},   {"abs", "std::abs", 1},   {"atan2", "std::atan2", 2},
    {"asin", "std::asin", 1},   {"acos", "std::acos", 1},   {"atan", "std::atan", 1}, {"sinh", "std::sinh", 1},
    {"cosh", "std::cosh", 1},   {"tanh", "std::tanh", 1},   {"csgn", "", 1},
};

std::uint64_t double_bits(double v) {
  std::uint64_t b = 0;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

// Seed of a node's hash: its kind (and function for calls).
std::uint64_t kind_seed(NodeKind k, std::uint8_t func) {
  return mix64((static_cast<std::uint64_t>(k) + 1) * 0x51ed270b27c1f3a5ULL + func);
}

}  // namespace

const char* func_name(Func f) { return kFuncs[static_cast<int>(f)].name; }
const char* func_cpp(Func f) { return kFuncs[static_cast<int>(f)].cpp; }
int func_arity(Func f) { return kFuncs[static_cast<int>(f)].arity; }

Dag::Dag() : table_(1024, Slot{0, -1}) {}

// Grow the open-addressing table to twice its size and re-insert every node.
void Dag::grow_table() {
  std::vector<Slot> t(table_.size() * 2, Slot{0, -1});
  const std::size_t mask = t.size() - 1;
  for (const Slot& s : table_) {
    if (s.id < 0) continue;
    std::size_t i = s.hash & mask;
    while (t[i].id >= 0) i = (i + 1) & mask;
    t[i] = s;
  }
  table_.swap(t);
}

// Structural identity of a candidate with an existing node: children are already
// hash-consed, so equal children means equal ids.
bool Dag::same(const Node& n, const NodeId* kids, std::int32_t nkids, NodeId existing) const {
  const Node& e = node(existing);
  if (e.hash != n.hash || e.kind != n.kind || e.func != n.func || e.nchild != nkids) return false;
  if (double_bits(e.value) != double_bits(n.value) || e.ref != n.ref || e.elem != n.elem) return false;
  const NodeId* ek = children(existing);
  return std::equal(kids, kids + nkids, ek);
}

// Hash-consing: return the existing identical node, or append a new one.
NodeId Dag::intern(Node n, const NodeId* kids, std::int32_t nkids) {
  std::size_t mask = table_.size() - 1;
  std::size_t i = n.hash & mask;
  while (table_[i].id >= 0) {
    if (table_[i].hash == n.hash && same(n, kids, nkids, table_[i].id)) return table_[i].id;
    i = (i + 1) & mask;
  }
  if (nodes_.size() >= static_cast<std::size_t>(INT32_MAX) - 1) throw std::runtime_error("expression DAG too large");
  const NodeId id = static_cast<NodeId>(nodes_.size());
  n.nchild = nkids;
  n.child_begin = static_cast<std::int32_t>(children_.size());
  n.max_step = n.kind == NodeKind::Sym ? n.ref : -1;
  for (std::int32_t c = 0; c < nkids; ++c) n.max_step = std::max(n.max_step, node(kids[c]).max_step);
  if (nkids > 0) {
    n.invariant = true;
    for (std::int32_t c = 0; c < nkids; ++c) n.invariant = n.invariant && node(kids[c]).invariant;
  }
  children_.insert(children_.end(), kids, kids + nkids);
  nodes_.push_back(n);
  table_[i] = Slot{n.hash, id};
  if (nodes_.size() * 2 > table_.size()) grow_table();
  return id;
}

NodeId Dag::make_number(double v) {
  Node n;
  n.kind = NodeKind::Number;
  n.value = v;
  n.invariant = true;
  n.hash = hash_combine(kind_seed(n.kind, 0), double_bits(v));
  return intern(n, nullptr, 0);
}

// Input texts are interned once; the node's payload is the text id, its hash the text's.
NodeId Dag::make_input(const std::string& text, bool invariant) {
  auto it = text_ids_.find(text);
  std::int32_t id;
  if (it == text_ids_.end()) {
    id = static_cast<std::int32_t>(texts_.size());
    texts_.push_back(text);
    text_hash_.push_back(hash_text(text));
    text_ids_.emplace(text, id);
  } else {
    id = it->second;
  }
  Node n;
  n.kind = NodeKind::Input;
  n.ref = id;
  n.invariant = invariant;
  n.hash = hash_combine(kind_seed(n.kind, 0), text_hash_[static_cast<std::size_t>(id)]);
  return intern(n, nullptr, 0);
}

NodeId Dag::make_sym(int step, int elem) {
  Node n;
  n.kind = NodeKind::Sym;
  n.ref = step;
  n.elem = elem;
  n.hash = hash_combine(hash_combine(kind_seed(n.kind, 0), static_cast<std::uint64_t>(step)),
                        static_cast<std::uint64_t>(elem));
  return intern(n, nullptr, 0);
}

// n-ary Add/Mul: sort the operands canonically, then hash kind + children in that order.
NodeId Dag::make_add(std::vector<NodeId> ops) {
  // Zero terms (a product with a zero coefficient, say) drop out.
  ops.erase(std::remove_if(ops.begin(), ops.end(),
                           [this](NodeId c) { return node(c).kind == NodeKind::Number && node(c).value == 0.0; }),
            ops.end());
  if (ops.size() >= 2) simplify_sum_terms(ops);
  if (ops.empty()) return make_number(0.0);
  if (ops.size() == 1) return ops[0];
  return make_flat_add(std::move(ops));
}

NodeId Dag::make_flat_add(std::vector<NodeId> ops) {
  std::sort(ops.begin(), ops.end(), [this](NodeId a, NodeId b) { return less(a, b); });
  Node n;
  n.kind = NodeKind::Add;
  n.hash = kind_seed(n.kind, 0);
  for (NodeId c : ops) n.hash = hash_combine(n.hash, node(c).hash);
  return intern(n, ops.data(), static_cast<std::int32_t>(ops.size()));
}

NodeId Dag::make_mul(std::vector<NodeId> ops) {
  // Flatten (the only nested products are invariant sub-products made below), so that
  // every rule here is a function of the factors alone, not of how they were grouped.
  std::vector<NodeId> flat;
  for (std::size_t i = 0; i < ops.size(); ++i) {
    if (node(ops[i]).kind != NodeKind::Mul) {
      flat.push_back(ops[i]);
      continue;
    }
    for (std::int32_t k = 0; k < node(ops[i]).nchild; ++k) ops.push_back(child(ops[i], k));
  }
  // Fold numeric factors (multiplied in canonical order) into one coefficient.
  std::vector<NodeId> numbers;
  ops.clear();
  for (NodeId c : flat) (node(c).kind == NodeKind::Number ? numbers : ops).push_back(c);
  std::sort(numbers.begin(), numbers.end(), [this](NodeId a, NodeId b) { return less(a, b); });
  double coef = 1.0;
  for (NodeId c : numbers) coef *= node(c).value;
  if (coef == 0.0) return make_number(0.0);
  if (ops.empty()) return make_number(coef);
  // Two or more invariant factors become one sub-product node: with varying factors,
  // the coefficient's magnitude goes in too (7*m*l^2 is shared by every entry that
  // has it) and only its sign stays outside; alone, they keep the coefficient out.
  std::vector<NodeId> invariant, varying;
  for (NodeId c : ops) (node(c).invariant ? invariant : varying).push_back(c);
  if (invariant.size() >= 2 && !varying.empty()) {
    if (std::fabs(coef) != 1.0) invariant.push_back(make_number(std::fabs(coef)));
    varying.push_back(make_invariant_product(std::move(invariant)));
    coef = coef < 0 ? -1.0 : 1.0;
    ops = std::move(varying);
  } else if (invariant.size() >= 2 && coef != 1.0) {
    ops = {make_invariant_product(std::move(invariant))};
  }
  if (coef != 1.0) ops.push_back(make_number(coef));
  if (ops.size() == 1) return ops[0];
  return make_flat_mul(std::move(ops));
}

// c * (product of invariant factors) with the factors' product as its own node, so that
// 7*m*l^2 reads the node m*l^2 that 5*m*l^2 reads too.
NodeId Dag::make_invariant_product(std::vector<NodeId> factors) {
  std::vector<NodeId> numbers, rest;
  for (NodeId c : factors) (node(c).kind == NodeKind::Number ? numbers : rest).push_back(c);
  NodeId core = rest.size() == 1 ? rest[0] : make_flat_mul(std::move(rest));
  if (numbers.empty()) return core;
  return make_flat_mul({core, numbers[0]});
}

// A Mul node from operands that are already in final form (sorted here).
NodeId Dag::make_flat_mul(std::vector<NodeId> ops) {
  std::sort(ops.begin(), ops.end(), [this](NodeId a, NodeId b) { return less(a, b); });
  Node n;
  n.kind = NodeKind::Mul;
  n.hash = kind_seed(n.kind, 0);
  for (NodeId c : ops) n.hash = hash_combine(n.hash, node(c).hash);
  return intern(n, ops.data(), static_cast<std::int32_t>(ops.size()));
}

NodeId Dag::make_pow(NodeId base, NodeId exponent) {
  Node n;
  n.kind = NodeKind::Pow;
  n.hash = hash_combine(hash_combine(kind_seed(n.kind, 0), node(base).hash), node(exponent).hash);
  const NodeId kids[2] = {base, exponent};
  return intern(n, kids, 2);
}

NodeId Dag::make_call(Func f, const std::vector<NodeId>& args) {
  Node n;
  n.kind = NodeKind::Call;
  n.func = static_cast<std::uint8_t>(f);
  n.hash = kind_seed(n.kind, n.func);
  for (NodeId c : args) n.hash = hash_combine(n.hash, node(c).hash);
  return intern(n, args.data(), static_cast<std::int32_t>(args.size()));
}

// Negation by structure. A function of the node's structure alone, so the memo is only a
// cache: it records no reverse entry, which would make negate's value depend on the order
// of the calls (negate(-1*s) is s for a sum s, while negate(s) is the sum of the negated
// terms: a reverse entry made after the first call gave -1*s for s).
NodeId Dag::negate(NodeId id) {
  auto it = negated_.find(id);
  if (it != negated_.end()) return it->second;
  const Node n = node(id);
  NodeId result;
  if (n.kind == NodeKind::Number) {
    result = make_number(-n.value);
  } else if (n.kind == NodeKind::Add) {
    // A term that is itself a sum (a substituted Define's value, which CSE shares) is
    // negated as -1 * it, the form a rewrite gives it, so that negating twice returns
    // this very node: as an Add its negation would be a second sum of the same terms.
    // The negated terms are not rewritten again: make_add is sign-equivariant, so they
    // are what make_add gives the negated input, also where its round bound cut it short
    // (rewriting them again would go on from there, and a sum and its negation would no
    // longer be each other's negation).
    std::vector<NodeId> terms(children(id), children(id) + n.nchild);
    for (NodeId& t : terms) t = node(t).kind == NodeKind::Add ? make_mul({t, make_number(-1.0)}) : negate(t);
    result = make_flat_add(std::move(terms));
  } else if (n.kind == NodeKind::Mul) {
    std::vector<NodeId> factors;
    bool had_coefficient = false;
    for (std::int32_t i = 0; i < n.nchild; ++i) {
      const NodeId c = child(id, i);
      if (node(c).kind == NodeKind::Number && !had_coefficient) {
        had_coefficient = true;
        if (node(c).value != -1.0) factors.push_back(make_number(-node(c).value));
      } else {
        factors.push_back(c);
      }
    }
    if (!had_coefficient) factors.push_back(make_number(-1.0));
    result = make_mul(std::move(factors));
  } else {
    result = make_mul({make_number(-1.0), id});
  }
  negated_[id] = result;
  return result;
}

NodeId Dag::negated_sum(NodeId id) const {
  const Node& n = node(id);
  if (n.kind != NodeKind::Mul || n.nchild != 2) return -1;
  const NodeId a = child(id, 0), b = child(id, 1);
  const NodeId number = node(a).kind == NodeKind::Number ? a : b, other = number == a ? b : a;
  if (node(number).kind != NodeKind::Number || node(number).value != -1.0 || node(other).kind != NodeKind::Add) return -1;
  return other;
}

NodeId Dag::canonical_sign(NodeId sum, bool& flipped) {
  // -1*s for a sum s is -s written as a product: the form a GiNaC sum takes when the
  // rewrites leave one term, a Define's sum, with coefficient -1 (and s itself when it is
  // handed over negated). Its sign is decided on s, among s and negate(s), so that both
  // forms of -s and s itself come out as one node.
  if (const NodeId s = negated_sum(sum); s >= 0) {
    const NodeId chosen = canonical_sign(s, flipped);
    flipped = !flipped;
    return chosen;
  }
  const NodeId neg = negate(sum);
  flipped = less(neg, sum);
  return flipped ? neg : sum;
}

// Canonical order: structural hash, then kind, payload, arity and children (recursively).
// The deep part only runs on a 64-bit hash collision between distinct nodes.
int Dag::compare(NodeId a, NodeId b) const {
  if (a == b) return 0;
  const Node& x = node(a);
  const Node& y = node(b);
  if (x.hash != y.hash) return x.hash < y.hash ? -1 : 1;
  if (x.kind != y.kind) return x.kind < y.kind ? -1 : 1;
  if (x.func != y.func) return x.func < y.func ? -1 : 1;
  switch (x.kind) {
    case NodeKind::Number: {
      const std::uint64_t bx = double_bits(x.value), by = double_bits(y.value);
      if (bx != by) return bx < by ? -1 : 1;
      break;
    }
    case NodeKind::Input: {
      const int c = input_text(x.ref).compare(input_text(y.ref));
      if (c != 0) return c < 0 ? -1 : 1;
      break;
    }
    case NodeKind::Sym:
      if (x.ref != y.ref) return x.ref < y.ref ? -1 : 1;
      if (x.elem != y.elem) return x.elem < y.elem ? -1 : 1;
      break;
    default:
      break;
  }
  if (x.nchild != y.nchild) return x.nchild < y.nchild ? -1 : 1;
  for (std::int32_t i = 0; i < x.nchild; ++i) {
    const int c = compare(child(a, i), child(b, i));
    if (c != 0) return c;
  }
  return 0;
}

}  // namespace mbsc::ir
