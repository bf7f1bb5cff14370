// SPDX-License-Identifier: GPL-2.0-or-later
/// Model names to LaTeX symbols (see latex_names.hpp). A name is read as
///   qualifier '.' ... '.' base  primes
/// The base gives the letter and its own subscripts; the qualifiers (the bodies and
/// subsystems it belongs to) go first in the subscript; each prime is a dot over the
/// letter.
#include "mbsc/print/latex_names.hpp"

#include <array>
#include <cctype>
#include <utility>
#include <vector>

namespace mbsc::print {
namespace {

/// A letter with its subscript items: stem_{sub[0],sub[1],...}.
struct Symbol {
  std::string stem;
  std::vector<std::string> sub;
};

bool is_digit(char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; }
bool is_alpha(char c) { return std::isalpha(static_cast<unsigned char>(c)) != 0; }
bool is_upper(char c) { return std::isupper(static_cast<unsigned char>(c)) != 0; }
bool is_lower(char c) { return std::islower(static_cast<unsigned char>(c)) != 0; }

bool all_of(const std::string& s, bool (*pred)(char)) {
  if (s.empty()) return false;
  for (char c : s)
    if (!pred(c)) return false;
  return true;
}

/// Greek letters spelled out, and the usual abbreviation th.
std::string greek(const std::string& w) {
  static const std::array<const char*, 29> lower = {
      "alpha",  "beta",    "gamma",      "delta", "epsilon", "varepsilon", "zeta",   "eta",    "theta",    "vartheta",
      "iota",   "kappa",   "lambda",     "mu",    "nu",      "xi",         "pi",     "varpi",  "rho",      "varrho",
      "sigma",  "varsigma", "tau",       "upsilon", "phi",   "varphi",     "chi",    "psi",    "omega"};
  static const std::array<const char*, 11> upper = {"Gamma", "Delta",   "Theta", "Lambda", "Xi",   "Pi",
                                                    "Sigma", "Upsilon", "Phi",   "Psi",    "Omega"};
  // Capitals without a LaTeX letter are drawn like Latin ones.
  static const std::array<std::pair<const char*, const char*>, 14> latin = {{{"Alpha", "A"},
                                                                             {"Beta", "B"},
                                                                             {"Epsilon", "E"},
                                                                             {"Zeta", "Z"},
                                                                             {"Eta", "H"},
                                                                             {"Iota", "I"},
                                                                             {"Kappa", "K"},
                                                                             {"Mu", "M"},
                                                                             {"Nu", "N"},
                                                                             {"Omicron", "O"},
                                                                             {"omicron", "o"},
                                                                             {"Rho", "P"},
                                                                             {"Tau", "T"},
                                                                             {"Chi", "X"}}};
  if (w == "th") return "\\theta";
  for (const auto& [name, letter] : latin)
    if (w == name) return letter;
  for (const char* g : lower)
    if (w == g) return std::string("\\") + g;
  for (const char* g : upper)
    if (w == g) return std::string("\\") + g;
  return "";
}

/// Any character but a letter or a digit is dropped from upright text (identifiers hold
/// none but '_', which is escaped).
std::string upright(const std::string& w) {
  std::string out;
  for (char c : w) {
    if (c == '_') out += "\\_";
    else if (is_alpha(c) || is_digit(c)) out += c;
  }
  return "\\mathrm{" + out + "}";
}

/// A word without '_' used as a subscript item: a number, a Greek letter, one letter,
/// either of these with a number (b1 -> b_{1}), or upright text.
std::string word_text(const std::string& w) {
  if (all_of(w, is_digit) || (w.size() == 1 && is_alpha(w[0]))) return w;
  if (const std::string g = greek(w); !g.empty()) return g;
  std::size_t k = w.size();
  while (k > 0 && is_digit(w[k - 1])) --k;
  if (k > 0 && k < w.size()) {
    const std::string head = w.substr(0, k), g = greek(head);
    if (head.size() == 1 || !g.empty()) return (g.empty() ? head : g) + "_{" + w.substr(k) + "}";
  }
  return upright(w);
}

/// One identifier: 'head' ('_' part)*, the head's trailing digits a subscript.
///   th1 -> \theta_{1}; m_3 -> m_{3}; mUL -> m_{UL}; Im -> I_{m}; m_crank -> m_{crank}
Symbol identifier_symbol(const std::string& id) {
  std::vector<std::string> parts{""};
  for (char c : id) {
    if (c == '_') parts.emplace_back();
    else parts.back() += c;
  }
  for (const auto& p : parts)
    if (p.empty()) return {upright(id), {}};  // _x, a__b, x_: no reading, as written
  std::string head = parts[0];
  std::size_t k = head.size();
  while (k > 0 && is_digit(head[k - 1])) --k;
  if (k == 0) return {upright(id), {}};
  const std::string digits = head.substr(k);
  head.resize(k);
  Symbol s;
  const std::string rest = head.substr(1);
  if (const std::string g = greek(head); !g.empty()) {
    s.stem = g;
  } else if (head.size() == 1) {
    s.stem = head;
  } else if (head.size() == 2 && is_alpha(head[0]) && is_alpha(head[1])) {
    s.stem = head.substr(0, 1);  // Im, bm, mL: a letter and a one-letter tag
    s.sub.push_back(rest);
  } else if (is_lower(head[0]) && rest.size() <= 3 && all_of(rest, is_upper)) {
    s.stem = head.substr(0, 1);  // mUL, aBR: a letter and a capital tag
    s.sub.push_back(upright(rest));
  } else {
    s.stem = upright(head);
  }
  if (!digits.empty()) s.sub.push_back(digits);
  for (std::size_t i = 1; i < parts.size(); ++i) s.sub.push_back(word_text(parts[i]));
  return s;
}

/// A body or subsystem name in a subscript: a label, not a symbol. crank -> crank,
/// b -> b, b1 -> b_{1}, crank_2 (from crank[2]) -> crank_{2}, motor_left -> motor\_left.
std::string qualifier_text(const std::string& name) {
  const auto cut = name.find('_');
  if (cut == std::string::npos) return word_text(name);
  if (cut == 0) return upright(name);
  std::string index;
  for (std::size_t i = cut; i < name.size(); ++i) {
    if (name[i] == '_' && i + 1 < name.size() && name[i + 1] != '_') index += index.empty() ? "" : ",";
    else if (is_digit(name[i])) index += name[i];
    else return upright(name);  // a word after '_' (or '__'): the name as written
  }
  return word_text(name.substr(0, cut)) + "_{" + index + "}";
}

std::string join_sub(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& it : items) out += (out.empty() ? "" : ",") + it;
  return out;
}

std::string text_of(const Symbol& s) { return s.sub.empty() ? s.stem : s.stem + "_{" + join_sub(s.sub) + "}"; }

/// The letter with k dots (k primes): \dot, \ddot, \dddot; more as a braced ^{(k)}.
std::string dotted(const std::string& stem, int k) {
  switch (k) {
    case 0: return stem;
    case 1: return "\\dot{" + stem + "}";
    case 2: return "\\ddot{" + stem + "}";
    case 3: return "\\dddot{" + stem + "}";
    default: return "{" + stem + "^{(" + std::to_string(k) + ")}}";
  }
}

/// Splits the primes off a name: "w1''" -> {"w1", 2}.
std::pair<std::string, int> strip_primes(const std::string& name) {
  std::size_t k = name.size();
  while (k > 0 && name[k - 1] == '\'') --k;
  return {name.substr(0, k), static_cast<int>(name.size() - k)};
}

}  // namespace

std::string latex_symbol(const std::string& name) {
  const auto [bare, primes] = strip_primes(name);
  std::vector<std::string> segments{""};
  for (char c : bare) {
    if (c == '.') segments.emplace_back();
    else segments.back() += c;
  }
  // q1_dot (the default name of a joint coordinate's rate) is the rate of q1: one more dot.
  int dots = primes;
  std::string last = segments.back();
  const std::string suffix = "_dot";
  if (last.size() > suffix.size() && last.compare(last.size() - suffix.size(), suffix.size(), suffix) == 0 &&
      is_alpha(last[0])) {
    last.resize(last.size() - suffix.size());
    ++dots;
  }
  Symbol base = identifier_symbol(last);
  std::vector<std::string> sub;
  for (std::size_t i = 0; i + 1 < segments.size(); ++i) sub.push_back(qualifier_text(segments[i]));
  sub.insert(sub.end(), base.sub.begin(), base.sub.end());
  base.stem = dotted(base.stem, dots);
  base.sub = sub;
  return text_of(base);
}

std::string latex_symbol(const std::string& name, const std::map<std::string, std::string>& overrides) {
  const auto [bare, primes] = strip_primes(name);
  const auto it = overrides.find(bare);
  if (it == overrides.end()) return latex_symbol(name);
  if (primes > 0) return dotted(it->second, primes);
  // x^{*} followed by ^{2}, or x' by ^{2}, would be a double superscript: brace them.
  const bool scripts = it->second.find_first_of("^_'") != std::string::npos;
  return scripts ? "{" + it->second + "}" : it->second;
}

std::string latex_call(const std::string& function, const std::string& args) {
  if (function == "abs") return "\\left|" + args + "\\right|";
  static const std::array<std::pair<const char*, const char*>, 14> known = {{{"sin", "\\sin"},
                                                                            {"cos", "\\cos"},
                                                                            {"tan", "\\tan"},
                                                                            {"sinh", "\\sinh"},
                                                                            {"cosh", "\\cosh"},
                                                                            {"tanh", "\\tanh"},
                                                                            {"asin", "\\arcsin"},
                                                                            {"acos", "\\arccos"},
                                                                            {"atan", "\\arctan"},
                                                                            {"exp", "\\exp"},
                                                                            {"log", "\\ln"},
                                                                            {"sqrt", "\\sqrt"},
                                                                            {"atan2", "\\operatorname{atan2}"},
                                                                            {"pow", "\\operatorname{pow}"}}};
  std::string op;
  for (const auto& [name, text] : known)
    if (function == name) op = text;
  if (op == "\\sqrt") return "\\sqrt{" + args + "}";
  if (op.empty()) op = "\\operatorname{" + upright(function).substr(8);  // \mathrm{x} -> x}
  return op + "\\left(" + args + "\\right)";
}

}  // namespace mbsc::print
