// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Massless links: a body may have mass 0 and/or inertia 0 (a massless rod between a
/// hinge and a point mass) as long as the reduced mass matrix M stays positive definite,
/// i.e. every motion the constraints allow moves something with inertia. When M is
/// singular at the probe point (parameter defaults, a generic state), the null motions
/// of M are followed to every speed; the bodies without mass or inertia that move in
/// them are what leaves M singular. Bodies that move in the same null motion are one
/// cause: one error names them all, at the `mass 0` or `inertia 0` the user most likely
/// just changed (one a --freeze made zero, else the one written last), with the
/// independent speeds of the motion, each body's speeds that carry no inertia and what
/// to give which body. M regular at the probe point may still be singular at the
/// model's reference configuration (a massless cart and cable with the load hanging
/// straight below): check_massless_at_reference warns there, the same way.
#include <Eigen/Dense>

#include <string>
#include <vector>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/model/model.hpp"
#include "mbsc/sym/eom.hpp"
#include "mbsc/sym/probe.hpp"

namespace mbsc::sym {

/// Bodies whose mass or inertia is zero at the probe's parameter values, as
/// "rod (mass 0, inertia 0)", in model order.
std::vector<std::string> massless_bodies(const model::Model& m, const Probe& probe);

/// Called when M (its value Mn at the probe point, finite) is not positive definite:
/// reports an error at each massless body that moves in a null motion of M. Returns
/// true when it reported one (otherwise the singularity has another cause).
bool report_massless_directions(const model::Model& m, const Eom& eom, const Probe& probe, const Eigen::MatrixXd& Mn,
                                Diagnostics& diags);

/// Called when M is positive definite at the probe point: M at the model's reference
/// configuration (Probe::reference; the numeric solves and named variables evaluated
/// there as the generated code does). Warns, per group of massless bodies that move in
/// a motion without inertia there, at the group's site; a singularity in which no
/// massless body moves (a coordinate singularity) is not theirs and is not reported.
MassAtReference check_massless_at_reference(const model::Model& m, const Eom& eom, const Probe& reference,
                                            Diagnostics& diags);

}  // namespace mbsc::sym
