// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The whole compiler as one call per stage group: model file -> Model -> Eom ->
/// functions -> files. Only the CLI touches the file system for output.
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/driver/residual_jacobian.hpp"
#include "mbsc/emit/generated_model.hpp"
#include "mbsc/ir/function_spec.hpp"
#include "mbsc/model/model.hpp"
#include "mbsc/sym/eom.hpp"
#include "mbsc/sym/kkt_elimination.hpp"
#include "mbsc/sym/minimal_state.hpp"

namespace mbsc::driver {

/// Every function generate can emit, in emission order.
const std::vector<std::string>& all_function_names();

/// "--outputs: unknown function 'enrgy' (did you mean 'energy'?) (known: rhs, ...)" for
/// the first name in `functions` that generate does not know, or "" when all are known.
std::string unknown_function_message(const std::set<std::string>& functions);

/// How rhs solves for the accelerations (docs/formulation.md, "O(N) right-hand side").
enum class Solver {
  Auto,    // sparse where the model's bodies form a tree and it is cheaper, else dense
  Dense,   // the reduced M z' = h by Cholesky (complement) / the Schur complement or KKT LU (multipliers)
  Sparse,  // block elimination of the sparse system over all speeds, in a tree order
};

/// How the mass_matrix output is formed.
enum class MassMatrixForm {
  Auto,      // Factors when the product C^T My C or M itself is big (kFactorFormMinWork)
  Symbolic,  // every entry of M = C^T My C formed symbolically, lowered with CSE
  Factors,   // the nonzeros of C and My, and a loop forming C^T My C in the generated code
};

/// Above this many products (upper triangle of C^T My C, what the loop does) or entries
/// of M (ndof^2: each formed, finalized and lowered in the symbolic form), auto forms
/// mass_matrix from its factors: a chain of about 40 links, 150 free particles and
/// bigger. No shipped model comes near it, so their generated code keeps the symbolic form.
inline constexpr long kFactorFormMinWork = 20000;

/// "auto", "symbolic" or "factors" (the CLI has checked the name).
MassMatrixForm mass_matrix_form_named(const std::string& name);

/// The products the loop of the factor form does for M = C^T My C (upper triangle).
long congruence_products(const GiNaC::matrix& C, const GiNaC::matrix& My);

/// "auto", "dense" or "sparse" (the CLI has checked the name).
Solver solver_named(const std::string& name);

struct GenerateOptions {
  std::set<std::string> functions;        // empty: all that the model defines
  std::map<std::string, double> frozen;   // --freeze name=value
  std::string name;                       // --name: C++ namespace and file stem (default: the model's name)
  bool minimal_state = false;             // --state minimal: x = (kept q0, z), see sym/minimal_state.hpp
  bool multipliers = false;               // --formulation multipliers (sym/multipliers.hpp)
  Solver solver = Solver::Auto;           // --solver
  MassMatrixForm mass_matrix = MassMatrixForm::Auto;  // --mass-matrix
  /// Also linear_parts (driver/linear_parts.hpp), which no default set includes; also
  /// asked for by naming it in `functions`.
  bool linear_parts = false;
  /// Also rhs_jacobian and inverse_dynamics_jacobian (docs/derivatives.md), which no
  /// default set includes (a long chain's are tens of megabytes of code); also asked
  /// for by naming them in `functions`.
  bool derivatives = false;
  /// Also rhs_jacobian alone (what `mbsc run` compiles for its Newton methods), unless
  /// its lowered code exceeds `rhs_jacobian_max_ops` operations (0: no limit): then it is
  /// written returning 4 (not defined), and the run takes difference quotients.
  bool rhs_jacobian = false;
  long rhs_jacobian_max_ops = 0;
};

/// The Baumgarte gains of the multipliers formulation: symbols bound to the last two p[]
/// entries (kParamNames "baumgarte_alpha", "baumgarte_beta").
struct BaumgarteGains {
  GiNaC::symbol alpha{"baumgarte_alpha"}, beta{"baumgarte_beta"};
  static constexpr double kDefault = 10.0;  // 1/s: critically damped, f ~ exp(-10 t)
};

/// A model with Coulomb friction (model::Model::frictions): every function that reads a
/// friction force gets the steps that solve the friction law for it (friction_closure.cpp);
/// inverse_dynamics becomes undefined. `multipliers`: the reactions carry Baumgarte terms.
/// `closure` holds those steps once built, so that a second call (for functions added
/// later) reuses them instead of deriving the closure again; it starts empty.
void close_friction(const model::Model& m, const sym::Eom& eom, bool multipliers, const BaumgarteGains& gains,
                    std::vector<ir::FunctionSpec>& specs, std::optional<std::vector<ir::Step>>& closure);

/// Prepends the model's kinematic names (named body rotations, Model::kinematic_names) as
/// Defines to every spec that does not define them yet and is defined, so that a spec
/// evaluated on its own (or emitted) never reads an undefined name.
void define_kinematic_names(const model::Model& m, const sym::Eom& eom, std::vector<ir::FunctionSpec>& specs);

/// rhs, multipliers and reaction_forces of the multipliers formulation.
std::vector<ir::FunctionSpec> multiplier_specs(const model::Model& m, const sym::Eom& eom, const GenerateOptions& opt,
                                               const BaumgarteGains& gains, Diagnostics& diags);

/// The O(N) solve of the accelerations (sym/kkt_elimination.hpp) with constraint
/// right-hand sides `c` (A q1' = c), prepared for emission: steps that define every
/// speed's rate and every lambda. nullopt with `why` when the model has no such order.
/// A loop is eliminated speeds first when every speed block is definite by itself
/// (sym::eliminate_kkt; KktElimination::regular() says whether auto may take it).
std::optional<sym::KktElimination> sparse_solve_steps(const model::Model& m, const sym::Eom& eom,
                                                      const sym::KktSystem& sys, const std::vector<GiNaC::ex>& c,
                                                      const std::vector<GiNaC::symbol>& lambda, std::string& why);

/// The accelerations: the articulated-body recursion where the model is a tree of bodies
/// placed by joint coordinates (sym/tree_recursion.hpp: one pivot per joint, the
/// multipliers only `with_multipliers`, from each body's own equations), else
/// sparse_solve_steps. Its steps define every speed's rate, and every lambda when
/// `with_multipliers` (or when the block elimination made them).
std::optional<sym::KktElimination> rhs_solve_steps(const model::Model& m, const sym::Eom& eom, const sym::KktSystem& sys,
                                                   const std::vector<GiNaC::ex>& c, const std::vector<GiNaC::symbol>& lambda,
                                                   bool with_multipliers, std::string& why);

/// The sparse steps with a speeds-first loop's constraint pivots reported to `power` in
/// `conditioning` (ir::Solve::report_power: 1/3 in the complement form, 2/3 in the
/// multipliers form); any other elimination's steps as they are.
std::vector<ir::Step> sparse_steps_reported(const sym::KktElimination& sparse, const GiNaC::numeric& power);

/// Whether rhs uses the sparse steps: --solver sparse or dense decides; auto takes them
/// when their pivots are regular wherever the dense forms' are (a tree of bodies, or a
/// loop eliminated speeds first: KktElimination::regular) and they cost less than the
/// dense rhs (both lowered and counted, solve flops weighted; above 64 speeds the dense
/// cost, cubic, is not built).
/// `dense` builds the dense rhs when it is needed.
bool prefer_sparse(const model::Model& m, const GenerateOptions& opt, const sym::KktElimination& sparse,
                   const ir::FunctionSpec& sparse_rhs, const std::function<ir::FunctionSpec()>& dense,
                   const std::vector<ir::Binding>& binds);

/// Rows redundant on the mechanism (sym::Eom::redundant_on_manifold) leave the tree
/// orders' pivots singular wherever the model moves: such a model takes the dense
/// solves (least squares, minimum norm). False, with an error, for --solver sparse.
bool redundancy_allows_sparse(const model::Model& m, const sym::Eom& eom, const GenerateOptions& opt, Diagnostics& diags);

/// Parses and builds a model file (includes resolved). nullopt on error.
/// `overrides` (the --freeze values) also set the parameters `for` loops and indices use,
/// and stand in for the defaults where values are checked. The model's name must be
/// usable as a C++ namespace unless `generated_name` (--name) replaces it. `sources`
/// (when given) receives the model file and every file it includes (ast::File::sources).
std::optional<model::Model> load_model(const std::string& path, Diagnostics& diags,
                                      const std::map<std::string, double>& overrides = {},
                                      const std::string& generated_name = "",
                                      std::vector<std::string>* sources = nullptr);

/// False (reported at `model NAME`) when the model's name cannot name the generated
/// C++ namespace and files, unless `generated_name` (--name) replaces it.
bool check_model_name(const model::Model& m, const std::string& generated_name, Diagnostics& diags);

/// Expression with component formals and frozen parameters substituted.
GiNaC::ex finalize(const model::Model& m, const sym::Eom& eom, const GiNaC::ex& e);

/// The FunctionSpecs of the requested functions and their input bindings.
/// With `minimal` (--state minimal) every function first rebuilds the coordinates and
/// speeds that are not in the state.
/// With `residual`, an rhs made by a tree recursion with no loop also fills it (the
/// implicit form of rhs_jacobian, driver/residual_jacobian.hpp); it stays empty otherwise.
std::vector<ir::FunctionSpec> function_specs(const model::Model& m, const sym::Eom& eom, const GenerateOptions& opt,
                                             Diagnostics& diags, const sym::MinimalState* minimal = nullptr,
                                             std::optional<TreeResidual>* residual = nullptr);
std::vector<ir::Binding> bindings(const model::Model& m, const sym::Eom& eom, const sym::MinimalState* minimal = nullptr);

/// The `conditioning` function of an rhs: the rcond of every block the rhs solves that
/// is `reported` (the dependent blocks with their gains, the reduced mass matrix by the
/// Cholesky test its solve makes), one output per block in solve order.
ir::FunctionSpec conditioning_spec(const ir::FunctionSpec& rhs, const std::string& name);
/// The labels of those blocks (kBlockNames).
std::vector<std::string> conditioning_labels(const ir::FunctionSpec& conditioning);

/// What run-time re-selection adds to a generated model (src/driver/partition_specs.cpp).
struct PartitionSpecs {
  std::vector<ir::FunctionSpec> specs;     // rhs_alt<k>, conditioning, conditioning_alt<k>
  emit::PartitionTable table;              // which function serves each partition
  std::vector<std::string> names;          // kPartitionNames: each partition's independent speeds
  std::vector<std::string> block_labels;   // kBlockNames: partition 0's LU-solved blocks
};
/// Derives partitions 1 .. npart-1 (each node's k-th `alternative`) and builds their rhs
/// and every partition's conditioning; `rhs0` is partition 0's rhs. nullopt on error.
std::optional<PartitionSpecs> partition_specs(const model::Model& m, const sym::Eom& eom, const GenerateOptions& opt,
                                             int npart, const ir::FunctionSpec& rhs0, Diagnostics& diags);

/// A dense Jacobian in compressed-row form (src/driver/sparse_jacobians.cpp): the
/// function writing its entries that are not identically zero, row by row, and the
/// pattern (row_ptr: rows + 1 offsets; col_idx: the column of each value).
struct SparseJacobian {
  ir::FunctionSpec values;  // <dense name>_values, out_shape <prefix>Nnz
  std::string prefix;       // "kConstraintJacobian": constants <prefix>Nnz, <prefix>RowPtr, <prefix>ColIdx
  std::vector<long> row_ptr, col_idx;
};
/// The CSR twin of `dense` (rows x cols outputs, row-major).
SparseJacobian sparse_jacobian(const ir::FunctionSpec& dense, long rows, long cols, const std::string& prefix);
/// For constraint_jacobian and position_jacobian among `specs`: their patterns, and the
/// _values functions the options ask for inserted after them (a dense Jacobian that was
/// built only for its twin is replaced by it).
std::vector<SparseJacobian> add_sparse_jacobians(const model::Model& m, const GenerateOptions& opt,
                                                 std::vector<ir::FunctionSpec>& specs);

/// Model + Eom -> everything the emitter prints.
std::optional<emit::GeneratedModel> generate(const model::Model& m, const sym::Eom& eom, const GenerateOptions& opt,
                                             Diagnostics& diags);

/// 64-bit FNV-1a of a text, as 16 hex digits (banner hash of the model source).
std::string text_hash(const std::string& text);

}  // namespace mbsc::driver
