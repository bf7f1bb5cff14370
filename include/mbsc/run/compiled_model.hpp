// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// A model compiled for `mbsc run`, `mbsc inverse` and `mbsc bench`: mbsc generates its
/// C++, compiles it with the system compiler into a shared object, caches that object,
/// and loads it as a runtime ModelTable.
///
/// The cache key hashes everything the object depends on: the text of the model and of
/// every file it includes, the formulation, the input expressions compiled in, the mbsc
/// version, and the compiler's command and version. The cache folder is `--cache-dir`,
/// else $MBSC_CACHE_DIR, else $XDG_CACHE_HOME/mbsc, else ~/.cache/mbsc. An entry is
/// written under a temporary name and renamed into place only when complete, so a run
/// that stops half-way leaves nothing a later run would load.
#include <iosfwd>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "mbsc/driver/commands.hpp"
#include "mbsc/model/model.hpp"
#include "mbsc/run/process.hpp"
#include "mbsc/runtime/model_table.hpp"

namespace mbsc::run {

/// The largest rhs_jacobian (operations of its generated code) a run compiles: about a
/// quarter of a minute of g++ -O2 on these machines (a 7-joint arm's is 10 000, a
/// 9-joint one's 118 000 and minutes; big straight-line functions are g++'s slow case).
inline constexpr long kRunJacobianMaxOps = 40000;

struct CompileRequest {
  std::string model_path;
  bool multipliers = false;  // --formulation multipliers
  bool minimal_state = false;  // --state minimal
  std::string solver = "auto";  // --solver auto|dense|sparse
  /// --input NAME=EXPR: the input's value as an expression of t and the parameters,
  /// compiled into the object (inputs not named here are 0).
  std::map<std::string, std::string> input_expressions;
  std::string cache_dir;  // "" = the default
  bool linear_parts = false;  // also linear_parts (mbsc linearize, mbsc eig)
  /// Also rhs_jacobian (the Newton matrices of the implicit integrators), unless its
  /// code would exceed kRunJacobianMaxOps operations (then it returns 4 and the run
  /// takes difference quotients); without, the table's pointer to it is null.
  bool rhs_jacobian = false;
  driver::WorkArgs work;
};

/// A loaded model: the table and the input function, valid while this object lives.
class CompiledModel {
 public:
  ~CompiledModel();
  CompiledModel(const CompiledModel&) = delete;
  CompiledModel& operator=(const CompiledModel&) = delete;

  const runtime::ModelTable& table() const { return table_; }
  /// linear_parts(t, x, w, p, OUT) when the request asked for it, else null.
  runtime::ModelTable::Fn linear_parts() const { return linear_parts_; }
  /// u(t) for the given parameters (the --input expressions; 0 for the others).
  int inputs(double t, const double* p, double* u) const { return inputs_(t, p, u); }
  /// Whether it came from the cache (no derivation, no compilation this time).
  bool from_cache() const { return from_cache_; }
  const std::string& folder() const { return folder_; }

 private:
  friend std::unique_ptr<CompiledModel> compile_model(const CompileRequest&, const model::Model&,
                                                      const std::vector<std::string>&, std::ostream&, int&);
  CompiledModel() = default;
  void* handle_ = nullptr;
  runtime::ModelTable table_{};
  int (*inputs_)(double, const double*, double*) = nullptr;
  runtime::ModelTable::Fn linear_parts_ = nullptr;
  bool from_cache_ = false;
  std::string folder_;
};

/// The C++ compiler mbsc runs: $MBSC_CXX, else $CXX, else c++.
std::string cxx_compiler();

/// Whether the compiler run `cc` succeeded; else the reason (the budget's time or memory
/// ran out, or the compiler's own messages) on `err`.
bool compiler_succeeded(const std::string& cxx, const ProcessResult& cc, const driver::WorkBudget& budget,
                        std::ostream& err);

/// Loads `m` (already read from req.model_path, with `sources` the files it read),
/// deriving, generating and compiling it first unless the cache has it. On failure the
/// messages are on `err`, `exit_code` is set (1: the user's model, expressions or
/// compiler; 2: ours) and the result is null.
std::unique_ptr<CompiledModel> compile_model(const CompileRequest& req, const model::Model& m,
                                             const std::vector<std::string>& sources, std::ostream& err, int& exit_code);

/// The cache folder a request uses.
std::string cache_folder(const std::string& requested);

/// C++ for an expression of t and the model's parameters (p[i]) given on the command
/// line; "" with `error` set when it does not parse or names something else.
std::string input_expression_cpp(const model::Model& m, const std::string& text, std::string& error);

}  // namespace mbsc::run
