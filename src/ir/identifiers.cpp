// SPDX-License-Identifier: GPL-2.0-or-later
#include "identifiers.hpp"

#include <algorithm>
#include <cctype>
#include <cstring>

namespace mbsc::ir {

namespace {

bool is_ident_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) != 0 || c == '_'; }
bool is_ident_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_'; }
bool is_digit(char c) { return c >= '0' && c <= '9'; }

// Sorted, for binary search.
constexpr const char* kKeywords[] = {
    "alignas",   "alignof",      "and",          "and_eq",      "asm",       "auto",     "bitand",
    "bitor",     "bool",         "break",        "case",        "catch",     "char",     "char16_t",
    "char32_t",  "class",        "compl",        "const",       "const_cast", "constexpr", "continue",
    "decltype",  "default",      "delete",       "do",          "double",    "dynamic_cast", "else",
    "enum",      "explicit",     "export",       "extern",      "false",     "float",    "for",
    "friend",    "goto",         "if",           "inline",      "int",       "long",     "mutable",
    "namespace", "new",          "noexcept",     "not",         "not_eq",    "nullptr",  "operator",
    "or",        "or_eq",        "private",      "protected",   "public",    "register", "reinterpret_cast",
    "return",    "short",        "signed",       "sizeof",      "static",    "static_assert", "static_cast",
    "struct",    "switch",       "template",     "this",        "thread_local", "throw", "true",
    "try",       "typedef",      "typeid",       "typename",    "union",     "unsigned", "using",
    "virtual",   "void",         "volatile",     "wchar_t",     "while",     "xor",      "xor_eq",
};

}  // namespace

bool is_identifier(const std::string& s) {
  if (s.empty() || !is_ident_start(s[0])) return false;
  return std::all_of(s.begin(), s.end(), is_ident_char);
}

bool is_cpp_keyword(const std::string& s) {
  return std::binary_search(std::begin(kKeywords), std::end(kKeywords), s.c_str(),
                            [](const char* a, const char* b) { return std::strcmp(a, b) < 0; });
}

// Macros a model name or a local variable name must not meet: the standard headers'
// and the platform's (std_macro_names.cpp, derived from GCC and glibc), a few of other
// platforms, and the families of <cmath> and <cstdint> by prefix.
bool is_std_macro_name(const std::string& s) {
  if (is_listed_std_macro(s)) return true;
  // Predefined on other targets (i386 on 32-bit x86) or by other C libraries.
  static constexpr const char* kExact[] = {"i386", "DOMAIN", "SING", "OVERFLOW", "UNDERFLOW", "TLOSS", "PLOSS"};
  for (const char* e : kExact)
    if (s == e) return true;
  static constexpr const char* kPrefixes[] = {"M_",         "FP_",        "HUGE_VAL",   "MATH_ERR",  "__",
                                              "INT8_",      "INT16_",     "INT32_",     "INT64_",    "INTMAX_",
                                              "INTPTR_",    "UINT8_",     "UINT16_",    "UINT32_",   "UINT64_",
                                              "UINTMAX_",   "UINTPTR_",   "INT_LEAST",  "INT_FAST",  "UINT_LEAST",
                                              "UINT_FAST",  "SIZE_",      "PTRDIFF_",   "WCHAR_",    "WINT_",
                                              "SIG_ATOMIC_"};
  for (const char* p : kPrefixes)
    if (s.compare(0, std::strlen(p), p) == 0) return true;
  return false;
}

bool is_generated_name(const std::string& s) {
  std::size_t digits_from = 0;
  if (s.size() >= 2 && (s[0] == 't' || s[0] == 's' || s[0] == 'c')) digits_from = 1;
  else if (s.size() >= 3 && (s[0] == 'A' || s[0] == 'B') && s[1] == '_') digits_from = 2;
  else return false;
  return std::all_of(s.begin() + static_cast<std::ptrdiff_t>(digits_from), s.end(), is_digit);
}

std::string namespace_name_problem(const std::string& name) {
  if (!is_identifier(name)) return "is not a C++ identifier (letters, digits and '_', not starting with a digit)";
  if (is_cpp_keyword(name)) return "is a C++ keyword";
  if (name.find("__") != std::string::npos) return "contains '__' (reserved in C++)";
  if (name[0] == '_') return "starts with '_' (reserved in C++)";
  if (is_std_macro_name(name)) return "is a macro of the C++ standard library or of the compiler";
  // The generated code says std::sin, mbsc_gen::..., and lives in mbsc_gen::NAME: a
  // namespace of either name inside mbsc_gen would capture those lookups.
  if (name == "std" || name == "mbsc_gen") return "is a namespace the generated code uses";
  if (name.size() > 200) return "is longer than 200 characters";
  return "";
}

// Replace invalid characters, collapse '_' runs, trim '_' at both ends, fix a leading digit.
std::string sanitize_identifier(const std::string& name) {
  std::string out;
  for (char c : name) {
    const char d = is_ident_char(c) ? c : '_';
    if (d == '_' && (out.empty() || out.back() == '_')) continue;
    out.push_back(d);
  }
  while (!out.empty() && out.back() == '_') out.pop_back();
  if (out.empty()) return "v";
  if (is_digit(out[0])) out = "v" + out;
  return out;
}

}  // namespace mbsc::ir
