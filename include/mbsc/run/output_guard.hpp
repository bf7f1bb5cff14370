// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Checks on the files `run`, `inverse` and `bench` will write, made before any work:
/// an output must not be the model or a file it includes (also through a link), not a
/// folder or anything else that is not a plain file (a FIFO would block the run), not
/// another output of the same command, hold no control character (a plot's script names
/// the CSV), and its folder must be writable; a
/// plot needs gnuplot. So a mistyped -o never destroys a user's file, and a run is not
/// thrown away for a plot that cannot be drawn.
#include <string>
#include <vector>

namespace mbsc::run {

/// `outputs`: (flag, path) pairs ("-" is standard output and always fine; "" is skipped).
/// False with `error` naming the flag and the problem.
bool check_outputs(const std::vector<std::pair<std::string, std::string>>& outputs,
                   const std::vector<std::string>& sources, std::string& error);

/// gnuplot can be run; false with `error` saying what to install.
bool gnuplot_available(std::string& error);

}  // namespace mbsc::run
