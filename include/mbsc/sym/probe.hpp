// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// A fixed, generic numeric configuration of a model ("probe point"): every coordinate,
/// speed, input and t gets a deterministic pseudo-random value, parameters their
/// defaults. Used to decide ranks and independent sets; never emitted.
#include <ginac/ginac.h>

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "mbsc/model/model.hpp"

namespace mbsc::sym {

class Probe {
 public:
  Probe(const model::Model& model, const std::map<std::string, double>& param_values, unsigned seed = 12345);
  /// The model's reference configuration instead (docs/language.md, "Independent
  /// speeds"): parameters at their values (defaults or --freeze), every coordinate,
  /// speed, input and t at 0. Opaque symbols are not bound, so what reads a numeric
  /// solve does not evaluate there (NaN).
  static Probe reference(const model::Model& model, const std::map<std::string, double>& param_values);
  /// A given configuration: coordinates q (model order) and speeds u (entries they leave
  /// out at 0), t and inputs at 0, parameters at their values (the assembled initial
  /// state, sym/manifold_points.hpp; `reference` is this with q and u empty).
  static Probe configuration(const model::Model& model, const std::map<std::string, double>& param_values,
                             const std::vector<double>& q, const std::vector<double>& u);
  /// Binds an opaque symbol (result of a numeric solve) to its value at the probe point.
  /// A value that is not finite (an overflow at the probe) leaves it unbound: what reads
  /// it does not evaluate (NaN), as GiNaC has no number for a NaN (CLN throws).
  void bind(const GiNaC::symbol& s, double v) {
    if (std::isfinite(v)) values_[s] = v;
    else values_.erase(s);
  }
  /// Value of e at the probe point; NaN when it does not evaluate to a real number.
  double eval(const GiNaC::ex& e) const;
  /// The same in double precision only, without GiNaC's evaluation for what the double
  /// walk does not know (NaN there): for points that may be anywhere, such as Newton's
  /// iterates, where GiNaC can meet a division by zero inside its constructors, throw and
  /// leak the half-built object.
  double eval_double(const GiNaC::ex& e) const;

 private:
  Probe() = default;
  void bind_parameters(const model::Model& model, const std::map<std::string, double>& param_values);
  void bind_kinematic_names(const model::Model& model);
  /// Every spherical joint's quaternion divided by its norm (see the definition).
  void unit_quaternions(const model::Model& model);
  GiNaC::exmap values_;
};

/// True when e depends on no state (t, q0, q1, q1dot, input) and no opaque symbol,
/// i.e. it is built from numbers, parameters and component formals only.
bool is_state_free(const GiNaC::ex& e, const model::Model& model);

}  // namespace mbsc::sym
