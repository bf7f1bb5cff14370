// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// What `mbsc run`, `mbsc inverse` and `mbsc bench` share before integrating: the
/// parameter vector (defaults, then --set) and a consistent initial state (the model's
/// `initial` statements, then --init, the rest completed by assembly).
#include <array>
#include <iosfwd>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "mbsc/driver/commands.hpp"
#include "mbsc/model/model.hpp"
#include "mbsc/runtime/assemble.hpp"
#include "mbsc/runtime/model_table.hpp"

namespace mbsc::run {

/// Reads and builds the model (no derivation), under the work budget; diagnostics on
/// `err`; nullopt on errors. `sources` receives the files read.
std::optional<model::Model> read_model(const std::string& path, const driver::WorkArgs& work,
                                       std::vector<std::string>& sources, std::ostream& err);

/// "name=value" items of --set / --init, in order (a name given twice: the last wins).
/// False with `error` for a malformed item.
bool parse_assignments(const std::vector<std::string>& items, const std::string& flag,
                       std::map<std::string, double>& out, std::string& error);
/// The same with values that may be expressions of the names in `known` (and pi).
bool parse_assignments(const std::vector<std::string>& items, const std::string& flag,
                       std::map<std::string, double>& out, std::string& error, const std::map<std::string, double>& known);

/// The --set names are parameters of the model (or the Baumgarte gains with
/// `multipliers`), the --init names its coordinates and speeds: checked on the model
/// itself, before anything is compiled. False with `error` naming the first unknown one.
bool check_names(const model::Model& m, const std::map<std::string, double>& sets,
                 const std::map<std::string, double>& inits, bool multipliers, std::string& error);

/// "--input: the model has no input named 'NAME' (its inputs: a, b)" (or "it has no
/// inputs"): the one message for an --input naming no input of `m`.
std::string unknown_input_message(const model::Model& m, const std::string& name);

/// kParamDefaults with the --set values; the Baumgarte gains of the multipliers form are
/// parameters too (baumgarte_alpha, baumgarte_beta). False with `error` naming an
/// unknown parameter (and the closest known name).
bool parameter_values(const runtime::ModelTable& t, const std::map<std::string, double>& sets, std::vector<double>& p,
                      std::string& error);

struct InitialState {
  std::vector<double> x;            // consistent full state
  runtime::AssemblyResult assembly;  // how assembly went (near_singular is a warning)
  std::vector<std::string> given;   // the names fixed by `initial` statements and --init
  /// The unit quaternions that started off |e| = 1 and were divided by their norm before
  /// assembly (a quaternion's scale is no rotation): "e0, e1, e2, e3 (norm 0.5)".
  std::vector<std::string> normalized;
};

/// The state indices of every unit quaternion (model::rigid3d::unit_quaternion_names)
/// that the state `t` carries, e0 first: what `mbsc run` keeps at |e| = 1.
std::vector<std::array<int, 4>> unit_quaternion_indices(const model::Model& m, const runtime::ModelTable& t);

/// The initial state at t0 (of a full-state model): `initial` values of the model (evaluated with p), --init
/// values over them, every other coordinate guessed 0 and every other speed solved from
/// the velocity constraints (minimum norm). Each unit quaternion (a body's attitude, a
/// spherical joint's) starts at its values divided by their norm, or at the identity when
/// none of its entries is given. False with `error` for an unknown name, a given
/// quaternion that is all zero, or a state the constraints do not allow (naming the
/// constraint).
bool initial_state(const model::Model& m, const runtime::ModelTable& t, const std::vector<double>& p,
                   const std::vector<double>& u0, const std::map<std::string, double>& inits, double t0,
                   InitialState& out, std::string& error);

}  // namespace mbsc::run
