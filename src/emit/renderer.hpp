// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Minimal template renderer (private to src/emit).
///
/// `{{key}}` is replaced by fragments[key]. A placeholder alone on its line takes the line's
/// indentation for every fragment line and removes the line when the fragment is empty;
/// an inline placeholder indents the fragment's later lines to its column. A fragment's
/// final newline ends its last line. `{{! text }}` is a template comment (a line holding
/// only comments disappears). Unknown keys, unused fragments, malformed placeholders:
/// std::runtime_error naming the template and line.
#include <map>
#include <string>

namespace mbsc::emit {

using Fragments = std::map<std::string, std::string>;

std::string render(const std::string& template_name, const std::string& text, const Fragments& fragments);

}  // namespace mbsc::emit
