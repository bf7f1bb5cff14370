// SPDX-License-Identifier: GPL-2.0-or-later
// Printing a scheduled Program as C++ statements, counting exactly the operations printed.
// Every inline node is used once, so it is printed (and counted) once.
#include <cmath>
#include <cstring>
#include <string>
#include <unordered_map>
#include <vector>

#include "../emit/number_literal.hpp"
#include "op_count.hpp"
#include "program_ir.hpp"

namespace mbsc::ir {

namespace {

// C++ precedence levels of printed expressions (higher binds tighter).
enum Prec : int { kSum = 1, kProduct = 2, kUnary = 3, kPrimary = 4 };

struct Text {
  std::string s;
  int prec;
};

std::string join(const std::vector<std::string>& parts, const char* sep) {
  std::string out;
  std::size_t size = 0;
  for (const auto& part : parts) size += part.size() + std::char_traits<char>::length(sep);
  out.reserve(size);
  for (std::size_t i = 0; i < parts.size(); ++i) {
    if (i) out += sep;
    out += parts[i];
  }
  return out;
}

// A label as a one-line comment: no line breaks, no trailing backslash (line splice).
std::string comment_text(const std::string& label) {
  std::string out;
  for (char c : label) out.push_back(c == '\n' || c == '\r' || c == '\t' || c == '\v' || c == '\f' ? ' ' : c);
  while (!out.empty() && (out.back() == '\\' || out.back() == ' ')) out.pop_back();
  return out;
}

class Printer {
 public:
  Printer(const Program& prog, OpCount& ops) : prog_(prog), dag_(prog.dag), ops_(ops) {
    for (const SolveBlock& s : prog.solves) {
      if (static_cast<std::size_t>(s.step) >= solve_number_.size()) solve_number_.resize(static_cast<std::size_t>(s.step) + 1, -1);
      solve_number_[static_cast<std::size_t>(s.step)] = s.number;
    }
  }

  // Statements, then the finiteness check and the status. When most outputs are the
  // literal 0 (a Jacobian, a sparse mass matrix), OUT is zeroed by one loop just before
  // the first output and only the other entries are written.
  std::string body() {
    std::vector<std::string> lines;
    const int zeros = zero_outputs();
    const bool fill = 2 * zeros > prog_.nout;
    bool filled = false;
    // Several solves share one test of the inputs for their failure paths (written once:
    // a list of every input per solve grew as solves x inputs in a big model).
    int nsolves = 0;
    for (const Statement& st : prog_.statements)
      nsolves += st.kind == Statement::Kind::Solve && !prog_.solves[static_cast<std::size_t>(st.index)].condition;  // rcond blocks have no failure path
    shared_input_check_ = nsolves > 1 && !prog_.live_inputs.empty();
    if (shared_input_check_)
      lines.push_back("  const auto inputs_finite_ = [&]() {\n    const double in_[" + std::to_string(prog_.live_inputs.size()) +
                      "] = {" + join(prog_.live_inputs, ", ") + "};\n    return all_finite(in_, " +
                      std::to_string(prog_.live_inputs.size()) + ");\n  };");
    for (const Statement& st : prog_.statements) {
      if (fill && st.kind == Statement::Kind::Output && !filled) {
        lines.push_back("  for (int i = 0; i < " + std::to_string(prog_.nout) + "; ++i) " + prog_.out_array + "[i] = 0.0;  // " +
                        std::to_string(zeros) + " of the " + std::to_string(prog_.nout) + " entries are zero");
        filled = true;
      }
      if (fill && st.kind == Statement::Kind::Output && literal_zero(st.node)) continue;
      switch (st.kind) {
        case Statement::Kind::Temp:
          lines.push_back("  const double " + name(st.node) + " = " + expr(st.node).s + ";");
          break;
        case Statement::Kind::Solve:
          solve(prog_.solves[static_cast<std::size_t>(st.index)], lines);
          break;
        case Statement::Kind::Output:
          lines.push_back("  " + prog_.out_array + "[" + std::to_string(st.index) + "] = " + ref(st.node).s + ";");
          break;
      }
    }
    if (prog_.nout > 0)
      lines.push_back("  if (!all_finite(" + prog_.out_array + ", " + std::to_string(prog_.nout) + ")) return 2;");
    else
      lines.push_back("  (void)OUT;");
    lines.push_back("  return 0;");
    return join(lines, "\n");
  }

 private:
  // An output that is the number +0 (what a structurally zero entry lowers to).
  bool literal_zero(NodeId id) const {
    const Node& n = dag_.node(id);
    return n.kind == NodeKind::Number && n.value == 0.0 && !std::signbit(n.value);
  }

  int zero_outputs() const {
    int count = 0;
    for (const Statement& st : prog_.statements) count += st.kind == Statement::Kind::Output && literal_zero(st.node) ? 1 : 0;
    return count;
  }

  const std::string& name(NodeId id) const { return prog_.names[static_cast<std::size_t>(id)]; }
  bool inline_node(NodeId id) const { return name(id).empty(); }
  static std::string wrap(const Text& t, int min_prec) { return t.prec < min_prec ? "(" + t.s + ")" : t.s; }

  // double A_i = {rows}; double B_i = {rows}; solve; status 1 when singular, 2 when A_i is not finite.
  void solve(const SolveBlock& s, std::vector<std::string>& lines) {
    const std::string id = std::to_string(s.number);
    const std::string label = comment_text(s.label);
    if (s.condition)
      lines.push_back("  // B_" + id + "[0] = reciprocal condition number of A_" + id + " (" + std::to_string(s.n) + "x" +
                      std::to_string(s.n) + ")" + (label.empty() ? "" : ": " + label));
    else
      lines.push_back("  // solve A_" + id + " X = B_" + id + " (" + std::to_string(s.n) + "x" + std::to_string(s.n) +
                      ", " + std::to_string(s.k) + (s.k == 1 ? " column" : " columns") + ")" +
                      (label.empty() ? "" : ": " + label));
    auto array = [&](const char* arr, const std::vector<NodeId>& entries, int cols) {
      lines.push_back("  double " + std::string(arr) + id + "[" + std::to_string(entries.size()) + "] = {");
      for (std::size_t r = 0; r * static_cast<std::size_t>(cols) < entries.size(); ++r) {
        std::vector<std::string> row;
        for (int c = 0; c < cols; ++c) row.push_back(ref(entries[r * static_cast<std::size_t>(cols) + static_cast<std::size_t>(c)]).s);
        const bool last = (r + 1) * static_cast<std::size_t>(cols) >= entries.size();
        lines.push_back("      " + join(row, ", ") + (last ? "};" : ","));
      }
    };
    if (s.condition) {
      // A_i is destroyed; G_i holds the gain columns (if any); B_i holds the result, then
      // A_i^-1 as workspace.
      array("A_", s.A, s.n);
      if (s.k > 0) array("G_", s.B, s.k);
      lines.push_back("  double B_" + id + "[" + std::to_string(s.n * s.n + 1) + "];");
      if (s.spd && s.rank > 0) {  // semidefinite: the pivots' ratio
        lines.push_back("  B_" + id + "[0] = psd_rcond<" + std::to_string(s.n) + ", " + std::to_string(s.rank) + ">(A_" + id + ");");
        ops_.solve_flops += chol_solve_flops(s.n, 0);
        return;
      }
      lines.push_back("  B_" + id + "[0] = rcond_1norm<" + std::to_string(s.n) + ", " + std::to_string(s.k) + ", " +
                      (s.spd ? "true" : "false") + ">(A_" + id + ", " + (s.k > 0 ? "G_" + id : std::string("nullptr")) +
                      ", B_" + id + " + 1);");
      ops_.solve_flops += lu_solve_flops(s.n, s.n) + 2L * s.n * s.n + 2L * s.n * s.n * s.k + (s.spd ? s.n * s.n * s.n / 3L : 0L);
      return;
    }
    array("A_", s.A, s.n);
    array("B_", s.B, s.k);
    // The smallest systems go to the loop-free solvers (same arithmetic).
    const std::string call = s.spd && s.rank > 0 ? "psd_min_norm_solve<" + std::to_string(s.n) + ", " + std::to_string(s.k) +
                                                       ", " + std::to_string(s.rank) + ">("
                             : s.n == 1 ? std::string(s.spd ? "chol_1x1(" : "solve_1x1(") + std::to_string(s.k) + ", "
                             : s.n == 2 && !s.spd ? "lu_solve_2x2<" + std::to_string(s.k) + ">("
                                                  : std::string(s.spd ? "chol_solve<" : "lu_solve<") + std::to_string(s.n) +
                                                        ", " + std::to_string(s.k) + ">(";
    // A failed solve is status 1 (singular) unless its matrix or an input the function
    // reads is not finite (a NaN parameter, an infinite state, 1/inf = 0 on a pivot):
    // then it is 2, like a non-finite result. Checked on this failure path only. (in_
    // cannot meet a variable: generated names have no trailing '_', see identifiers.hpp.)
    const std::string finite_matrix = "all_finite(A_" + id + ", " + std::to_string(s.n * s.n) + ")";
    if (prog_.live_inputs.empty()) {
      lines.push_back("  if (" + call + "A_" + id + ", B_" + id + ") != 0) return " + finite_matrix + " ? 1 : 2;");
    } else if (shared_input_check_) {
      lines.push_back("  if (" + call + "A_" + id + ", B_" + id + ") != 0) return " + finite_matrix +
                      " && inputs_finite_() ? 1 : 2;");
    } else {
      lines.push_back("  if (" + call + "A_" + id + ", B_" + id + ") != 0) {");
      lines.push_back("    const double in_[" + std::to_string(prog_.live_inputs.size()) + "] = {" +
                      join(prog_.live_inputs, ", ") + "};");
      lines.push_back("    return " + finite_matrix + " && all_finite(in_, " + std::to_string(prog_.live_inputs.size()) +
                      ") ? 1 : 2;");
      lines.push_back("  }");
    }
    ops_.solve_flops += s.spd ? chol_solve_flops(s.n, s.k) : lu_solve_flops(s.n, s.k);
  }

  // A child as its parent sees it: a temporary's name or the inline expression.
  Text ref(NodeId id) { return inline_node(id) ? expr(id) : Text{name(id), kPrimary}; }

  // Literal text of a constant, formatted once per distinct value (lookup-only cache).
  std::string number(double v) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &v, sizeof bits);
    auto it = numbers_.find(bits);
    if (it == numbers_.end()) it = numbers_.emplace(bits, emit::cpp_double_literal(v)).first;
    return it->second;
  }

  // The full expression of a node (its definition, even when it is a temporary).
  Text expr(NodeId id) {
    const Node& n = dag_.node(id);
    switch (n.kind) {
      case NodeKind::Number:
        return {number(n.value), std::signbit(n.value) ? kUnary : kPrimary};
      case NodeKind::Input:
        return {dag_.input_text(n.ref), kPrimary};
      case NodeKind::Sym:
        if (n.elem == -1) return ref(prog_.define_ref_value[static_cast<std::size_t>(n.ref)]);  // a named Define
        return {"B_" + std::to_string(solve_number_[static_cast<std::size_t>(n.ref)]) + "[" + std::to_string(n.elem) + "]",
                kPrimary};
      case NodeKind::Add:
        return add(id);
      case NodeKind::Mul:
        return mul(id, false);
      case NodeKind::Pow:
        return power(id);
      case NodeKind::Call:
        return call(id);
    }
    return {"", kPrimary};
  }

  // First numeric factor of an inline product (its sign is the product's sign), or -1.
  NodeId coefficient(NodeId mul) const {
    const Node& n = dag_.node(mul);
    for (std::int32_t i = 0; i < n.nchild; ++i)
      if (dag_.node(dag_.child(mul, i)).kind == NodeKind::Number) return dag_.child(mul, i);
    return -1;
  }

  // An inline term printed as a subtraction: a negative number or a product with a
  // negative coefficient.
  bool negative(NodeId term) const {
    if (!inline_node(term)) return false;
    const Node& n = dag_.node(term);
    if (n.kind == NodeKind::Number) return n.value < 0;
    if (n.kind != NodeKind::Mul) return false;
    const NodeId c = coefficient(term);
    return c >= 0 && dag_.node(c).value < 0;
  }

  // Sum: non-constant terms in canonical order, constants last; a positive term leads when
  // there is one; negative terms print as "- |term|". `flip` prints the negated sum (every
  // sign reversed), for a product that takes the sign out: -2.0*t*(-a - b) -> 2.0*t*(a + b).
  Text add(NodeId id, bool flip = false) {
    const Node& n = dag_.node(id);
    std::vector<NodeId> terms;
    for (std::int32_t i = 0; i < n.nchild; ++i)
      if (dag_.node(dag_.child(id, i)).kind != NodeKind::Number) terms.push_back(dag_.child(id, i));
    for (std::int32_t i = 0; i < n.nchild; ++i)
      if (dag_.node(dag_.child(id, i)).kind == NodeKind::Number) terms.push_back(dag_.child(id, i));
    auto subtracted = [&](NodeId t) { return negative(t) != flip; };
    for (std::size_t i = 0; i < terms.size(); ++i) {
      if (subtracted(terms[i])) continue;
      const NodeId lead = terms[i];
      terms.erase(terms.begin() + static_cast<std::ptrdiff_t>(i));
      terms.insert(terms.begin(), lead);
      break;
    }
    // |term| for a term printed with a sign of its own (a negative one, without its "-").
    auto magnitude = [&](NodeId t) -> Text {
      if (!negative(t)) return ref(t);
      const Node& tn = dag_.node(t);
      return tn.kind == NodeKind::Number ? Text{number(-tn.value), kPrimary} : mul(t, true);
    };
    std::string out;
    for (std::size_t i = 0; i < terms.size(); ++i) {
      const NodeId t = terms[i];
      if (i == 0 && !flip) {
        out = wrap(ref(t), kSum);
      } else if (i == 0) {
        const Text m = magnitude(t);
        out = subtracted(t) ? "-" + wrap(m, kProduct) : wrap(m, kSum);
      } else if (subtracted(t)) {
        out += " - " + wrap(magnitude(t), kProduct);
      } else {
        const Text pos = magnitude(t);
        out += " + " + (pos.s[0] == '-' ? "(" + pos.s + ")" : wrap(pos, kSum));
      }
    }
    ops_.adds += static_cast<long>(terms.size()) - 1;
    return {out, kSum};
  }

  // An inline sum with more subtracted terms than added ones (printed negated in products).
  bool mostly_subtracted(NodeId f) const {
    const Node& n = dag_.node(f);
    if (n.kind != NodeKind::Add || !inline_node(f)) return false;
    int neg = 0;
    for (std::int32_t i = 0; i < n.nchild; ++i) neg += negative(dag_.child(f, i)) ? 1 : 0;
    return 2 * neg > n.nchild;
  }

  // Product: [-][coefficient*]factors[/denominator]. Inline powers with exponent -1..-4 or
  // -1/2 go to the denominator, inline powers 2..4 repeat their base; `negate` flips the
  // coefficient's sign (used for "a - 2.0*b").
  Text mul(NodeId id, bool negate) {
    const Node& n = dag_.node(id);
    const NodeId coef = coefficient(id);
    double c = coef >= 0 ? dag_.node(coef).value : 1.0;
    if (negate) c = -c;
    bool minus = std::signbit(c);
    const double mag = std::fabs(c);
    std::vector<std::string> num, den;
    if (coef >= 0 && mag != 1.0) num.push_back(number(mag));
    for (std::int32_t i = 0; i < n.nchild; ++i) {
      const NodeId f = dag_.child(id, i);
      if (f == coef) continue;
      const Node& fn = dag_.node(f);
      if (fn.kind == NodeKind::Pow && inline_node(f) && dag_.node(dag_.child(f, 1)).kind == NodeKind::Number) {
        const double e = dag_.node(dag_.child(f, 1)).value;
        const int r = repeated_power(dag_, f);
        const NodeId base = dag_.child(f, 0);
        if (r != 0 || e == -1.0) {
          const std::string b = wrap(ref(base), kPrimary);
          auto& dest = r > 0 ? num : den;
          for (int k = 0; k < (r == 0 ? 1 : std::abs(r)); ++k) dest.push_back(b);
          continue;
        }
        if (e == -0.5) {
          den.push_back("std::sqrt(" + ref(base).s + ")");
          ++ops_.calls;
          continue;
        }
      }
      if (mostly_subtracted(f)) {  // -a - b: print (a + b) and take the sign out
        num.push_back(wrap(add(f, true), kPrimary));
        minus = !minus;
        continue;
      }
      num.push_back(wrap(ref(f), kPrimary));
    }
    // A coefficient of magnitude 1 is dropped unless it is all there is ("1.0/x", "-1.0/x").
    if (num.empty()) num.push_back(number(mag));
    std::string out = (minus ? "-" : "") + join(num, "*");
    ops_.muls += static_cast<long>(num.size()) - 1;
    if (!den.empty()) {
      out += "/" + (den.size() == 1 ? den[0] : "(" + join(den, "*") + ")");
      ops_.muls += static_cast<long>(den.size()) - 1;
      ++ops_.divs;
    }
    const int prec = minus ? kUnary : (num.size() > 1 || !den.empty()) ? kProduct : kPrimary;
    return {out, prec};
  }

  // Power: x*x..x for 2..4, 1.0/x, 1.0/(x*x..), std::sqrt, 1.0/std::sqrt, else std::pow.
  Text power(NodeId id) {
    const NodeId base = dag_.child(id, 0);
    const NodeId ex = dag_.child(id, 1);
    const int r = repeated_power(dag_, id);
    if (r != 0) {
      const std::string b = wrap(ref(base), kPrimary);
      std::vector<std::string> parts(static_cast<std::size_t>(std::abs(r)), b);
      ops_.muls += std::abs(r) - 1;
      if (r > 0) return {join(parts, "*"), kProduct};
      ++ops_.divs;
      return {"1.0/(" + join(parts, "*") + ")", kProduct};
    }
    const Node& en = dag_.node(ex);
    if (en.kind == NodeKind::Number && en.value == -1.0) {
      ++ops_.divs;
      return {"1.0/" + wrap(ref(base), kPrimary), kProduct};
    }
    if (en.kind == NodeKind::Number && (en.value == 0.5 || en.value == -0.5)) {
      ++ops_.calls;
      const std::string root = "std::sqrt(" + ref(base).s + ")";
      if (en.value > 0) return {root, kPrimary};
      ++ops_.divs;
      return {"1.0/" + root, kProduct};
    }
    ++ops_.calls;
    const std::string b = ref(base).s;
    return {"std::pow(" + b + ", " + ref(ex).s + ")", kPrimary};
  }

  Text call(NodeId id) {
    const Node& n = dag_.node(id);
    std::vector<std::string> args;
    for (std::int32_t i = 0; i < n.nchild; ++i) args.push_back(ref(dag_.child(id, i)).s);
    ++ops_.calls;
    // sign(a) in {-1, 0, 1} without a helper: copysign(1 or 0, a) (a = -0 gives -0).
    if (static_cast<Func>(n.func) == Func::Sign)
      return {"std::copysign(static_cast<double>(" + args[0] + " != 0.0), " + args[0] + ")", kPrimary};
    return {std::string(func_cpp(static_cast<Func>(n.func))) + "(" + join(args, ", ") + ")", kPrimary};
  }

  const Program& prog_;
  bool shared_input_check_ = false;  // the solves' failure paths call inputs_finite_()
  const Dag& dag_;
  OpCount& ops_;
  std::vector<int> solve_number_;
  std::unordered_map<std::uint64_t, std::string> numbers_;
};

}  // namespace

std::string print_program(const Program& prog, OpCount& ops) { return Printer(prog, ops).body(); }

}  // namespace mbsc::ir
