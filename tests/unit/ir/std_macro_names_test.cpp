// SPDX-License-Identifier: GPL-2.0-or-later
// The model name becomes a C++ namespace (and a local variable may be named after a let
// or a speed): a name the standard headers define as a macro breaks the generated code
// where it is included after them. src/ir/std_macro_names.cpp holds the list GCC and
// glibc gave; here the system's compiler gives it again, and every macro that is an
// identifier the other rules let through (no leading '_', no "__") must be refused.
#include <catch2/catch.hpp>

#include <cctype>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "../../../src/ir/identifiers.hpp"
#include "../emit/compile_helpers.hpp"

namespace {

/// The compiler to ask: $CXX (its first word), else c++; "" when there is none.
std::string system_compiler() {
  std::string cxx = "c++";
  if (const char* env = std::getenv("CXX"); env && *env) {
    std::istringstream words(env);
    words >> cxx;
  }
  std::string out;
  return mbsc::test::run_command("command -v '" + cxx + "' >/dev/null", out) == 0 ? cxx : "";
}

/// NAME of every "#define NAME..." line.
std::vector<std::string> defined_names(const std::string& dump) {
  std::vector<std::string> names;
  std::istringstream lines(dump);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("#define ", 0) != 0) continue;
    std::size_t end = 8;
    while (end < line.size() && (std::isalnum(static_cast<unsigned char>(line[end])) || line[end] == '_')) ++end;
    names.push_back(line.substr(8, end - 8));
  }
  return names;
}

}  // namespace

TEST_CASE("every macro of the standard headers is refused as a model name", "[ir][names]") {
  const std::string cxx = system_compiler();
  if (cxx.empty()) {
    WARN("standard macro list check skipped: no C++ compiler found ($CXX or c++)");
    return;
  }
  // The headers of std_macro_names.cpp's command; <bits/stdc++.h> is libstdc++'s, so
  // another library lists its C++ headers' macros through <cmath>, <cstdio>, ... instead.
  const char* const c_headers[] = {"assert.h", "ctype.h",  "errno.h",  "fenv.h",   "float.h",  "inttypes.h",
                                   "iso646.h", "limits.h", "locale.h", "math.h",   "setjmp.h", "signal.h",
                                   "stdarg.h", "stddef.h", "stdint.h", "stdio.h",  "stdlib.h", "string.h",
                                   "time.h",   "uchar.h",  "wchar.h",  "wctype.h"};
  mbsc::test::ScratchDir dir("std_macros");
  std::string source = "#if __has_include(<bits/stdc++.h>)\n#include <bits/stdc++.h>\n#else\n"
                       "#include <cmath>\n#include <cstdio>\n#include <cstdlib>\n#include <cerrno>\n#include <climits>\n"
                       "#include <csignal>\n#include <ctime>\n#include <iostream>\n#endif\n";
  for (const char* h : c_headers) source += std::string("#include <") + h + ">\n";
  mbsc::test::write_file(dir.file("all.cpp"), source);
  std::string dump;
  const int status = mbsc::test::run_command(cxx + " -std=gnu++17 -dM -E -x c++ '" + dir.file("all.cpp") + "'", dump);
  if (status != 0) {
    WARN("standard macro list check skipped: " << cxx << " could not preprocess the standard headers:\n" << dump.substr(0, 2000));
    return;
  }
  const std::vector<std::string> names = defined_names(dump);
  REQUIRE(names.size() > 500);  // the command worked: glibc and libstdc++ define about 3600
  std::vector<std::string> let_through;
  std::size_t checked = 0;
  for (const auto& name : names) {
    if (name.empty() || name[0] == '_' || name.find("__") != std::string::npos) continue;  // reserved: refused anyway
    ++checked;
    if (mbsc::ir::namespace_name_problem(name).empty()) let_through.push_back(name);
  }
  INFO(checked << " macro names checked with " << cxx << "; let through as a model name (add them to "
                  "src/ir/std_macro_names.cpp with the command there):");
  for (const auto& n : let_through) INFO(n);
  CHECK(let_through.empty());
  // Sanity: the names of the issue, and some that must stay usable.
  for (const char* macro : {"RAND_MAX", "EOF", "NULL", "errno", "assert", "stdin", "EXIT_SUCCESS", "INT_MAX", "SIGINT", "M_PI",
                            "unix", "linux"})
    CHECK_FALSE(mbsc::ir::namespace_name_problem(macro).empty());
  for (const char* fine : {"double_pendulum", "rand_max", "eof", "sigint", "pendulum"})
    CHECK(mbsc::ir::namespace_name_problem(fine).empty());
}
