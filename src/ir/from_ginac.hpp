// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// GiNaC expression -> canonical DAG conversion (private to src/ir).
///
/// Define'd symbols are substituted by their value's node (converted lazily, the first
/// time a live expression reads them), so a Define whose symbol nothing live reads is
/// never converted. Solve results become Sym leaves; reading one marks its Solve as live.
#include <ginac/ginac.h>

#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "canonical_dag.hpp"
#include "mbsc/ir/function_spec.hpp"

namespace mbsc::ir {

/// Open-addressing map from a GiNaC node's address to its DAG node (lookup only, never
/// iterated; the addresses never influence the output).
class AddressMemo {
 public:
  AddressMemo() : keys_(1024, nullptr), values_(1024, -1) {}
  NodeId find(const void* key) const;
  void insert(const void* key, NodeId value);

 private:
  std::vector<const void*> keys_;
  std::vector<NodeId> values_;
  std::size_t size_ = 0;
};

class GinacConverter {
 public:
  /// Throws std::runtime_error when a symbol is bound or defined twice.
  GinacConverter(Dag& dag, const FunctionSpec& spec, const std::vector<Binding>& bindings);

  /// Converts one expression (memoised on GiNaC nodes). `context_step` is the index of the
  /// step that reads the expression (spec.steps.size() for outputs): reading a Solve result
  /// of that step or a later one throws.
  NodeId convert(const GiNaC::ex& e, int context_step);

  /// Whether a Define was read by converted expressions, and its value's node.
  bool define_live(int step) const { return define_state_[static_cast<std::size_t>(step)] == kDone; }
  /// Whether a converted expression refers to a named Define (by its leaf, Sym(step, -1)).
  bool define_referenced(int step) const { return named_ref_[static_cast<std::size_t>(step)] != 0; }
  NodeId define_node(int step) const { return define_node_[static_cast<std::size_t>(step)]; }
  /// Whether some converted expression reads one of a Solve's results.
  bool solve_live(int step) const { return solve_live_[static_cast<std::size_t>(step)] != 0; }

 private:
  enum : char { kUntouched = 0, kInProgress = 1, kDone = 2 };
  enum class SymKind { Binding, Define, SolveX };
  struct SymInfo {
    GiNaC::ex sym;
    SymKind kind;
    int step;  // Define / SolveX: step index
    int elem;  // SolveX: flat index i*k+j
    std::string text;  // Binding: C++ text
    bool invariant = false;  // Binding: same value in every call
    NodeId node = -1;  // Binding / SolveX: its leaf, once made
  };

  /// GiNaC classes the converter distinguishes.
  enum class GKind : std::uint8_t { Numeric, Add, Mul, Power, Symbol, Function, Constant, Other };

  GKind classify(const GiNaC::ex& e) const;
  SymInfo* find_symbol(const GiNaC::ex& e);
  NodeId leaf_or_start(const GiNaC::ex& e, GKind kind, bool& is_leaf, int& define_step, Func& func);
  NodeId build(GKind kind, Func func, const NodeId* kids, const std::uint8_t* classes, std::size_t nkids);
  bool is_sum_power(const GiNaC::ex& e) const;
  bool function_of(const GiNaC::ex& e, Func& f) const;

  Dag& dag_;
  const FunctionSpec& spec_;
  // Symbol table: entries, and an index keyed by GiNaC's hash of the symbol (a function of
  // its serial within this run) whose collisions are resolved with is_equal. Lookup only.
  std::vector<SymInfo> symbols_;
  std::unordered_map<unsigned, std::vector<int>> symbol_index_;
  std::vector<std::pair<unsigned, Func>> function_serials_;  // GiNaC function serial -> Func
  AddressMemo memo_;
  std::vector<GiNaC::ex> keep_alive_;  // memoised nodes stay alive so their addresses stay unique
  std::vector<char> define_state_;
  std::vector<NodeId> define_node_;
  std::vector<char> named_ref_;
  std::vector<char> solve_live_;
  // GiNaC's per-class registration records: comparing their addresses classifies a node
  // with one virtual call (typeid comparison or dynamic_cast cost far more).
  const GiNaC::registered_class_info* numeric_info_;
  const GiNaC::registered_class_info* add_info_;
  const GiNaC::registered_class_info* mul_info_;
  const GiNaC::registered_class_info* power_info_;
  const GiNaC::registered_class_info* symbol_info_;
  const GiNaC::registered_class_info* function_info_;
};

}  // namespace mbsc::ir
