// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// C++ identifier helpers shared by the IR printer and the emitter (private).
#include <string>

namespace mbsc::ir {

/// True for a syntactically valid C++ identifier ([A-Za-z_][A-Za-z0-9_]*).
bool is_identifier(const std::string& s);
/// C++17 keywords and alternative tokens ("and", "or", ...).
bool is_cpp_keyword(const std::string& s);
/// Names the standard library or the platform may define as macros (M_PI, NAN, errno,
/// RAND_MAX, EOF, stdin, SIGINT, linux, ...): is_listed_std_macro, and prefix families.
bool is_std_macro_name(const std::string& s);
/// The macros of GCC's and glibc's standard headers, by name (std_macro_names.cpp).
bool is_listed_std_macro(const std::string& s);
/// Names the printer generates itself: t<N>, s<N>, c<N>, A_<N>, B_<N>.
bool is_generated_name(const std::string& s);
/// Why `name` cannot be the namespace and file stem of a generated model (a C++
/// keyword, a reserved name, a standard macro, ...), or "" when it can.
std::string namespace_name_problem(const std::string& name);
/// Maps any text to an identifier: invalid characters become '_', runs of '_' collapse,
/// no leading or trailing '_', a leading digit gets a "v" prefix, "" becomes "v".
std::string sanitize_identifier(const std::string& name);

}  // namespace mbsc::ir
