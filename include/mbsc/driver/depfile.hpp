// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The make-style dependency file `generate --depfile FILE` writes: which files the
/// generated code was derived from (the model and every file it includes), so that a
/// build tool (make, ninja, CMake's DEPFILE) regenerates when any of them changes.
#include <string>
#include <vector>

namespace mbsc::driver {

/// `path` written for make: a space, tab or '#' gets a backslash (and the backslashes
/// right before it are doubled), '$' becomes "$$". Everything else is kept as it is.
std::string make_escaped(const std::string& path);

/// The depfile text: one rule, `TARGET1 TARGET2: PREREQ1 PREREQ2 ...` (one prerequisite
/// a line, each line but the last ending in a backslash), then an empty rule `PREREQ:`
/// for each prerequisite after the first (as `gcc -MP` writes), so that make does not
/// stop at an included file that has been removed. False, with `error` set, when a path
/// holds a character make or ninja would read as syntax and that has no escape: a
/// control character (a line break), ';' (a recipe: a command make would run), ':',
/// '=', '|', '%', '&', parentheses or a wildcard.
bool depfile_text(const std::vector<std::string>& targets, const std::vector<std::string>& prerequisites,
                  std::string& text, std::string& error);

}  // namespace mbsc::driver
