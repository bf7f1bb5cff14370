// SPDX-License-Identifier: GPL-2.0-or-later
// Coulomb friction on a prismatic joint closed in the generated code (docs/formulation.md,
// "Coulomb friction on a reaction"). The friction force F is a symbol in the forces; every
// function that reads it gets, before its first use, the steps that define it:
//  1. the system over all speeds [My -A^T; A 0] [q1'; lambda] = [hy; c] solved for two
//     right-hand sides, hy at F = 0 and dhy/dF (the forces are affine in F), so that the
//     joint's normal reaction is N = N0 + F N1;
//  2. the law F = -mu sign(v) |N| squared: (1 - mu^2 |N1|^2) F^2 - 2 mu^2 (N0.N1) F -
//     mu^2 |N0|^2 = 0, whose roots have opposite signs while 1 - mu^2 |N1|^2 > 0; the
//     root of sign -sign(v) is F, and v = 0 gives F = 0;
//  3. 1 - mu^2 |N1|^2 is "solved" as a 1x1 positive definite block: where it is not
//     positive (the Painleve case: friction jams the joint) the function returns 1.
#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "mbsc/driver/pipeline.hpp"
#include "mbsc/sym/multipliers.hpp"
#include "mbsc/sym/tidy.hpp"

namespace mbsc::driver {

namespace {

bool reads(const ir::Step& step, const GiNaC::symbol& F) {
  if (const auto* d = std::get_if<ir::Define>(&step)) return d->value.has(F);
  const auto& s = std::get<ir::Solve>(step);
  return std::any_of(s.A.begin(), s.A.end(), [&](const GiNaC::ex& e) { return e.has(F); }) ||
         std::any_of(s.B.begin(), s.B.end(), [&](const GiNaC::ex& e) { return e.has(F); });
}

bool defines(const ir::Step& step, const GiNaC::symbol& F) {
  const auto* d = std::get_if<ir::Define>(&step);
  return d && d->sym.is_equal(F);
}

/// The steps that define the friction force F of `fr`.
std::vector<ir::Step> closure_steps(const model::Model& m, const sym::Eom& eom, const model::Friction& fr,
                                    bool multipliers, const BaumgarteGains& gains) {
  auto fin = [&](const GiNaC::ex& e) { return sym::tidy(finalize(m, eom, e)); };
  const sym::MultiplierForm form = sym::multiplier_form(m);
  const unsigned nu = form.My.rows(), nc = form.A.rows();
  auto row = [&](const std::string& name) {
    for (std::size_t r = 0; r < m.constraints.size(); ++r)
      if (m.constraints[r].name == name) return static_cast<unsigned>(r);
    throw std::logic_error("friction: no row '" + name + "'");
  };
  const unsigned r1 = row(fr.row1), r2 = row(fr.row2);
  const GiNaC::exmap no_friction{{fr.force, 0}};
  ir::Solve s;
  s.label = fmt::format("friction of joint '{}': [My -A^T; A 0] [q1'; lambda] = [hy; c] at F = 0 and d/dF", fr.joint);
  s.n = static_cast<int>(nu + nc);
  s.k = 2;
  s.reported = false;
  for (unsigned i = 0; i < nu + nc; ++i) {
    for (unsigned j = 0; j < nu + nc; ++j) {
      GiNaC::ex e = 0;
      if (i < nu && j < nu) e = form.My(i, j);
      else if (i < nu) e = -form.A(j - nu, i);
      else if (j < nu) e = form.A(i - nu, j);
      s.A.push_back(fin(e));
    }
    if (i < nu) {
      const GiNaC::ex h = form.hy(i, 0);  // affine in F
      s.B.push_back(fin(h.subs(no_friction)));
      s.B.push_back(fin(h.diff(fr.force)));
    } else {
      // The multipliers form's lambda carries its Baumgarte terms (its own rhs uses them).
      const unsigned r = i - nu;
      GiNaC::ex c = -form.b(r, 0);
      if (multipliers) c -= 2 * gains.alpha * form.velocity(r, 0) + gains.beta * gains.beta * form.g(r, 0);
      s.B.push_back(fin(c));
      s.B.push_back(0);
    }
    for (int col = 0; col < 2; ++col) s.X.emplace_back(fmt::format("friction_kkt_{}_{}", i, col));
  }
  auto lambda = [&](unsigned r, int col) { return GiNaC::ex(s.X[(nu + r) * 2 + static_cast<unsigned>(col)]); };
  const GiNaC::ex w1 = fin(fr.weight1), w2 = fin(fr.weight2), mu = fin(fr.mu);
  const GiNaC::ex n00 = w1 * pow(lambda(r1, 0), 2) + w2 * pow(lambda(r2, 0), 2);
  const GiNaC::ex n11 = w1 * pow(lambda(r1, 1), 2) + w2 * pow(lambda(r2, 1), 2);
  const GiNaC::ex n01 = w1 * lambda(r1, 0) * lambda(r1, 1) + w2 * lambda(r2, 0) * lambda(r2, 1);
  // sigma first: at rest (sigma = 0) the law gives F = 0 whatever N, and the lead below
  // is 1, so a joint at rest never reports a jam.
  const GiNaC::symbol sigma("friction_sign"), root("friction_root");
  ir::Solve lead;
  lead.label = fmt::format("friction of joint '{}': 1 - mu^2 |N1|^2 > 0, else the joint jams (status 1)", fr.joint);
  lead.n = 1;
  lead.k = 1;
  lead.spd = true;
  lead.reported = false;
  lead.A.push_back(1 - sigma * sigma * mu * mu * n11);
  lead.B.push_back(1);
  const GiNaC::symbol inverse("friction_inverse_lead");
  lead.X.push_back(inverse);
  const GiNaC::ex b = -2 * mu * mu * n01, c = -mu * mu * n00;
  std::vector<ir::Step> steps{s};
  steps.push_back(ir::Define{sigma, GiNaC::csgn(fin(fr.slide_velocity)), false});
  steps.push_back(lead);
  // b^2 - 4 a c >= b^2 >= 0 since a > 0 and c <= 0.
  steps.push_back(ir::Define{root, GiNaC::sqrt(b * b - 4 * c / inverse), false});
  steps.push_back(ir::Define{fr.force, -(sigma * sigma * b + sigma * root) * inverse / 2, true});
  return steps;
}

}  // namespace

void close_friction(const model::Model& m, const sym::Eom& eom, bool multipliers, const BaumgarteGains& gains,
                    std::vector<ir::FunctionSpec>& specs, std::optional<std::vector<ir::Step>>& closure) {
  if (m.frictions.empty()) return;
  const model::Friction& fr = m.frictions.front();
  // `closure` is built for the first function that needs it.
  for (auto& f : specs) {
    if (!f.undefined_reason.empty()) continue;
    if (std::any_of(f.steps.begin(), f.steps.end(), [&](const ir::Step& s) { return defines(s, fr.force); })) continue;
    const auto first = std::find_if(f.steps.begin(), f.steps.end(), [&](const ir::Step& s) { return reads(s, fr.force); });
    const bool outputs = std::any_of(f.outputs.begin(), f.outputs.end(), [&](const GiNaC::ex& e) { return e.has(fr.force); });
    if (first == f.steps.end() && !outputs) continue;
    if (f.third_arg == "zdot") {
      // Given accelerations, the friction and the inputs are one coupled problem (the
      // thesis's inverse dynamics of Ex 4.5): not generated.
      f.undefined_reason =
          fmt::format("the friction of joint '{}' and the inputs are coupled; solve them together", fr.joint);
      continue;
    }
    if (!closure) closure = closure_steps(m, eom, fr, multipliers, gains);
    f.steps.insert(first, closure->begin(), closure->end());
  }
}

}  // namespace mbsc::driver
