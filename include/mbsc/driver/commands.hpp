// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The CLI subcommands. Each returns the process exit code: 0 ok, 1 user error
/// (diagnostics printed to stderr), 2 internal error.
#include <functional>
#include <optional>
#include <iosfwd>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "mbsc/driver/output_folder.hpp"
#include "mbsc/driver/work_monitor.hpp"

namespace mbsc::model {
struct Model;
}
namespace mbsc::emit {
struct GeneratedModel;
struct GeneratedFiles;
}  // namespace mbsc::emit

namespace mbsc::driver {

/// Options every command takes: the budgets of the symbolic work and the progress line.
struct WorkArgs {
  WorkBudget budget;
  ProgressMode progress = ProgressMode::Auto;
  bool quiet = false;  // --quiet: no progress line, and generate says nothing on success
};

struct CheckArgs {
  std::string model;
  std::map<std::string, double> frozen;  // --freeze: check the model as it would be generated
  WorkArgs work;
};
int run_check(const CheckArgs& a, std::ostream& out, std::ostream& err);

struct PrintArgs {
  std::string model;
  std::string node;                 // "" = root; a dotted subsystem name
  std::vector<std::string> what;    // eom M h invariants rates A B C S f fbar (empty: a default set)
  bool what_given = false;          // --what was on the command line (then it may not be empty)
  bool latex = false;
  bool expand = false;              // --expand: M, h (and every item) in closed form
  bool standalone = false;          // --standalone: a whole LaTeX document (implies latex)
  bool stats = false;
  std::map<std::string, double> frozen;
  std::set<std::string> functions;  // for --stats with --outputs
  bool minimal_state = false;       // for --stats with --state minimal
  std::string solver = "auto";      // for --stats: --solver auto|dense|sparse
  WorkArgs work;
};
int run_print(const PrintArgs& a, std::ostream& out, std::ostream& err);

struct GenerateArgs {
  std::string model;
  std::string out_dir;              // files go to out_dir/<model name>/
  std::set<std::string> functions;  // --outputs
  std::map<std::string, double> frozen;
  std::string name;                 // --name (default: the model's name)
  bool minimal_state = false;       // --state minimal
  bool multipliers = false;         // --formulation multipliers
  std::string solver = "auto";      // --solver auto|dense|sparse (GenerateOptions::solver)
  std::string mass_matrix = "auto";  // --mass-matrix auto|symbolic|factors (GenerateOptions::mass_matrix)
  bool force = false;               // --force: write into an OUT/<name> mbsc did not write
  std::string depfile;              // --depfile: also write this make-style depfile (driver/depfile.hpp)
  bool python = false;              // --python: also NAME.py (ctypes over the extern "C" functions)
  /// --batch: functions that also get batched entry points (docs/batched.md); unset: rhs,
  /// unless --outputs names the functions; {"none"} or empty: none.
  std::optional<std::vector<std::string>> batch;
  bool linear_parts = false;        // also linear_parts (what `mbsc linearize` compiles)
  bool derivatives = false;         // --derivatives: also rhs_jacobian, inverse_dynamics_jacobian
  bool rhs_jacobian = false;        // also rhs_jacobian alone, capped (GenerateOptions::rhs_jacobian)
  long rhs_jacobian_max_ops = 0;
  WorkArgs work;
  /// What run_generate made, for `extra_outputs`.
  struct Made {
    const model::Model& model;
    const std::vector<std::string>& sources;  // the model's file and those it includes
    const emit::GeneratedModel& generated;
    const emit::GeneratedFiles& files;
  };
  /// Called once the C++ is emitted, before anything is written: adds files to write
  /// with the others, all or nothing (generate --fmi adds NAME.fmu: src/fmu). Returns 0,
  /// or the exit code with its messages on `err`.
  std::function<int(const Made&, std::vector<OutputFile>&, std::ostream& err)> extra_outputs;
};
int run_generate(const GenerateArgs& a, std::ostream& out, std::ostream& err);

/// Parses "name=value" (for --freeze). Returns false, with `why`, on malformed text
/// ("expects name=value with a finite number": nan, inf, hex) and on a number a double
/// does not hold (the model language's message for such a literal: 1e400, 1e-320).
bool parse_assignment(const std::string& text, std::string& name, double& value, std::string& why);

/// The items `print --what` knows, in the order the help lists them.
const std::vector<std::string>& print_items();

}  // namespace mbsc::driver
