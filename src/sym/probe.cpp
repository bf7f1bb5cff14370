// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/sym/probe.hpp"
#include "mbsc/sym/symbol_set.hpp"

#include "mbsc/model/exact_guard.hpp"
#include "mbsc/model/value_bound.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <random>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

namespace mbsc::sym {

Probe::Probe(const model::Model& model, const std::map<std::string, double>& param_values, unsigned seed) {
  // mt19937's sequence is fixed by the standard, so the probe point is the same on every run.
  std::mt19937 rng(seed);
  auto next = [&rng](double lo, double hi) { return lo + (hi - lo) * (static_cast<double>(rng()) / 4294967296.0); };
  values_[model.time] = next(0.1, 1.0);
  for (const auto& q : model.coords) values_[q.sym] = next(-1.3, 1.3);
  for (const auto& u : model.speeds) values_[u.sym] = next(-1.3, 1.3);
  for (const auto& in : model.inputs) values_[in.sym] = next(-1.0, 1.0);
  // A friction force is given like an input until the generated code closes its law.
  for (const auto& f : model.frictions) values_[f.force] = next(-1.0, 1.0);
  unit_quaternions(model);
  bind_parameters(model, param_values);
  bind_kinematic_names(model);
}

void Probe::unit_quaternions(const model::Model& model) {
  // A spherical joint's quaternion scales its child's rotation by |e|^2, and a chain of
  // such joints multiplies those factors: unnormalized draws would scale the k-th body
  // of a chain by a k-fold product (the 32-link chain's last joint row looked redundant).
  // So each joint quaternion is drawn on |e| = 1. A body's own quaternion keeps its
  // draw: its homogeneous matrix is exact at any norm and scales that body alone, and
  // the independent sets chosen at this point for such models stay as they were.
  for (const auto& node : model.nodes) {
    const auto& e = node.rigid3d.joint_quaternion_coords;
    if (e.size() != 4) continue;
    std::vector<double> v;
    double n2 = 0.0;
    for (int c : e) {
      v.push_back(GiNaC::ex_to<GiNaC::numeric>(values_[model.coords[static_cast<std::size_t>(c)].sym]).to_double());
      n2 += v.back() * v.back();
    }
    if (!(n2 > 0.0)) continue;
    for (std::size_t k = 0; k < 4; ++k) values_[model.coords[static_cast<std::size_t>(e[k])].sym] = v[k] / std::sqrt(n2);
  }
}

Probe Probe::reference(const model::Model& model, const std::map<std::string, double>& param_values) {
  return configuration(model, param_values, {}, {});
}

Probe Probe::configuration(const model::Model& model, const std::map<std::string, double>& param_values,
                           const std::vector<double>& q, const std::vector<double>& u) {
  Probe p;  // what q and u leave out is 0, as are t and the inputs
  p.values_[model.time] = 0.0;
  for (std::size_t i = 0; i < model.coords.size(); ++i) p.values_[model.coords[i].sym] = i < q.size() ? q[i] : 0.0;
  for (std::size_t i = 0; i < model.speeds.size(); ++i) p.values_[model.speeds[i].sym] = i < u.size() ? u[i] : 0.0;
  for (const auto& in : model.inputs) p.values_[in.sym] = 0.0;
  for (const auto& f : model.frictions) p.values_[f.force] = 0.0;
  p.bind_parameters(model, param_values);
  p.bind_kinematic_names(model);
  return p;
}

void Probe::bind_kinematic_names(const model::Model& model) {
  // In definition order: each value reads only bound symbols and earlier names.
  for (const auto& k : model.kinematic_names) {
    const double v = eval(k.value);
    if (std::isfinite(v)) values_[k.sym] = v;
  }
}

void Probe::bind_parameters(const model::Model& model, const std::map<std::string, double>& param_values) {
  for (size_t i = 0; i < model.params.size(); ++i) {
    auto it = param_values.find(model.params[i].name);
    values_[model.params[i].sym] = it != param_values.end() ? it->second : model.param_defaults[i];
  }
  // Formals may refer to parameters: bind them to their argument values.
  for (int pass = 0; pass < 4; ++pass)
    for (const auto& [name, f] : model.formals) values_[f.sym] = f.value.subs(values_);
}

namespace {

/// e in double precision at `values`, walking the expression without building new ones:
/// false when it meets something it does not know (then GiNaC evaluates). Used to see a
/// division by zero before GiNaC does: GiNaC throws from inside its constructors there
/// and leaks the half-built object (LeakSanitizer sees it at the reference configuration
/// of a quaternion body, where every entry of e vanishes).
///
/// Expressions are DAGs (subexpressions shared after substitutions), so every node's
/// value is remembered by address for the duration of one walk (a tree walk would be
/// exponential in the depth of the sharing); op(i) of a sum or product may build a
/// temporary, so every remembered node is kept alive until the walk ends.
class DoubleWalk {
 public:
  // Sums and products are formed in an order of the operands' values (by magnitude, then
  // value), not in GiNaC's run-dependent order of the operands: rounding depends on the
  // order, and these values decide pivots, ranks and partitions, where a tie could fall
  // either way from run to run (docs/backend.md "Determinism").
  // Of the equal magnitudes in a sum, opposite values cancel exactly and the rest are
  // added, so that the sum of negated terms is exactly the negated sum (GiNaC holds a
  // sum with either sign, as its term order makes it).
  static bool by_magnitude(double a, double b) { return std::fabs(a) != std::fabs(b) ? std::fabs(a) < std::fabs(b) : a < b; }

  static double ordered_sum(std::vector<double>& v) {
    double acc = 0.0;
    for (double x : v) acc += x;
    if (!std::isfinite(acc)) return acc;  // not finite in any order
    std::sort(v.begin(), v.end(), by_magnitude);
    acc = 0.0;
    for (std::size_t i = 0; i < v.size();) {
      const double magnitude = std::fabs(v[i]);
      int balance = 0;  // positive minus negative values of this magnitude
      for (; i < v.size() && std::fabs(v[i]) == magnitude; ++i) balance += v[i] > 0.0 ? 1 : v[i] < 0.0 ? -1 : 0;
      for (int k = 0; k < std::abs(balance); ++k) acc += balance > 0 ? magnitude : -magnitude;
    }
    return acc;
  }

  static double ordered_product(std::vector<double>& v) {
    double acc = 1.0;
    for (double x : v) acc *= x;
    if (!std::isfinite(acc)) return acc;  // not finite in any order
    std::sort(v.begin(), v.end(), by_magnitude);
    acc = 1.0;
    for (double x : v) acc *= x;
    return acc;
  }

  explicit DoubleWalk(const GiNaC::exmap& values) : values_(values) {}

  bool value(const GiNaC::ex& e, double& out) {
    using namespace GiNaC;
    if (is_a<numeric>(e) || is_a<symbol>(e)) return leaf(e, out);
    const basic* key = &ex_to<basic>(e);
    if (const auto it = seen_.find(key); it != seen_.end()) {
      out = it->second.second;
      return it->second.first;
    }
    const bool known = inner(e, out);
    seen_.emplace(key, std::make_pair(known, out));
    pinned_.push_back(e);  // alive while remembered: a freed temporary's address is reused
    return known;
  }

 private:
  bool leaf(const GiNaC::ex& e, double& out) const {
    using namespace GiNaC;
    const ex* n = &e;
    if (is_a<symbol>(e)) {
      const auto it = values_.find(e);
      if (it == values_.end()) return false;
      n = &it->second;
    }
    if (!is_a<numeric>(*n) || !ex_to<numeric>(*n).is_real()) return false;
    out = ex_to<numeric>(*n).to_double();
    return true;
  }

  bool inner(const GiNaC::ex& e, double& out) {
    using namespace GiNaC;
    if (is_a<add>(e) || is_a<mul>(e)) {
      std::vector<double> v(e.nops());
      for (std::size_t i = 0; i < e.nops(); ++i)
        if (!value(e.op(i), v[i])) return false;
      out = is_a<add>(e) ? ordered_sum(v) : ordered_product(v);
      return true;
    }
    if (is_a<power>(e)) {
      double b = 0.0, x = 0.0;
      if (!value(e.op(0), b) || !value(e.op(1), x)) return false;
      out = std::pow(b, x);
      return true;
    }
    if (is_a<function>(e)) {  // evaluated as the generated code calls it
      std::vector<double> args(e.nops());
      for (std::size_t i = 0; i < e.nops(); ++i)
        if (!value(e.op(i), args[i])) return false;
      return model::function_value(ex_to<function>(e).get_name(), args, out);
    }
    return false;
  }

  const GiNaC::exmap& values_;
  std::unordered_map<const GiNaC::basic*, std::pair<bool, double>> seen_;
  std::vector<GiNaC::ex> pinned_;
};

}  // namespace

double Probe::eval_double(const GiNaC::ex& e) const {
  if (GiNaC::is_a<GiNaC::numeric>(e) && GiNaC::ex_to<GiNaC::numeric>(e).is_zero()) return 0.0;
  if (double d = 0.0; DoubleWalk(values_).value(e, d)) return std::isfinite(d) ? d : std::numeric_limits<double>::quiet_NaN();
  return std::numeric_limits<double>::quiet_NaN();
}

double Probe::eval(const GiNaC::ex& e) const {
  if (GiNaC::is_a<GiNaC::numeric>(e)) {  // most entries of big matrices: 0
    const auto& n = GiNaC::ex_to<GiNaC::numeric>(e);
    if (n.is_zero()) return 0.0;
  }
  // Double precision first: no expression is built (GiNaC's substitution and evalf cost
  // far more, and throw from inside constructors, leaking, where a division by zero
  // meets them). Not finite (a division by zero, a root of a negative number): NaN.
  if (double d = 0.0; DoubleWalk(values_).value(e, d))
    return std::isfinite(d) ? d : std::numeric_limits<double>::quiet_NaN();
  // Something the walk does not know (another function, a complex value): GiNaC.
  try {
    // Only the symbols e holds (model::subs_present): linear in the model's size.
    GiNaC::ex v = GiNaC::evalf(model::subs_present(e, values_));
    if (!GiNaC::is_a<GiNaC::numeric>(v)) return std::numeric_limits<double>::quiet_NaN();
    const auto& n = GiNaC::ex_to<GiNaC::numeric>(v);
    if (!n.is_real()) return std::numeric_limits<double>::quiet_NaN();
    return n.to_double();
  } catch (const std::exception&) {
    return std::numeric_limits<double>::quiet_NaN();
  }
}

namespace {

/// The parameters' and formals' symbols of one model, for membership tests in O(1).
/// Rebuilt only when the model differs from the last one asked about (its time symbol,
/// created fresh with every model, and a fingerprint of its parameters and formals):
/// is_state_free is called once per matrix entry, and an index per call would make
/// that quadratic in the model's size.
struct ConstantSymbols {
  GiNaC::ex time;
  std::size_t fingerprint = 0;
  std::unordered_set<GiNaC::ex, ExHash, GiNaC::ex_is_equal> symbols;
};

std::size_t fingerprint_of(const model::Model& model) {
  std::size_t h = model.params.size() * 1000003u + model.formals.size();
  for (const auto& p : model.params) h = h * 31u + p.sym.gethash();
  for (const auto& [name, f] : model.formals) h = h * 31u + f.sym.gethash();
  return h;
}

const ConstantSymbols& constant_symbols(const model::Model& model) {
  thread_local ConstantSymbols cache;
  const std::size_t fp = fingerprint_of(model);
  if (cache.fingerprint == fp && cache.time.is_equal(model.time)) return cache;
  cache.time = model.time;
  cache.fingerprint = fp;
  cache.symbols.clear();
  for (const auto& p : model.params) cache.symbols.insert(p.sym);
  for (const auto& [name, f] : model.formals) cache.symbols.insert(f.sym);
  return cache;
}

}  // namespace

bool is_state_free(const GiNaC::ex& e, const model::Model& model) {
  if (GiNaC::is_a<GiNaC::numeric>(e)) return true;
  // One traversal: every symbol must be a parameter or a formal (t, coordinates, speeds,
  // their derivatives, inputs and opaque symbols are none of these).
  const auto& known = constant_symbols(model).symbols;
  for (GiNaC::const_preorder_iterator it = e.preorder_begin(); it != e.preorder_end(); ++it)
    if (GiNaC::is_a<GiNaC::symbol>(*it) && !known.count(*it)) return false;
  return true;
}

}  // namespace mbsc::sym
