// SPDX-License-Identifier: GPL-2.0-or-later
/// Is the text of a `latex` statement safe in a formula? (latex_text.hpp)
///
/// An allow-list, not a deny-list: the text goes into a document the user compiles, and
/// engines such as lualatex run code (\directlua) or touch files from commands. So only
/// printable ASCII, and only the commands a symbol needs, all of them in LaTeX itself or
/// amsmath (the package of `--standalone`): Greek letters, math fonts, accents, a few
/// symbols, spacing, \text{words} without commands, and \left ... \right pairs, each pair
/// inside one brace group. No character that ends the formula or the line ($ %), starts
/// an alignment cell (&) or a macro parameter (#); balanced braces; a ^ or _, an accent
/// or a font with something to apply to.
#include "mbsc/parse/latex_text.hpp"

#include <cctype>
#include <set>
#include <vector>

namespace mbsc::parse {
namespace {

constexpr std::size_t kMaxLength = 200;

bool is_letter(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); }

/// Commands that stand for a symbol on their own.
const std::set<std::string>& symbol_commands() {
  static const std::set<std::string> words = {
      // Greek letters, their variants (amsmath has the slanted capitals \varGamma ...)
      "alpha", "beta", "gamma", "delta", "epsilon", "varepsilon", "zeta", "eta", "theta", "vartheta", "iota", "kappa",
      "lambda", "mu", "nu", "xi", "pi", "varpi", "rho", "varrho", "sigma", "varsigma", "tau", "upsilon", "phi", "varphi",
      "chi", "psi", "omega", "Gamma", "Delta", "Theta", "Lambda", "Xi", "Pi", "Sigma", "Upsilon", "Phi", "Psi", "Omega",
      "varGamma", "varDelta", "varTheta", "varLambda", "varXi", "varPi", "varSigma", "varUpsilon", "varPhi", "varPsi",
      "varOmega",
      // letters and marks
      "prime", "ell", "hbar", "imath", "jmath", "partial", "nabla", "infty", "emptyset", "aleph",
      // operators a tag may carry
      "cdot", "times", "ast", "star", "circ", "bullet", "dagger", "ddagger", "pm", "mp", "perp", "parallel",
      // spacing
      "quad", "qquad"};
  return words;
}

/// Commands that apply to what follows them (a letter or a brace group).
const std::set<std::string>& argument_commands() {
  static const std::set<std::string> words = {
      "mathrm", "mathbf", "mathit", "mathsf", "mathtt", "mathcal", "boldsymbol", "operatorname",
      "bar", "hat", "dot", "ddot", "dddot", "tilde", "vec", "breve", "check", "acute", "grave",
      "widehat", "widetilde", "overline", "underline"};
  return words;
}

/// Delimiter commands after \left or \right.
const std::set<std::string>& delimiter_commands() {
  static const std::set<std::string> words = {"langle", "rangle", "lvert", "rvert", "lVert", "rVert",
                                              "lfloor", "rfloor", "lceil", "rceil", "vert", "Vert"};
  return words;
}

/// Control symbols allowed in math: spacing (\, \; \: \! \> and \ ) and escaped
/// characters (\{ \} \| \_ \% \$ \# \&).
bool allowed_control_symbol(char c) {
  for (char ok : std::string(",;:!> {}|_%$#&"))
    if (c == ok) return true;
  return false;
}

/// Reads the text one element at a time; each check returns why the text is refused.
class Checker {
 public:
  explicit Checker(const std::string& text) : s_(text) {}

  std::string run() {
    for (i_ = 0; i_ < s_.size(); ++i_)
      if (std::string why = step(); !why.empty()) return why;
    if (lefts_.size() > 1) return "it has a '{' that is not closed";
    if (lefts_.back() > 0) return "it has a '\\left' without its '\\right'";
    return "";
  }

 private:
  /// The character at i_, and what comes with it.
  std::string step() {
    const char c = s_[i_];
    const unsigned char u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7F) return "it has a control character";
    if (u >= 0x80) return "it has a character outside ASCII (write a command such as \\theta)";
    switch (c) {
      case '$': return "it has '$', which would end the formula";
      case '%': return "it has '%', which would comment out the rest of the line";
      case '&': return "it has '&', which would start a new matrix cell";
      case '#': return "it has '#'";
      case '{': lefts_.push_back(0); return "";
      case '}':
        if (lefts_.size() == 1) return "it has a '}' without its '{'";
        if (lefts_.back() > 0) return "it has a '\\left' whose '\\right' is not in the same brace group";
        lefts_.pop_back();
        return "";
      case '^':
      case '_':
        if (!operand_follows(i_ + 1)) return std::string("it has a '") + c + "' with nothing after it to apply to";
        return "";
      case '\\': return command();
      default: return "";
    }
  }

  /// Is there something for a ^, _, accent or font at j (spaces skipped)?
  bool operand_follows(std::size_t j) const {
    while (j < s_.size() && s_[j] == ' ') ++j;
    return j < s_.size() && s_[j] != '}' && s_[j] != '^' && s_[j] != '_';
  }

  /// The command name starting after the backslash at j, or "" for a control symbol.
  std::string word_at(std::size_t j) const {
    std::size_t k = j + 1;
    while (k < s_.size() && is_letter(s_[k])) ++k;
    return s_.substr(j + 1, k - j - 1);
  }

  /// A backslash at i_: a control symbol or a command of the allow-list.
  std::string command() {
    if (i_ + 1 == s_.size()) return "it ends with a lone '\\'";
    const char next = s_[i_ + 1];
    if (next == '\\') return "it has '\\\\', a line break";
    if (!is_letter(next)) {
      if (!allowed_control_symbol(next)) return std::string("it has '\\") + next + "', which is not for formulas";
      ++i_;  // an escaped brace counts for nothing
      return "";
    }
    const std::string word = word_at(i_);
    i_ += word.size();  // on the command's last letter
    if (symbol_commands().count(word)) return "";
    if (argument_commands().count(word)) {
      if (!operand_follows(i_ + 1)) return "it has '\\" + word + "' with nothing after it to apply to";
      return "";
    }
    if (word == "text") return text_argument();
    if (word == "left") {
      ++lefts_.back();
      return delimiter("left");
    }
    if (word == "right") {
      if (lefts_.back() == 0) return "it has a '\\right' without its '\\left' in the same brace group";
      --lefts_.back();
      return delimiter("right");
    }
    return "it has '\\" + word + "', which is not a command for symbols (see \"Symbols in LaTeX\" in docs/language.md)";
  }

  /// The delimiter after \left or \right (i_ on the command's last letter).
  std::string delimiter(const std::string& which) {
    std::size_t j = i_ + 1;
    while (j < s_.size() && s_[j] == ' ') ++j;
    const std::string bad = "it has '\\" + which + "' without a delimiter after it such as ( [ | . or \\langle";
    if (j == s_.size()) return bad;
    if (std::string("()[]|./").find(s_[j]) != std::string::npos) {
      i_ = j;
      return "";
    }
    if (s_[j] != '\\' || j + 1 == s_.size()) return bad;
    if (s_[j + 1] == '{' || s_[j + 1] == '}' || s_[j + 1] == '|') {
      i_ = j + 1;
      return "";
    }
    const std::string word = word_at(j);
    if (!delimiter_commands().count(word)) return bad;
    i_ = j + word.size();
    return "";
  }

  /// \text{words}: letters, digits, spaces and punctuation, no command, brace, ^ or _
  /// (text mode has no math, and the allow-list would not hold inside it).
  std::string text_argument() {
    std::size_t j = i_ + 1;
    while (j < s_.size() && s_[j] == ' ') ++j;
    if (j == s_.size() || s_[j] != '{') return "it has '\\text' without '{words}' after it";
    for (++j; j < s_.size() && s_[j] != '}'; ++j) {
      const unsigned char u = static_cast<unsigned char>(s_[j]);
      if (u < 0x20 || u >= 0x7F) return "it has a character in '\\text{...}' that is not printable ASCII";
      if (std::string("\\{^_$%&#~").find(s_[j]) != std::string::npos)
        return std::string("it has '") + s_[j] + "' in '\\text{...}', which takes plain words only";
    }
    if (j == s_.size()) return "it has a '{' that is not closed";
    i_ = j;
    return "";
  }

  const std::string& s_;
  std::size_t i_ = 0;
  std::vector<int> lefts_{0};  // per open brace group (the text itself first): its open \left
};

}  // namespace

std::string latex_text_problem(const std::string& text) {
  if (text.empty()) return "it is empty";
  if (text.size() > kMaxLength) return "it is longer than " + std::to_string(kMaxLength) + " characters";
  return Checker(text).run();
}

}  // namespace mbsc::parse
