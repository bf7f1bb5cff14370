// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/sym/multipliers.hpp"

#include "mbsc/sym/eom.hpp"
#include "mbsc/sym/own_force.hpp"

namespace mbsc::sym {

MultiplierForm multiplier_form(const model::Model& m) {
  const unsigned nu = static_cast<unsigned>(m.speeds.size()), nc = static_cast<unsigned>(m.constraints.size());
  MultiplierForm out{GiNaC::matrix(nu, nu), GiNaC::matrix(nu, 1), GiNaC::matrix(nc, nu), GiNaC::matrix(nc, 1),
                     GiNaC::matrix(nc, 1), GiNaC::matrix(nc, 1)};
  GiNaC::exmap no_rates;
  for (const auto& s : m.speed_dots) no_rates[s] = 0;
  for (unsigned i = 0; i < nu; ++i) {
    const GiNaC::ex f = own_force(m, static_cast<int>(i));
    for (unsigned j = 0; j < nu; ++j) out.My(i, j) = -f.diff(m.speed_dots[j]);
    out.hy(i, 0) = f.subs(no_rates);
  }
  const std::vector<GiNaC::ex> order1 = velocity_residuals(m);
  for (unsigned r = 0; r < nc; ++r) {
    out.velocity(r, 0) = order1[r];
    for (unsigned j = 0; j < nu; ++j) out.A(r, j) = order1[r].diff(m.speeds[j].sym);
    out.b(r, 0) = time_derivative(m, order1[r]).subs(no_rates);
    const auto& c = m.constraints[r];
    out.g(r, 0) = c.level == model::Constraint::Level::Position ? c.residual : GiNaC::ex(0);
  }
  return out;
}

}  // namespace mbsc::sym
