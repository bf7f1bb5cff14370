// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Running another program (the C++ compiler, gnuplot) without a shell: the arguments
/// are passed as they are, so no file name is ever interpreted as shell syntax.
#include <string>
#include <vector>

namespace mbsc::run {

struct ProcessResult {
  int exit_code = -1;       // the program's exit status; 127 when it could not be started
  std::string output;       // its standard output and standard error, interleaved
  std::string spawn_error;  // why it could not be started ("" when it was)
  bool timed_out = false;   // stopped (killed, with what it started) after the timeout
};

/// Runs args[0] (looked up in PATH) with the rest as arguments; `input` is written to
/// its standard input. Waits for it, at most `timeout_seconds` (0: no limit), then kills
/// it and its process group. The program dies with mbsc (a killed mbsc leaves no
/// compiler running).
ProcessResult run_process(const std::vector<std::string>& args, const std::string& input = "",
                          double timeout_seconds = 0);

}  // namespace mbsc::run
