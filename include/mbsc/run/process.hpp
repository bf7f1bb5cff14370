// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Running another program (the C++ compiler, gnuplot) without a shell: the arguments
/// are passed as they are, so no file name is ever interpreted as shell syntax.
///
/// The program never outlives mbsc. It runs under a small guardian process (a fork of
/// mbsc that runs no other code) which leads a process group of its own: whatever the
/// program starts (the compiler driver's cc1plus and as) stays in that group. When mbsc
/// ends for any reason (exit, SIGINT, SIGTERM, even SIGKILL) the kernel signals the
/// guardian (PR_SET_PDEATHSIG), which kills the whole group; a timeout kills it from mbsc.
/// A terminal's Ctrl-C does not reach the group (it is not the terminal's foreground
/// group): mbsc dies of it, and the guardian ends the rest.
#include <sys/types.h>

#include <cstddef>
#include <string>
#include <vector>

namespace mbsc::run {

struct ProcessOptions {
  std::string input;               // written to the program's standard input
  double timeout_seconds = 0;      // then the program and its group are killed; 0: no limit
  std::size_t memory_mib = 0;      // RLIMIT_DATA of the program and its children; 0: none
  int working_folder = -1;         // an open folder the program starts in (fchdir); -1: mbsc's own
  bool private_files = false;      // umask 077: what it creates is the user's alone (the cache)
  bool separate_errors = false;    // standard error in `errors`, not interleaved into `output`
};

struct ProcessResult {
  int exit_code = -1;       // the program's exit status (128 + N when signal N ended it); 127 when it could not be started
  std::string output;       // its standard output (and standard error, unless separate_errors)
  std::string errors;       // its standard error, with separate_errors
  std::string spawn_error;  // why it could not be started ("" when it was)
  bool timed_out = false;   // stopped (killed, with what it started) after the timeout
};

/// Runs args[0] (looked up in PATH) with the rest as arguments and waits for it.
ProcessResult run_process(const std::vector<std::string>& args, const ProcessOptions& options);

/// The common case: `input` on standard input, at most `timeout_seconds` (0: no limit).
ProcessResult run_process(const std::vector<std::string>& args, const std::string& input = "",
                          double timeout_seconds = 0);

}  // namespace mbsc::run
