// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// The initial state of each benchmarked model, read from bench/simbody/initial_states.txt
// (one place for the Simbody peer, the mbsc reference driver and `mbsc bench`).
//
// Format: one line per model, `#` starts a comment, fields separated by blanks:
//   MODEL  name=value ...  name~value ...
// `name=value` gives an independent coordinate or speed (mbsc's state names) and is held
// fixed while the rest of the state is assembled; `name~value` is a starting guess for a
// dependent coordinate, which only picks the assembly branch (elbow up or down); every
// coordinate not named starts at 0. Values are plain decimal numbers.
#include <string>
#include <utility>
#include <vector>

namespace simbench {

struct InitialState {
  std::string model;
  std::vector<std::pair<std::string, double>> given;  // held fixed
  std::vector<std::pair<std::string, double>> guess;  // branch choice only
};

// Throws std::runtime_error "FILE:LINE: ..." on a malformed line.
std::vector<InitialState> read_initial_states(const std::string& path);
// The entry for `model`; throws when the file has none.
InitialState find_initial_state(const std::string& path, const std::string& model);

}  // namespace simbench
