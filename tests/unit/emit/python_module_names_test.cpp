// SPDX-License-Identifier: GPL-2.0-or-later
// The names a `generate --python` module must not take (emit/python_module_names.hpp).
#include <catch2/catch.hpp>

#include "mbsc/emit/python_module_names.hpp"

using mbsc::emit::is_python_module_name;

TEST_CASE("Python's standard modules and numpy are taken names", "[emit][python]") {
  // Built into the interpreter (import finds them before NAME.py) and loaded from files
  // (NAME.py hides them), first and last of the list, and one with a capital.
  for (const char* name : {"gc", "sys", "time", "math", "os", "random", "signal", "array", "abc", "zoneinfo", "cProfile",
                           "collections", "xml", "tomllib", "asyncore", "numpy"}) {
    INFO(name);
    CHECK(is_python_module_name(name));
  }
}

TEST_CASE("model names that are no Python module are free", "[emit][python]") {
  for (const char* name : {"double_pendulum", "gantry", "Math", "gc_model", "pendulum", "mathx", "", "cprofile", "np"}) {
    INFO(name);
    CHECK(!is_python_module_name(name));
  }
}
