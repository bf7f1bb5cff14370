// SPDX-License-Identifier: GPL-2.0-or-later
#include "from_ginac.hpp"

#include <cmath>
#include <cstdint>
#include <sstream>
#include <stdexcept>

#include "hash.hpp"

namespace mbsc::ir {

namespace {

const GiNaC::basic* address(const GiNaC::ex& e) { return &GiNaC::ex_to<GiNaC::basic>(e); }

std::string printed(std::string s) {
  if (s.size() > 80) s = s.substr(0, 77) + "...";
  return s;
}

std::string printed(const GiNaC::ex& e) {
  std::ostringstream os;
  os << e;
  return printed(os.str());
}

// The model's values are real and bounded (model/value_bound.hpp), so these are the
// products the derivation formed from them; the driver reports them as the model's errors.
double to_double_checked(const GiNaC::numeric& n, const GiNaC::ex& where) {
  if (!n.is_real()) throw std::runtime_error("it computes with the complex number " + printed(where) + ", not a real one");
  double v = HUGE_VAL;
  try {
    v = n.to_double();
  } catch (const std::exception&) {  // CLN: beyond its double conversion
  }
  if (!std::isfinite(v)) {
    std::ostringstream approx;
    approx << GiNaC::ex(n).evalf();
    throw std::runtime_error("it computes with the constant " + printed(approx.str()) +
                             ", which does not fit a double (the model's values multiply beyond its range: "
                             "docs/language.md, \"Limits\")");
  }
  return v;
}

std::size_t slot_of(const void* key, std::size_t mask) {
  return static_cast<std::size_t>(mix64(reinterpret_cast<std::uintptr_t>(key))) & mask;
}

}  // namespace

NodeId AddressMemo::find(const void* key) const {
  const std::size_t mask = keys_.size() - 1;
  for (std::size_t i = slot_of(key, mask);; i = (i + 1) & mask) {
    if (keys_[i] == key) return values_[i];
    if (keys_[i] == nullptr) return -1;
  }
}

// Linear probing; the table doubles at half load.
void AddressMemo::insert(const void* key, NodeId value) {
  if ((size_ + 1) * 2 > keys_.size()) {
    std::vector<const void*> old_keys(keys_.size() * 2, nullptr);
    std::vector<NodeId> old_values(keys_.size() * 2, -1);
    old_keys.swap(keys_);
    old_values.swap(values_);
    size_ = 0;
    for (std::size_t i = 0; i < old_keys.size(); ++i)
      if (old_keys[i]) insert(old_keys[i], old_values[i]);
  }
  const std::size_t mask = keys_.size() - 1;
  std::size_t i = slot_of(key, mask);
  while (keys_[i] != nullptr && keys_[i] != key) i = (i + 1) & mask;
  if (keys_[i] == nullptr) ++size_;
  keys_[i] = key;
  values_[i] = value;
}

// Symbol table: bindings, Define'd symbols and Solve results, each seen once.
GinacConverter::GinacConverter(Dag& dag, const FunctionSpec& spec, const std::vector<Binding>& bindings)
    : dag_(dag),
      spec_(spec),
      define_state_(spec.steps.size(), kUntouched),
      define_node_(spec.steps.size(), -1),
      named_ref_(spec.steps.size(), 0),
      solve_live_(spec.steps.size(), 0),
      numeric_info_(&GiNaC::numeric::get_class_info_static()),
      add_info_(&GiNaC::add::get_class_info_static()),
      mul_info_(&GiNaC::mul::get_class_info_static()),
      power_info_(&GiNaC::power::get_class_info_static()),
      symbol_info_(&GiNaC::symbol::get_class_info_static()),
      function_info_(&GiNaC::function::get_class_info_static()) {
  auto add = [this](const GiNaC::symbol& s, SymKind kind, int step, int elem, const std::string& text, bool invariant) {
    const GiNaC::ex e(s);
    if (find_symbol(e)) throw std::runtime_error("symbol '" + s.get_name() + "' is bound or defined twice");
    symbol_index_[e.gethash()].push_back(static_cast<int>(symbols_.size()));
    symbols_.push_back({e, kind, step, elem, text, invariant});
  };
  for (const Binding& b : bindings) add(b.sym, SymKind::Binding, -1, -1, b.cpp, b.invariant);
  for (std::size_t j = 0; j < spec.steps.size(); ++j) {
    const int step = static_cast<int>(j);
    if (const auto* d = std::get_if<Define>(&spec.steps[j])) {
      add(d->sym, SymKind::Define, step, -1, {}, false);
    } else {
      const auto& s = std::get<Solve>(spec.steps[j]);
      if (s.n < 0 || s.k < 0 || s.A.size() != static_cast<std::size_t>(s.n) * static_cast<std::size_t>(s.n) ||
          (s.condition ? s.B.size() != static_cast<std::size_t>(s.n) * static_cast<std::size_t>(s.k) || s.X.size() != 1
                       : s.B.size() != static_cast<std::size_t>(s.n) * static_cast<std::size_t>(s.k) || s.X.size() != s.B.size()))
        throw std::runtime_error("solve step '" + s.label + "' has inconsistent sizes");
      for (std::size_t e = 0; e < s.X.size(); ++e) add(s.X[e], SymKind::SolveX, step, static_cast<int>(e), {}, false);
    }
  }
  // GiNaC's serial of each supported function (sqrt is a power in GiNaC, not a function).
  for (int f = 0; f <= static_cast<int>(Func::Sign); ++f) {
    try {
      const unsigned serial = GiNaC::function::find_function(func_name(static_cast<Func>(f)),
                                                             static_cast<unsigned>(func_arity(static_cast<Func>(f))));
      function_serials_.emplace_back(serial, static_cast<Func>(f));
    } catch (const std::exception&) {
    }
  }
}

GinacConverter::SymInfo* GinacConverter::find_symbol(const GiNaC::ex& e) {
  auto it = symbol_index_.find(e.gethash());
  if (it == symbol_index_.end()) return nullptr;
  for (int i : it->second)
    if (symbols_[static_cast<std::size_t>(i)].sym.is_equal(e)) return &symbols_[static_cast<std::size_t>(i)];
  return nullptr;
}

bool GinacConverter::function_of(const GiNaC::ex& e, Func& f) const {
  const unsigned serial = GiNaC::ex_to<GiNaC::function>(e).get_serial();
  for (const auto& [s, fn] : function_serials_) {
    if (s == serial) {
      f = fn;
      return true;
    }
  }
  return false;
}

// Exact class by registration record; subclasses (realsymbol, ...) by dynamic_cast.
GinacConverter::GKind GinacConverter::classify(const GiNaC::ex& e) const {
  const GiNaC::registered_class_info* ci = &GiNaC::ex_to<GiNaC::basic>(e).get_class_info();
  if (ci == numeric_info_) return GKind::Numeric;
  if (ci == symbol_info_) return GKind::Symbol;
  if (ci == mul_info_) return GKind::Mul;
  if (ci == add_info_) return GKind::Add;
  if (ci == power_info_) return GKind::Power;
  if (ci == function_info_) return GKind::Function;
  if (GiNaC::is_a<GiNaC::symbol>(e)) return GKind::Symbol;
  if (GiNaC::is_a<GiNaC::constant>(e)) return GKind::Constant;
  if (GiNaC::is_a<GiNaC::function>(e)) return GKind::Function;
  return GKind::Other;
}

// Leaves become nodes at once; a Define'd symbol starts the conversion of its value;
// anything else is an operator whose operands are converted first (is_leaf = false).
NodeId GinacConverter::leaf_or_start(const GiNaC::ex& e, GKind kind, bool& is_leaf, int& define_step, Func& func) {
  is_leaf = true;
  define_step = -1;
  switch (kind) {
    case GKind::Numeric:
      return dag_.make_number(to_double_checked(GiNaC::ex_to<GiNaC::numeric>(e), e));
    case GKind::Add:
    case GKind::Mul:
    case GKind::Power:
      is_leaf = false;
      return -1;
    case GKind::Function:
      // A derivative of a function (D[0](csgn)(x)) carries its function's serial: never it.
      if (GiNaC::is_a<GiNaC::fderivative>(e))
        throw std::runtime_error("unsupported derivative of a function in " + printed(e));
      if (!function_of(e, func)) {
        const std::string name = GiNaC::ex_to<GiNaC::function>(e).get_name();
        // GiNaC's derivative of abs(x) reads conjugate(x) (its symbols may be complex).
        const char* hint = name == "conjugate" ? " (a derivative of abs(): write abs(x) as sqrt(x^2) where the equations "
                                                 "differentiate it, as in a position constraint)"
                                               : "";
        throw std::runtime_error("unsupported function '" + name + "' in " + printed(e) + hint);
      }
      is_leaf = false;
      return -1;
    case GKind::Constant: {
      const GiNaC::ex v = e.evalf();
      if (!GiNaC::is_exactly_a<GiNaC::numeric>(v)) throw std::runtime_error("cannot evaluate constant " + printed(e));
      return dag_.make_number(to_double_checked(GiNaC::ex_to<GiNaC::numeric>(v), e));
    }
    case GKind::Other:
      throw std::runtime_error("cannot lower expression " + printed(e));
    case GKind::Symbol:
      break;
  }
  SymInfo* info = find_symbol(e);
  if (!info)
    throw std::runtime_error("unbound symbol '" + GiNaC::ex_to<GiNaC::symbol>(e).get_name() + "' in function '" +
                             spec_.name + "'");
  switch (info->kind) {
    case SymKind::Binding:
      if (info->node < 0) info->node = dag_.make_input(info->text, info->invariant);
      return info->node;
    case SymKind::SolveX:
      solve_live_[static_cast<std::size_t>(info->step)] = 1;
      if (info->node < 0) info->node = dag_.make_sym(info->step, info->elem);
      return info->node;
    case SymKind::Define: {
      const Define& d = std::get<Define>(spec_.steps[static_cast<std::size_t>(info->step)]);
      // A named number (a speed that the minimal state rebuilds as a constant 0) is the
      // number itself, so that products with it fold away.
      if (d.named && GiNaC::is_exactly_a<GiNaC::numeric>(d.value))
        return dag_.make_number(to_double_checked(GiNaC::ex_to<GiNaC::numeric>(d.value), d.value));
      if (d.named) {
        named_ref_[static_cast<std::size_t>(info->step)] = 1;
        return dag_.make_sym(info->step, -1);
      }
      break;
    }
  }
  const auto st = static_cast<std::size_t>(info->step);
  if (define_state_[st] == kDone) return define_node_[st];
  if (define_state_[st] == kInProgress)
    throw std::runtime_error("definition of '" + GiNaC::ex_to<GiNaC::symbol>(e).get_name() + "' depends on itself");
  define_state_[st] = kInProgress;
  is_leaf = false;
  define_step = info->step;
  return -1;
}

// GiNaC makes a sum that is a factor of a product, or the base of an integer power,
// "unit normal": it flips the sum's sign so that its *first* term has a positive
// coefficient and moves the sign into the coefficient. Which term is first depends on
// GiNaC's run-dependent order, so the same expression has (a-b)*c in one run and
// -(b-a)*c in another. Such sums are therefore given our own canonical sign
// (Dag::canonical_sign), and the sign moves into the product's coefficient.
// SignClass of an operand: 1 = a GiNaC sum, 2 = a GiNaC integer power of a sum.
bool GinacConverter::is_sum_power(const GiNaC::ex& e) const {
  const GiNaC::ex& ex_exp = e.op(1);
  return classify(e.op(0)) == GKind::Add && GiNaC::is_exactly_a<GiNaC::numeric>(ex_exp) &&
         GiNaC::ex_to<GiNaC::numeric>(ex_exp).is_integer();
}

// Operator node from its converted operands (with their sign classes, see above).
NodeId GinacConverter::build(GKind kind, Func func, const NodeId* kids, const std::uint8_t* classes, std::size_t nkids) {
  switch (kind) {
    case GKind::Add:
      return dag_.make_add(std::vector<NodeId>(kids, kids + nkids));
    case GKind::Mul: {
      std::vector<NodeId> factors(kids, kids + nkids);
      bool negative = false;
      for (std::size_t i = 0; i < nkids; ++i) {
        if (classes[i] == 1) {
          bool flipped = false;
          factors[i] = dag_.canonical_sign(factors[i], flipped);
          negative = negative != flipped;
        } else if (classes[i] == 2) {
          // A flipped odd power came back as -1 * power: take the -1 into the coefficient.
          const Node& n = dag_.node(factors[i]);
          if (n.kind == NodeKind::Mul && n.nchild == 2) {
            const NodeId a = dag_.child(factors[i], 0), b = dag_.child(factors[i], 1);
            const NodeId minus = dag_.node(a).kind == NodeKind::Number ? a : b;
            if (dag_.node(minus).kind == NodeKind::Number && dag_.node(minus).value == -1.0) {
              factors[i] = minus == a ? b : a;
              negative = !negative;
            }
          }
        }
      }
      if (negative) factors.push_back(dag_.make_number(-1.0));
      return dag_.make_mul(std::move(factors));
    }
    case GKind::Power: {
      const Node& e = dag_.node(kids[1]);
      if (classes[0] == 1 && e.kind == NodeKind::Number && std::nearbyint(e.value) == e.value) {
        const double exponent = e.value;
        bool flipped = false;
        const NodeId base = dag_.canonical_sign(kids[0], flipped);
        const NodeId p = dag_.make_pow(base, kids[1]);
        const bool odd = std::fmod(exponent, 2.0) != 0.0;
        return flipped && odd ? dag_.make_mul({dag_.make_number(-1.0), p}) : p;
      }
      return dag_.make_pow(kids[0], kids[1]);
    }
    default:
      return dag_.make_call(func, std::vector<NodeId>(kids, kids + nkids));
  }
}

// Iterative post-order conversion (GiNaC trees can be deeper than the call stack allows).
// Operator nodes that something besides us holds (reference count >= 2) are memoised by
// address and kept alive, so an address is never reused for a different node while the
// memo exists. A node only we hold (a temporary made by op(), e.g. add's coeff*rest) cannot
// be met again, so it is not memoised. Leaves are cheap and never memoised.
NodeId GinacConverter::convert(const GiNaC::ex& root, int context_step) {
  struct Frame {
    GiNaC::ex e;
    std::size_t next = 0;
    std::size_t nops = 0;
    std::size_t kid_base = 0;
    int define_step = -1;  // >= 0: this frame converts that Define's value
    bool memoise = false;
    GKind kind = GKind::Other;
    Func func = Func::Sin;
    std::uint8_t sign_class = 0;
  };
  std::vector<Frame> frames;
  std::vector<NodeId> kids;
  std::vector<std::uint8_t> classes;  // sign class of each entry of `kids`

  // Start one expression: either a finished node is pushed on `kids`, or a frame is opened.
  auto open = [&](const GiNaC::ex& e) {
    // Only a node with another holder can be in the memo (the memo keeps its nodes alive).
    const GKind kind = classify(e);
    const bool op = kind == GKind::Add || kind == GKind::Mul || kind == GKind::Power || kind == GKind::Function;
    const std::uint8_t sign_class = kind == GKind::Add ? 1 : kind == GKind::Power && is_sum_power(e) ? 2 : 0;
    const bool shared = op && GiNaC::ex_to<GiNaC::basic>(e).get_refcount() >= 2;
    if (shared) {
      const NodeId hit = memo_.find(address(e));
      if (hit >= 0) {
        kids.push_back(hit);
        classes.push_back(sign_class);
        return;
      }
    }
    bool is_leaf = false;
    int define_step = -1;
    Func func = Func::Sin;
    const NodeId id = leaf_or_start(e, kind, is_leaf, define_step, func);
    if (is_leaf) {
      kids.push_back(id);
      classes.push_back(0);
      return;
    }
    Frame f;
    f.memoise = shared;  // a Define'd symbol is resolved through define_state_ instead
    f.kind = kind;
    f.func = func;
    f.sign_class = sign_class;
    f.e = e;
    f.kid_base = kids.size();
    f.define_step = define_step;
    f.nops = define_step >= 0 ? 1 : e.nops();
    frames.push_back(std::move(f));
  };

  open(root);
  while (!frames.empty()) {
    Frame& top = frames.back();
    // Descend into the next operand (a Define'd symbol's single operand is its value).
    if (top.next < top.nops) {
      const std::size_t i = top.next++;
      if (top.define_step >= 0) {
        const GiNaC::ex value = std::get<Define>(spec_.steps[static_cast<std::size_t>(top.define_step)]).value;
        open(value);
      } else {
        const GiNaC::ex child = top.e.op(i);
        open(child);
      }
      continue;
    }
    // All operands done: build (or substitute) this node, memoise it, hand it to the parent.
    NodeId id;
    if (top.define_step >= 0) {
      id = kids.back();
      const auto st = static_cast<std::size_t>(top.define_step);
      if (dag_.node(id).max_step >= top.define_step)
        throw std::runtime_error("definition of '" + std::get<Define>(spec_.steps[st]).sym.get_name() +
                                 "' reads the result of a later solve");
      define_state_[st] = kDone;
      define_node_[st] = id;
    } else {
      id = build(top.kind, top.func, kids.data() + top.kid_base, classes.data() + top.kid_base,
                 kids.size() - top.kid_base);
    }
    kids.resize(top.kid_base);
    classes.resize(top.kid_base);
    const std::uint8_t sign_class = top.sign_class;
    if (top.memoise) {
      memo_.insert(address(top.e), id);
      keep_alive_.push_back(std::move(top.e));
    }
    frames.pop_back();
    kids.push_back(id);
    classes.push_back(sign_class);
  }
  const NodeId result = kids.back();
  if (dag_.node(result).max_step >= context_step)
    throw std::runtime_error("an expression of function '" + spec_.name + "' reads a solve result before it is computed");
  return result;
}

}  // namespace mbsc::ir
