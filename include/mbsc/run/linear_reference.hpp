// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// What `mbsc linearize` and `mbsc eig` share: the model compiled with its linear_parts,
/// and the reference (parameters, inputs, state completed by assembly as for `mbsc run`).
#include <complex>
#include <iosfwd>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "mbsc/driver/commands.hpp"
#include "mbsc/model/model.hpp"
#include "mbsc/run/compiled_model.hpp"
#include "mbsc/runtime/linear_model.hpp"

namespace mbsc::run {

struct ReferenceRequest {
  std::string model_path;
  std::vector<std::string> lets;                 // --let NAME=VALUE: names the other values may use
  std::vector<std::string> sets, inits, inputs;  // --set, --init, --input NAME=EXPR
  double t = 0.0;
  /// Values that replace a --let, a parameter or an --init (a sweep's point, the
  /// second-order form's splitting, a steady-motion search): name -> value.
  std::map<std::string, double> overrides;
  std::string cache_dir;
  driver::WorkArgs work;
};

/// The reference: full state x (consistent), inputs u, parameters p.
struct LinearReference {
  std::vector<double> x, u, p;
};

/// Compiles (or loads from the cache) the complement form with linear_parts. A model
/// with Coulomb friction is refused (its linear model is not defined). Null on failure,
/// with the messages on `err` and `exit_code` set.
std::unique_ptr<CompiledModel> compile_for_linearization(const ReferenceRequest& req, const model::Model& m,
                                                         const std::vector<std::string>& sources, std::ostream& err,
                                                         int& exit_code);

/// The runtime's view of the compiled linear_parts.
runtime::LinearParts parts_of(const CompiledModel& c, const model::Model& m);

/// Parameters (defaults, --set), inputs (0, --input) and the state (the model's
/// `initial` values, --init, the rest assembled). --set values are expressions of the
/// --let names; --init and --input values of those and the parameters. False with `error` naming what is wrong
/// (an unknown name, a state the constraints do not allow, naming the constraint).
bool reference_state(const model::Model& m, const CompiledModel& c, const ReferenceRequest& req, LinearReference& ref,
                     std::string& error);

/// The error for --find unknowns and --steady rates whose numbers differ (each unknown
/// needs a rate that vanishes).
std::string find_steady_count_error(std::size_t unknowns, std::size_t rates);

/// A steady motion: the values of `unknowns` (coordinates or speeds of the state, --let
/// names or parameters) that make the rates of `steady` (state components) vanish, by
/// Newton's method from the request's own values (finite-difference Jacobian, each
/// iterate re-assembled). On success `req.overrides` holds the solution and `ref` the
/// reference there. False with `error` (sizes differ, an unknown name, no convergence
/// naming the largest residual rate).
bool find_steady(const model::Model& m, const CompiledModel& c, ReferenceRequest& req, const std::vector<std::string>& unknowns,
                 const std::vector<std::string>& steady, LinearReference& ref, std::string& error);

/// How fast the linear model in the components `sel` changes along the reference motion:
/// max |d Am/dt| / max |Am| (1/s), by central differences of the linear model at
/// x -+ h x' (t -+ h). Zero (to rounding) at an equilibrium or a steady motion of these
/// components; otherwise the eigenvalues of Am are those of a time-varying model frozen at
/// one instant and depend on the components chosen. -1 where it cannot be evaluated.
double model_rate(const runtime::LinearParts& parts, const runtime::ModelTable& t, double time, const LinearReference& ref,
                  const std::vector<int>& sel);

/// The warning a model_rate calls for ("" when the reference is steady in those
/// components): the model changes along the reference (its eigenvalues are those of a
/// frozen time-varying model), or the rate cannot be measured (the rhs fails there, as
/// where redundant constraints make its solve singular).
std::string model_rate_warning(double rate);

/// The default order in which the minimal state takes components (after --keep): the
/// coordinates that are not a body's position (angles, joint coordinates, a subsystem's
/// own), then positions (names ending in .x, .y, .z), then the model's independent speeds.
/// Positions last: a vehicle's lean and steer should be states, and its position, which
/// nothing depends on, then stays a cyclic component.
std::vector<int> default_component_order(const runtime::ModelTable& t);

/// The minimal state: the components named by --keep first (each must be taken: an
/// error names one the linearized constraints fix given those before it), then
/// default_component_order's. False with `error` for an unknown or refused name.
bool minimal_state(const runtime::LinearModel& lin, const runtime::ModelTable& t, const std::vector<std::string>& keep,
                   std::vector<int>& sel, std::string& error);

/// Eigenvalues of the n x n row-major matrix A, by real part then imaginary part.
std::vector<std::complex<double>> sorted_eigenvalues(const std::vector<double>& A, int n);

/// The same with the cyclic components (runtime::cyclic_components, returned in `cyclic`)
/// dropped first: their exact zeros come first, then the rest's eigenvalues sorted.
std::vector<std::complex<double>> eigenvalues_without_cyclic(const std::vector<double>& A, int n, std::vector<int>& cyclic);

}  // namespace mbsc::run
