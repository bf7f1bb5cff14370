// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The rhs at the start of a run, before anything is integrated or written: where it is
/// not finite (two ends of a spring at one point, a square root of a negative number),
/// the message names the force that is not finite there and where the model writes it,
/// else the rates that are not (docs/running.md, "When the start is wrong").
#include <string>
#include <vector>

#include "mbsc/model/model.hpp"
#include "mbsc/runtime/model_table.hpp"

namespace mbsc::run {

/// False, with `error` (a whole message line, "FILE:LINE:COL: error: ..." at the force),
/// when the rhs of `table` is not finite at
/// (t, x, u, p). `full` is `x` over the full state (`full_table`'s layout: every
/// coordinate and speed), read to evaluate the model's forces one by one.
bool rhs_finite_at_start(const model::Model& m, const runtime::ModelTable& table, const runtime::ModelTable& full_table,
                         double t, const std::vector<double>& x, const std::vector<double>& full,
                         const std::vector<double>& u, const std::vector<double>& p, std::string& error);

}  // namespace mbsc::run
