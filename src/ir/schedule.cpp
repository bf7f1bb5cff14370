// SPDX-License-Identifier: GPL-2.0-or-later
// Scheduling of a Program: which nodes become named temporaries, what they are called,
// and the order of the statements. Only the roots' order, the canonical child order and
// structural properties decide anything here; node indices are mere handles.
#include <algorithm>
#include <cctype>
#include <climits>
#include <cstdlib>
#include <map>
#include <set>
#include <tuple>
#include <stdexcept>

#include "identifiers.hpp"
#include "program_ir.hpp"

namespace mbsc::ir {

namespace {

bool is_leaf(const Node& n) {
  return n.kind == NodeKind::Number || n.kind == NodeKind::Input || n.kind == NodeKind::Sym;
}

bool is_trig(const Node& n) {
  return n.kind == NodeKind::Call && (n.func == static_cast<std::uint8_t>(Func::Sin) ||
                                      n.func == static_cast<std::uint8_t>(Func::Cos));
}

// Calls `f(node)` for every root node, in root order (Solve: A then B, row-major).
template <class F>
void for_each_root_node(const Program& prog, F f) {
  for (const Root& r : prog.roots) {
    if (r.kind == Root::Kind::Solve) {
      const SolveBlock& s = prog.solves[static_cast<std::size_t>(r.index)];
      for (NodeId e : s.A) f(r, e);
      for (NodeId e : s.B) f(r, e);
    } else {
      f(r, r.node);
    }
  }
}

class Scheduler {
 public:
  Scheduler(Program& prog, const std::vector<std::string>& define_names, const std::vector<std::string>& reserved)
      : prog_(prog), dag_(prog.dag), define_names_(define_names), taken_(reserved.begin(), reserved.end()) {}

  void run() {
    const std::size_t n = dag_.size();
    prog_.names.assign(n, std::string());
    live_.assign(n, 0);
    uses_.assign(n, 0);
    temp_.assign(n, 0);
    sin_of_.assign(n, -1);
    cos_of_.assign(n, -1);
    emitted_.assign(n, 0);
    count_uses();
    choose_temps();
    name_defines();
    cap_inline_depth();
    first_visit_order();
    group_leaf_trig_args();
    emit_statements();
    collect_used_args();
  }

 private:
  // Live nodes and use counts: one count per parent edge and per root occurrence
  // (a Define root reads nothing by itself, so it adds no use).
  void count_uses() {
    count_uses_from_roots();
    // A named Define's readers hold its leaf Sym(step, -1): they use its value node.
    for (std::size_t i = 0; i < dag_.size(); ++i) {
      const Node& nd = dag_.node(static_cast<NodeId>(i));
      if (nd.kind != NodeKind::Sym || nd.elem != -1 || !live_[i]) continue;
      const NodeId value = prog_.define_ref_value[static_cast<std::size_t>(nd.ref)];
      if (value >= 0) uses_[static_cast<std::size_t>(value)] += uses_[i];
    }
  }

  void count_uses_from_roots() {
    std::vector<NodeId> stack;
    for_each_root_node(prog_, [&](const Root& r, NodeId root) {
      if (r.kind != Root::Kind::Define) ++uses_[static_cast<std::size_t>(root)];
      if (live_[static_cast<std::size_t>(root)]) return;
      live_[static_cast<std::size_t>(root)] = 1;
      stack.push_back(root);
      while (!stack.empty()) {
        const NodeId id = stack.back();
        stack.pop_back();
        const Node& nd = dag_.node(id);
        for (std::int32_t i = 0; i < nd.nchild; ++i) {
          const NodeId c = dag_.child(id, i);
          ++uses_[static_cast<std::size_t>(c)];
          if (!live_[static_cast<std::size_t>(c)]) {
            live_[static_cast<std::size_t>(c)] = 1;
            stack.push_back(c);
          }
        }
      }
    });
  }

  // Temporaries: shared nodes, every sin/cos (paired by argument), and the base of a
  // power printed as repeated multiplication.
  void choose_temps() {
    for (std::size_t i = 0; i < dag_.size(); ++i) {
      const NodeId id = static_cast<NodeId>(i);
      const Node& nd = dag_.node(id);
      if (!live_[i] || is_leaf(nd)) continue;
      if (uses_[i] >= 2) temp_[i] = 1;
      if (is_trig(nd)) {
        temp_[i] = 1;
        auto& slot = nd.func == static_cast<std::uint8_t>(Func::Sin) ? sin_of_ : cos_of_;
        slot[static_cast<std::size_t>(dag_.child(id, 0))] = id;
      }
      if (nd.kind == NodeKind::Pow && repeated_power(dag_, id) != 0) {
        const NodeId base = dag_.child(id, 0);
        if (!is_leaf(dag_.node(base))) temp_[static_cast<std::size_t>(base)] = 1;
      }
    }
  }

  // A live Define's value is a temporary named after the symbol (first Define wins when
  // two Defines share a value); leaf values stay inline.
  void name_defines() {
    for (const Root& r : prog_.roots) {
      if (r.kind != Root::Kind::Define) continue;
      const auto id = static_cast<std::size_t>(r.node);
      // Read by nothing after all (its readers folded a sign into a different node): dead.
      if (uses_[id] == 0) continue;
      if (is_leaf(dag_.node(r.node)) || !prog_.names[id].empty()) continue;
      temp_[id] = 1;
      prog_.names[id] = unique_name(sanitize_identifier(define_names_[static_cast<std::size_t>(r.index)]));
    }
  }

  std::string unique_name(const std::string& base) {
    std::string name = base;
    for (int suffix = 1; is_cpp_keyword(name) || is_std_macro_name(name) || is_generated_name(name) || taken_.count(name);
         ++suffix)
      name = base + "_" + std::to_string(suffix);
    taken_.insert(name);
    return name;
  }

  // Inline depth: children first (index order is topological); an expression deeper than
  // kMaxInlineDepth becomes a temporary so no printed expression nests without bound.
  void cap_inline_depth() {
    std::vector<int> depth(dag_.size(), 0);
    for (std::size_t i = 0; i < dag_.size(); ++i) {
      const NodeId id = static_cast<NodeId>(i);
      const Node& nd = dag_.node(id);
      if (!live_[i] || is_leaf(nd) || temp_[i]) continue;
      int d = 0;
      for (std::int32_t c = 0; c < nd.nchild; ++c) d = std::max(d, depth[static_cast<std::size_t>(dag_.child(id, c))]);
      if (d + 1 > kMaxInlineDepth) temp_[i] = 1;
      else depth[i] = d + 1;
    }
  }

  // Post-order position of every live node in a walk of the roots (children in canonical
  // order); orders the sin/cos pairs hoisted to the top or to just after a solve.
  void first_visit_order() {
    order_.assign(dag_.size(), -1);
    int counter = 0;
    std::vector<std::pair<NodeId, std::int32_t>> stack;
    for_each_root_node(prog_, [&](const Root&, NodeId root) {
      if (order_[static_cast<std::size_t>(root)] >= 0) return;
      stack.emplace_back(root, 0);
      order_[static_cast<std::size_t>(root)] = -2;  // on the stack
      while (!stack.empty()) {
        auto& [id, next] = stack.back();
        if (next < dag_.node(id).nchild) {
          const NodeId c = dag_.child(id, next++);
          if (order_[static_cast<std::size_t>(c)] == -1) {
            order_[static_cast<std::size_t>(c)] = -2;
            stack.emplace_back(c, 0);
          }
          continue;
        }
        order_[static_cast<std::size_t>(id)] = counter++;
        stack.pop_back();
      }
    });
  }

  // Leaf arguments of sin/cos, grouped by when they become available (-1: at the top for
  // inputs and numbers, else the Solve step producing them), each group sorted by the
  // first use of either function.
  void group_leaf_trig_args() {
    std::vector<std::tuple<int, int, NodeId>> found;  // (group, first use, argument)
    for (std::size_t i = 0; i < dag_.size(); ++i) {
      if (sin_of_[i] < 0 && cos_of_[i] < 0) continue;
      const Node& nd = dag_.node(static_cast<NodeId>(i));
      if (!is_leaf(nd) || (nd.kind == NodeKind::Sym && nd.elem == -1)) continue;
      int first = INT32_MAX;
      if (sin_of_[i] >= 0) first = std::min(first, order_[static_cast<std::size_t>(sin_of_[i])]);
      if (cos_of_[i] >= 0) first = std::min(first, order_[static_cast<std::size_t>(cos_of_[i])]);
      found.emplace_back(nd.kind == NodeKind::Sym ? nd.ref : -1, first, static_cast<NodeId>(i));
    }
    std::sort(found.begin(), found.end());
    for (const auto& [group, first, arg] : found) leaf_trig_args_[group].push_back(arg);
  }

  void emit_leaf_trig_pairs(int group) {
    auto it = leaf_trig_args_.find(group);
    if (it == leaf_trig_args_.end()) return;
    for (NodeId a : it->second) emit_trig_pair(a);
  }

  // One statement for a temporary; its name is the Define's, or the next t<N>.
  void emit_temp(NodeId id) {
    auto& name = prog_.names[static_cast<std::size_t>(id)];
    if (name.empty()) {
      do name = "t" + std::to_string(next_temp_++);
      while (taken_.count(name));
    }
    prog_.statements.push_back({Statement::Kind::Temp, id, 0});
    emitted_[static_cast<std::size_t>(id)] = 1;
  }

  // sin(a) and cos(a) together, once, named s<N>/c<N> (only those that are used).
  void emit_trig_pair(NodeId arg) {
    const NodeId s = sin_of_[static_cast<std::size_t>(arg)];
    const NodeId c = cos_of_[static_cast<std::size_t>(arg)];
    const bool need_s = s >= 0 && !emitted_[static_cast<std::size_t>(s)];
    const bool need_c = c >= 0 && !emitted_[static_cast<std::size_t>(c)];
    if (!need_s && !need_c) return;
    std::string number;
    do number = std::to_string(next_trig_++);
    while (taken_.count("s" + number) || taken_.count("c" + number));
    for (NodeId f : {s, c}) {
      if (f < 0 || emitted_[static_cast<std::size_t>(f)]) continue;
      auto& name = prog_.names[static_cast<std::size_t>(f)];
      if (name.empty()) name = (f == s ? "s" : "c") + number;
      prog_.statements.push_back({Statement::Kind::Temp, f, 0});
      emitted_[static_cast<std::size_t>(f)] = 1;
    }
  }

  // Post-order walk from one root: emit every temporary it needs, children first; right
  // after a temporary, emit the sin/cos of it (as early as their argument exists).
  void ensure(NodeId root) {
    if (emitted_[static_cast<std::size_t>(root)] || is_leaf(dag_.node(root))) return;
    std::vector<std::pair<NodeId, std::int32_t>> stack{{root, 0}};
    while (!stack.empty()) {
      auto& [id, next] = stack.back();
      if (next < dag_.node(id).nchild) {
        const NodeId c = dag_.child(id, next++);
        if (!emitted_[static_cast<std::size_t>(c)] && !is_leaf(dag_.node(c))) stack.emplace_back(c, 0);
        continue;
      }
      const NodeId done = id;
      stack.pop_back();
      if (emitted_[static_cast<std::size_t>(done)]) continue;
      const Node& nd = dag_.node(done);
      if (is_trig(nd)) {
        emit_trig_pair(dag_.child(done, 0));
      } else if (temp_[static_cast<std::size_t>(done)]) {
        emit_temp(done);
        emit_trig_pair(done);
      } else {
        emitted_[static_cast<std::size_t>(done)] = 1;  // inline: its temporaries exist now
      }
    }
  }

  // Statements: trig of inputs first, then each live step and each output in order.
  void emit_statements() {
    emit_leaf_trig_pairs(-1);
    prog_.statements.reserve(prog_.statements.size() + prog_.roots.size());
    for (const Root& r : prog_.roots) {
      switch (r.kind) {
        case Root::Kind::Define:
          if (uses_[static_cast<std::size_t>(r.node)] > 0) ensure(r.node);
          break;
        case Root::Kind::Solve: {
          const SolveBlock& s = prog_.solves[static_cast<std::size_t>(r.index)];
          for (NodeId e : s.A) ensure(e);
          for (NodeId e : s.B) ensure(e);
          prog_.statements.push_back({Statement::Kind::Solve, -1, r.index});
          emit_leaf_trig_pairs(s.step);
          break;
        }
        case Root::Kind::Output:
          ensure(r.node);
          prog_.statements.push_back({Statement::Kind::Output, r.node, r.index});
          break;
      }
    }
  }

  // Which of the arguments t, x, u, p the live inputs read (identifier tokens of the text).
  void collect_used_args() {
    bool used[6] = {false, false, false, false, false, false};
    static const char* const kArgs[6] = {"t", "x", "u", "zdot", "w", "p"};
    prog_.live_inputs.clear();
    for (std::size_t i = 0; i < dag_.size(); ++i) {
      const Node& nd = dag_.node(static_cast<NodeId>(i));
      if (!live_[i] || nd.kind != NodeKind::Input) continue;
      const std::string& text = dag_.input_text(nd.ref);
      prog_.live_inputs.push_back(text);
      for (std::size_t b = 0; b < text.size();) {
        const auto ident = [&](std::size_t j) {
          const char c = text[j];
          return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_';
        };
        if (!ident(b)) {
          ++b;
          continue;
        }
        std::size_t e = b;
        while (e < text.size() && ident(e)) ++e;
        const std::string tok = text.substr(b, e - b);
        for (int a = 0; a < 6; ++a)
          if (tok == kArgs[a]) used[a] = true;
        b = e;
      }
    }
    // Natural order: p[2] before p[10] (the array, then the index).
    auto key = [](const std::string& text) {
      const auto open = text.find('[');
      if (open == std::string::npos) return std::make_pair(text, -1L);
      return std::make_pair(text.substr(0, open), std::strtol(text.c_str() + open + 1, nullptr, 10));
    };
    std::sort(prog_.live_inputs.begin(), prog_.live_inputs.end(),
              [&](const std::string& a, const std::string& b) { return key(a) < key(b); });
    prog_.live_inputs.erase(std::unique(prog_.live_inputs.begin(), prog_.live_inputs.end()), prog_.live_inputs.end());
    prog_.used_args.clear();
    for (int a = 0; a < 6; ++a)
      if (used[a]) prog_.used_args.emplace_back(kArgs[a]);
  }

  Program& prog_;
  const Dag& dag_;
  const std::vector<std::string>& define_names_;
  std::set<std::string> taken_;
  std::vector<char> live_;
  std::vector<int> uses_;
  std::vector<char> temp_;
  std::vector<NodeId> sin_of_;
  std::vector<NodeId> cos_of_;
  std::vector<int> order_;
  std::map<int, std::vector<NodeId>> leaf_trig_args_;
  std::vector<char> emitted_;
  int next_temp_ = 0;
  int next_trig_ = 0;
};

}  // namespace

int repeated_power(const Dag& dag, NodeId pow) {
  const Node& e = dag.node(dag.child(pow, 1));
  if (e.kind != NodeKind::Number) return 0;
  const double v = e.value;
  if (!(v >= -kMaxRepeatedPower && v <= kMaxRepeatedPower)) return 0;
  const int n = static_cast<int>(v);
  if (static_cast<double>(n) != v || (n > -2 && n < 2)) return 0;
  return n;
}

void schedule(Program& prog, const std::vector<std::string>& define_names, const std::vector<std::string>& reserved) {
  Scheduler(prog, define_names, reserved).run();
}

}  // namespace mbsc::ir
