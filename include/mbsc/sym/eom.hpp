// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The modular method of thesis Table 4.1, leaves to root, at order sigma = 2
/// (docs/formulation.md). Letters as in docs/notation.md:
///   q0 coordinates, q1 quasi-velocities (speeds), q1dot their rates,
///   y  = (own q1dot, children's independent q1dot)      (the R-reduced variables)
///   B  = d(order-2 invariants)/dy,  b = invariants at y = 0
///   C  = orthogonal complement of B (B*C == 0), partitioned on the independent set #
///   f  = (f_own, fbar_children) = -My y' + hy,  fbar = C^T f = -M z' + h
/// Blocks of B whose inverse would be a configuration-dependent symbolic inverse are
/// not inverted here: they become numeric LU solves in the generated code (ir::Solve),
/// and their results appear in later expressions as opaque symbols.
#include <ginac/ginac.h>

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/ir/function_spec.hpp"
#include "mbsc/model/model.hpp"

namespace mbsc::sym {

/// A matrix formed on first use. The root's reduced mass matrix M = C^T My C is one:
/// the O(N) rhs never reads it, and for a chain it is dense with entries of O(N) terms
/// each (cubic work), so a model that asks only for rhs should not pay for it. Copies
/// share the one result.
class DeferredMatrix {
 public:
  DeferredMatrix() = default;
  /// rows x cols, formed by `form` on first read.
  DeferredMatrix(unsigned rows, unsigned cols, std::function<GiNaC::matrix()> form) : state_(std::make_shared<State>()) {
    state_->rows = rows;
    state_->cols = cols;
    state_->form = std::move(form);
  }
  explicit DeferredMatrix(std::function<GiNaC::matrix()> form) : state_(std::make_shared<State>()) {
    state_->form = std::move(form);
    state_->sized = false;
  }
  /// A matrix formed already.
  explicit DeferredMatrix(GiNaC::matrix value) : state_(std::make_shared<State>()) {
    state_->rows = value.rows();
    state_->cols = value.cols();
    state_->value = std::move(value);
  }
  const GiNaC::ex& operator()(unsigned i, unsigned j) const { return get()(i, j); }
  const GiNaC::matrix& get() const {
    if (!state_) state_ = std::make_shared<State>();
    if (!state_->value) state_->value = state_->form ? state_->form() : GiNaC::matrix(0, 0);
    return *state_->value;
  }
  bool formed() const { return state_ && state_->value.has_value(); }
  unsigned rows() const { return state_ && state_->sized ? state_->rows : get().rows(); }
  unsigned cols() const { return state_ && state_->sized ? state_->cols : get().cols(); }

 private:
  struct State {
    std::function<GiNaC::matrix()> form;
    std::optional<GiNaC::matrix> value;
    unsigned rows = 0, cols = 0;
    bool sized = true;
  };
  mutable std::shared_ptr<State> state_;
};

/// What was derived at one node of the tree.
struct NodeResult {
  int node = 0;
  std::vector<int> y;            // speeds whose rates form y (own speeds, then children's independent ones)
  std::vector<int> rows;         // constraint indices, order-2 rows of B
  std::vector<int> redundant;    // constraints redundant on the mechanism (kept: least squares)
  GiNaC::matrix B;               // rows x ny (may contain opaque symbols of children's solves)
  GiNaC::matrix b;               // rows x 1
  std::vector<int> independent;  // speeds chosen as # (subset of y), size ndof
  std::vector<int> dependent;    // speeds eliminated here (⋆)
  int rank = 0;
  bool symbolic_complement = true;   // false: B* is solved numerically (see `solve`)
  int numeric_core = 0;              // size of the block left to the numeric solve (0: none)
  /// ny x ndof, B*C == 0. Formed on first read at a triangular root: the rhs of a chain
  /// reads the rate steps instead, and C's entries there are sums over the whole chain.
  DeferredMatrix C;
  GiNaC::matrix e;               // ny x 1: y' = C z' + e (e is zero on the independent rows)
  GiNaC::matrix My, hy;          // f over y: f = -My y' + hy (My block-diagonal: own block, children's M)
  GiNaC::matrix M, h;            // fbar = C^T f = -M z' + h over the independent speeds z (root: M in Eom::M)
  /// q1dot of each dependent speed in terms of the node's y# (dependent -> expression).
  std::map<int, GiNaC::ex> dependent_rates;
  /// Triangular partitions only: the dependent rates in substitution order, each in terms
  /// of y# and the rates before it (what the generated code evaluates; linear in size).
  std::vector<std::pair<int, GiNaC::ex>> rate_steps;
  std::vector<int> step_rows;    // the row of B each rate step solves (aligned with rate_steps)
  std::vector<ir::Solve> solves;  // numeric solves this node adds (0 or 1)
  /// Triangular nodes: e row by row (named e_<speed>), then the transposed steps that
  /// form h (named r_<speed>), in evaluation order.
  std::vector<ir::Define> named_defines;
  bool from_component_cache = false;
};

struct Options {
  std::map<std::string, double> frozen;  // parameter name -> value folded into the code
  bool reuse_components = true;           // derive a component once, instantiate by substitution
  /// Which declared independent set to use: 0 = each node's `independent` (or automatic),
  /// k > 0 = each node's k-th `alternative` where it has one (model::Model::partition_count).
  int partition = 0;
};

/// The reduced mass matrix at the model's reference configuration, for a model with
/// massless bodies (sym/massless_check.hpp).
enum class MassAtReference {
  NotChecked,         // no massless body, or M not positive definite generically
  NotEvaluated,       // M does not evaluate there (a dependent block singular there)
  PositiveDefinite,
  SingularMassless,   // singular, massless bodies move in the motion without inertia (warned)
  SingularOtherwise,  // singular, but no massless body moves in that motion
};

/// Derived equations of a whole model.
struct Eom {
  const model::Model* model = nullptr;
  Options options;
  std::vector<NodeResult> nodes;   // aligned with model.nodes (post-order)
  std::vector<int> independent;    // root's independent speeds (size ndof)
  DeferredMatrix M;                // ndof x ndof, M(q0, q1, t) with fbar_root = -M z' + h (formed when read)
  GiNaC::matrix h;                 // ndof x 1
  std::vector<ir::Solve> solves;   // all numeric solves of the tree, leaves to root
  /// Everything h needs before M z' = h, leaves to root and in derivation order: the
  /// numeric solves and the named e_/r_ variables (what rhs, mass_matrix and forcing emit first).
  std::vector<ir::Step> pre_steps;
  std::vector<ir::Define> top_down;  // dependent q1dot, root to leaves
  GiNaC::ex kinetic, potential;    // energy terms (valid when has_energy)
  bool has_energy = false;
  bool mass_matrix_spd = true;     // M positive definite at the probe point: solved by Cholesky
  std::vector<std::string> massless;  // bodies with mass or inertia 0 ("rod (mass 0, inertia 0)"), for `check`
  MassAtReference mass_at_reference = MassAtReference::NotChecked;
  std::map<std::string, double> param_values;  // defaults, with frozen values
  /// Why the initial state was not assembled at generation time (sym/manifold_points.hpp);
  /// empty when it was: then ranks are measured there and the automatic independent
  /// sets checked there.
  std::string start_missing;
  /// Constraints whose rows are redundant on the mechanism (independent at a generic
  /// point, dependent wherever the constraints hold): each node solves its dependent
  /// block in the least-squares sense, the multipliers form for minimum-norm multipliers.
  std::vector<int> redundant_on_manifold;
  std::vector<int> free_params;    // parameters left in p[] (not frozen)
  int ndof() const { return static_cast<int>(independent.size()); }
};

/// Runs the recursive algorithm. Reports rank problems, redundant or inconsistent
/// constraints and unusable independent sets at the constraint or `independent`
/// statement. Returns nullopt on error.
std::optional<Eom> derive(const model::Model& model, const Options& options, Diagnostics& diags);

/// d/dt of an expression in (t, q0, q1) along the model's kinematics, with q1dot symbols.
GiNaC::ex time_derivative(const model::Model& model, const GiNaC::ex& e);

/// Order-1 form of every constraint (position constraints differentiated once), in model order.
std::vector<GiNaC::ex> velocity_residuals(const model::Model& model);

}  // namespace mbsc::sym
