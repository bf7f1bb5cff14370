// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The top-level module names a generated Python module (`generate --python`) must not
/// take: NAME.py next to a script is found by `import NAME` only when NAME is not a
/// standard-library module Python loads first, and when it is found it hides that module
/// from every other import (numpy's, ours).
#include <string>

namespace mbsc::emit {

/// True when `name` is a public top-level module of Python 3's standard library (any
/// version from 3.0 on: the modules removed since are listed too, as an older Python
/// still has them), or a package the generated module itself imports (numpy).
bool is_python_module_name(const std::string& name);

}  // namespace mbsc::emit
