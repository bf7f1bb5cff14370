// SPDX-License-Identifier: GPL-2.0-or-later
// The last checks of the model: masses and inertias are constants of the parameters, not
// negative at their defaults or --freeze values, and a rigid3d body's inertia tensor is
// positive definite there.
#include "build_internal.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <exception>
#include <stdexcept>

#include "mbsc/model/exact_guard.hpp"
#include "mbsc/model/value_bound.hpp"
#include "mbsc/model/varying_part.hpp"

namespace mbsc::model::build_detail {

/// What makes e vary with the motion: "coordinate 'q'", "speed 'b.u'", "input 'F'",
/// "the time t"; "" when e holds parameters and numbers only.
std::string Builder::varying_part(const GiNaC::ex& e) const { return model::varying_part(m_, e); }

/// Masses and inertias are constants: a body's inertia forces are m v' and J w', which
/// lack the terms of dm/dt when m changes with the motion. So they read parameters
/// only (directly, through a let or through a component's argument). They may not be
/// negative, at the parameters' defaults or their --freeze values (which the message
/// names, since the file alone looks right). Zero is allowed (a massless link); the
/// derivation then checks that the reduced mass matrix stays positive definite
/// (sym/massless_check.hpp).
/// A rigid3d inertia tensor is constant and, at the parameters' defaults (or their
/// --freeze values), symmetric positive definite (its leading minors are positive) or
/// zero.
/// (A tensor that is not makes the mass matrix singular or indefinite.)
void Builder::check_rigid3d_inertia(const Node& node, const SourcePos& pos, const GiNaC::exmap& formals) {
  std::vector<double> I(9);
  for (std::size_t k = 0; k < 9; ++k) {
    GiNaC::ex e = node.rigid3d.inertia[k];
    try {
      for (int pass = 0; pass < 2 && !formals.empty(); ++pass) {
        std::string why;
        const auto next = guarded_subs(e, formals, why);
        if (!next) throw std::runtime_error(why);
        e = *next;
      }
      if (const std::string varying = varying_part(e); !varying.empty()) {
        diags_.error(pos, fmt::format("inertia of body '{}' must be constant: it reads {} (inertias may use parameters "
                                      "only)",
                                      node.name, varying));
        return;
      }
      const GiNaC::ex v = substitute_param_defaults(e, true);
      if (const auto problem = value_problem(v)) {
        diags_.error(pos, fmt::format("inertia of body '{}' at the parameter values{}: {}", node.name, frozen_note(e),
                                      problem->text()));
        return;
      }
      if (!evaluate_number(v, I[k])) return;  // left symbolic: not checked here
    } catch (const std::exception& ex) {
      diags_.error(pos, fmt::format("inertia of body '{}' is undefined at these parameter values ({})", node.name, ex.what()));
      return;
    }
  }
  const double m1 = I[0], m2 = I[0] * I[4] - I[1] * I[3];
  const double m3 = I[0] * (I[4] * I[8] - I[5] * I[7]) - I[1] * (I[3] * I[8] - I[5] * I[6]) + I[2] * (I[3] * I[7] - I[4] * I[6]);
  GiNaC::ex all = 0;  // every entry, for the note on frozen parameters
  for (const auto& e : node.rigid3d.inertia) all += GiNaC::pow(e, 2);
  // A zero tensor on a body a joint places (a point mass, or with mass 0 a massless
  // carriage between joints) is allowed: its attitude follows from the joints, and the
  // derivation checks that every motion still moves some inertia. A body with an
  // attitude of its own needs the whole tensor.
  const bool zero = node.rigid3d.placed() && std::all_of(I.begin(), I.end(), [](double v) { return v == 0; });
  if (!zero && !(m1 > 0 && m2 > 0 && m3 > 0))
    diags_.error(pos, fmt::format("inertia tensor of body '{}' is not positive definite at the parameter values "
                                  "(leading minors {:g}, {:g}, {:g}; all must be positive){}",
                                  node.name, m1, m2, m3, frozen_note(all)));
}

void Builder::check_masses() {
  GiNaC::exmap formals;
  for (auto& [name, f] : m_.formals) {
    try {
      formals[f.sym] = substitute_param_defaults(f.value, true);
    } catch (const std::exception&) {
      // Left symbolic: the masses that use it are not checked here (derive reports it).
    }
  }
  for (size_t n = 0; n < m_.nodes.size(); ++n) {
    const Node& node = m_.nodes[n];
    auto check = [&](const GiNaC::ex& e, const SourcePos& pos, const char* what) {
      GiNaC::ex with_formals = e, v;
      try {
        for (int pass = 0; pass < 2 && !formals.empty(); ++pass) {
          std::string why;
          const auto next = guarded_subs(with_formals, formals, why);
          if (!next) throw std::runtime_error(why);
          with_formals = *next;
        }
        if (const std::string varying = varying_part(with_formals); !varying.empty()) {
          diags_.error(pos, fmt::format("{} of body '{}' must be constant: it reads {} (masses and inertias may use "
                                        "parameters only; a body whose {} changes with the motion needs the terms of "
                                        "its rate: write it as a custom leaf with its own forces)",
                                        what, node.name, varying, what));
          return;
        }
        v = substitute_param_defaults(with_formals, true);
      } catch (const std::exception& ex) {
        diags_.error(pos, fmt::format("{} of body '{}' is undefined at these parameter values{} ({})", what, node.name,
                                      frozen_note(with_formals), ex.what()));
        return;
      }
      // At these values the generated code computes with it: a real number within the
      // bound (sqrt(a) with a = -1 is not; neither is a*a with a = 1e20).
      if (const auto problem = value_problem(v)) {
        diags_.error(pos, fmt::format("{} of body '{}' at the parameter values{}: {}", what, node.name,
                                      frozen_note(with_formals), problem->text()));
        return;
      }
      double d;
      if (evaluate_number(v, d) && !(d >= 0))
        diags_.error(pos, fmt::format("{} of body '{}' is negative ({}){}", what, node.name, d,
                                      frozen_note(with_formals)));
    };
    if (has_mass_.count(static_cast<int>(n))) check(node.mass, node.mass_pos, "mass");
    if (inertia_pos_.count(static_cast<int>(n))) check(node.inertia, inertia_pos_[n], "inertia");
    if (rigid3d_inertia_pos_.count(static_cast<int>(n))) check_rigid3d_inertia(node, rigid3d_inertia_pos_[n], formals);
  }
}

/// ", with --freeze a=1" naming the frozen parameters e depends on, or "".
std::string Builder::frozen_note(const GiNaC::ex& e) const {
  std::string names;
  for (const auto& p : m_.params) {
    const auto it = frozen_.find(p.name);
    if (it == frozen_.end() || !e.has(p.sym)) continue;
    names += fmt::format("{}{}={}", names.empty() ? "" : " ", p.name, it->second);
  }
  return names.empty() ? "" : ", with --freeze " + names;
}

}  // namespace mbsc::model::build_detail
