// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// "did you mean 'm3'?" for a name that is not known: the closest of the names that
/// would have been accepted at that place, when one is close enough to be a typo.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace mbsc {

/// Edit distance between a and b counting insertions, deletions, substitutions and
/// swaps of two neighbouring characters (each costs 1): "intertia" -> "inertia" is 1,
/// "mas" -> "mass" is 1, "m3" -> "m_3" is 1, "tehta" -> "theta" is 1.
std::size_t edit_distance(const std::string& a, const std::string& b);

/// The largest distance that still reads as a typo of a name of `length` characters:
/// 1 up to 4 characters, 2 up to 8, 3 beyond, and always less than `length` (a one-letter
/// name suggests nothing: every other letter is one edit away).
std::size_t typo_distance_limit(std::size_t length);

/// The candidate closest to `written` within typo_distance_limit, or nothing. Ties go to
/// the candidate listed first (callers list the innermost scope first), so the answer
/// does not depend on anything but the two inputs. `written` itself is never suggested.
std::optional<std::string> closest_name(const std::string& written, const std::vector<std::string>& candidates);

/// " (did you mean 'm3'?)" for the closest candidate; when none is close, the candidates
/// that end in "." + written (" (did you mean 'load.theta'?)" for "theta"; several as
/// "'cart.u' or 'load.u'"); "" otherwise.
std::string did_you_mean(const std::string& written, const std::vector<std::string>& candidates);

/// A name as a command line may write it, as the model declares it: every "[N]" (a
/// loop's index, N digits) after a name becomes "_N", so "blk[1].x" is "blk_1.x".
std::string declared_name(const std::string& written);

/// "a, b and c" (or "a" or "a and b"), for "known kinds: ..." lists.
std::string list_names(const std::vector<std::string>& names);

}  // namespace mbsc
