// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The text of a `latex NAME "..."` statement goes into every formula `mbsc print --latex`
/// writes with that name. It must be safe there: pasted into a math environment of a
/// document (amsmath loaded), inside a matrix cell, and followed by a subscript or a
/// power, it may not end the formula, break the document or the cell, nor leave a
/// group open.
#include <string>

namespace mbsc::parse {

/// Why `text` is not safe LaTeX for a symbol ("has a '{' that is not closed"), or ""
/// when it is.
std::string latex_text_problem(const std::string& text);

}  // namespace mbsc::parse
