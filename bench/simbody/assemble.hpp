// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// A consistent Simbody state from an InitialState: the given coordinates are locked and
// Simbody's Assembler solves the loop closures for the others (starting from the
// guesses); the given speeds are held by ConstantSpeed constraints (enabled only here)
// while projectU solves the velocity constraints for the other speeds.
#include "initial_states.hpp"
#include "mechanism.hpp"

namespace simbench {

// Adds a disabled ConstantSpeed for each independent speed; call before realizeTopology.
void add_speed_locks(Mechanism& m);
// Throws std::runtime_error when a name is unknown or the closure cannot be met.
SimTK::State assemble_initial_state(Mechanism& m, const InitialState& init);

}  // namespace simbench
