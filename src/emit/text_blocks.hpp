// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Text pieces every emitted file shares (private to src/emit; defined in emit.cpp).
#include <string>
#include <vector>

#include "mbsc/emit/generated_model.hpp"

namespace mbsc::emit {

/// Defined in the build directory's embedded_templates.cpp (cmake/embed_templates.cmake).
const std::string& template_text(const std::string& name);

/// The parts with `sep` between them ("a, b, c").
std::string join(const std::vector<std::string>& parts, const std::string& sep);

/// Every line of `text` behind a comment marker ("//", "#"), control characters made
/// spaces, trailing blanks and backslashes dropped.
std::string comment_block(const std::string& text, const std::string& marker);

/// A double-quoted string literal valid in C++ and in Python: bytes outside printable
/// ASCII become 3-digit octal escapes.
std::string c_string_literal(const std::string& s);

/// The banner's text without comment markers: provenance, operation counts, notes and
/// the licence exception.
std::string banner_text(const GeneratedModel& m);

}  // namespace mbsc::emit
