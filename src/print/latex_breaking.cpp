// SPDX-License-Identifier: GPL-2.0-or-later
/// How wide a formula sets, and where it breaks into lines (latex_layout.hpp): widths are
/// estimated from Computer Modern's glyphs at 10pt, so that the layout can keep every
/// line of a displayed formula inside the text width.
#include <algorithm>
#include <cctype>
#include <string>
#include <vector>

#include "mbsc/print/latex_layout.hpp"

namespace mbsc::print::latex_layout_detail {
namespace {

bool is_letter(char c) { return std::isalpha(static_cast<unsigned char>(c)) != 0; }

/// The command word that starts at text[i] == '\\' ("" for a control symbol such as \,).
std::string command_at(const std::string& text, std::size_t i) {
  std::size_t j = i + 1;
  while (j < text.size() && is_letter(text[j])) ++j;
  return text.substr(i + 1, j - i - 1);
}

// Glyph widths (pt at 10pt) of cmmi10 (math italic) and cmr10 (upright), a to z.
constexpr double kItalic[26] = {5.3, 4.3, 4.3, 5.2, 4.7, 4.9, 4.8, 5.8, 3.5, 4.1, 5.2, 3.0, 8.8,
                                6.0, 4.9, 5.0, 4.6, 4.5, 4.7, 3.6, 5.7, 4.9, 7.2, 5.7, 4.9, 4.7};
constexpr double kUpright[26] = {5.0, 5.6, 4.4, 5.6, 4.4, 3.1, 5.0, 5.6, 2.8, 3.1, 5.3, 2.8, 8.3,
                                 5.6, 5.0, 5.6, 5.3, 3.9, 3.9, 3.9, 5.6, 5.3, 7.2, 5.3, 5.3, 4.4};

double glyph(char c, bool upright) {
  if (c >= 'a' && c <= 'z') return upright ? kUpright[c - 'a'] : kItalic[c - 'a'];
  if (c >= 'A' && c <= 'Z') return upright ? 7.4 : 7.9;
  if (c >= '0' && c <= '9') return 5.0;
  switch (c) {
    case '+': return 12.2;  // a binary operator and its spaces
    case '=': case '<': case '>': return 13.4;
    case '(': case ')': case '[': case ']': return 3.9;
    case ',': return 4.5;
    case '.': case '|': case '\'': case '!': case ';': case ':': return 2.8;
    case '/': return 5.0;
    case ' ': case '&': return 0.0;
    default: return 5.5;
  }
}

/// A recursive reader of a formula: the width of a group, at a script scale.
class Measure {
 public:
  explicit Measure(const std::string& s) : s_(s) {}
  double all() {
    double w = 0;
    while (i_ < s_.size()) w += group(1.0, false, true);
    return w;
  }

 private:
  /// The next item (upright: \mathrm-like letters); a '}' ends a group (top: skipped).
  double group(double scale, bool upright, bool top) {
    double w = 0;
    while (i_ < s_.size()) {
      const char c = s_[i_];
      if (c == '}') {
        ++i_;
        if (!top) return w;
        continue;
      }
      w += item(scale, upright);
    }
    return w;
  }

  /// One braced group or one token.
  double argument(double scale, bool upright) {
    while (i_ < s_.size() && s_[i_] == ' ') ++i_;
    if (i_ < s_.size() && s_[i_] == '{') {
      ++i_;
      return group(scale, upright, false);
    }
    return i_ < s_.size() ? item(scale, upright) : 0.0;
  }

  double item(double scale, bool upright) {
    const char c = s_[i_];
    if (c == '{') {
      ++i_;
      return group(scale, upright, false);
    }
    if (c == '^' || c == '_') {
      // A subscript and a superscript stack: the wider counts.
      ++i_;
      const double small = scale > 0.75 ? 0.7 : 0.5;
      double w = argument(scale * small, upright);
      if (i_ < s_.size() && (s_[i_] == '^' || s_[i_] == '_') && s_[i_] != c) {
        ++i_;
        w = std::max(w, argument(scale * small, upright));
      }
      return w;
    }
    if (c == '-') {
      ++i_;
      const bool binary = i_ >= 2 && s_[i_ - 2] == ' ';
      return scale * (binary && scale > 0.75 ? 12.2 : 7.8);
    }
    if (c != '\\') {
      ++i_;
      return scale * (c == '+' && scale <= 0.75 ? 7.8 : glyph(c, upright));
    }
    const std::string word = command_at(s_, i_);
    if (word.empty()) {  // \, \{ ...
      const char k = i_ + 1 < s_.size() ? s_[i_ + 1] : ' ';
      i_ += 2;
      return scale * (k == ',' ? 1.7 : k == ';' ? 2.8 : k == '!' ? -1.7 : k == ' ' ? 3.3 : 5.0);
    }
    i_ += word.size() + 1;
    if (word == "frac") {
      const double a = argument(scale, upright), b = argument(scale, upright);
      return std::max(a, b) + 2.4 * scale;
    }
    if (word == "sqrt") return argument(scale, upright) + 8.3 * scale;
    if (word == "left" || word == "right") {
      if (i_ < s_.size() && s_[i_] == '\\') i_ += 2;  // \left\{
      else ++i_;
      return i_ > 0 && s_[i_ - 1] == '.' ? 1.2 : (word == "left" ? 6.0 : 5.5) * scale;
    }
    if (word == "mathrm" || word == "text" || word == "operatorname" || word == "textrm")
      return argument(scale, true) + (word == "operatorname" ? 1.7 * scale : 0.0);
    if (word == "mathbf") return 1.15 * argument(scale, true);
    if (word == "dot" || word == "ddot" || word == "dddot" || word == "bar" || word == "hat" || word == "tilde" ||
        word == "vec" || word == "overline" || word == "boldsymbol" || word == "mathit")
      return argument(scale, upright);
    static const char* const functions[] = {"sin",    "cos",    "tan",    "ln",     "log",   "exp", "sinh",
                                            "cosh",   "tanh",   "arcsin", "arccos", "arctan"};
    for (const char* f : functions)
      if (word == f) {
        double w = 3.4;  // the thin spaces around an operator
        for (char l : word) w += glyph(l, true);
        return scale * w;
      }
    if (word == "quad") return 10.0 * scale;
    if (word == "qquad") return 20.0 * scale;
    if (word == "cdot") return 7.2 * scale;
    if (word == "times") return 12.2 * scale;
    if (word == "cdots" || word == "ldots" || word == "dots") return 13.4 * scale;
    if (word == "infty") return 10.0 * scale;
    if (word.size() > 1 && std::isupper(static_cast<unsigned char>(word[0]))) return 7.5 * scale;  // \Theta
    return 6.0 * scale;  // a Greek letter, \ell, \partial, ...
  }

  const std::string& s_;
  std::size_t i_ = 0;
};

/// Where a formula may break: before a term's sign (" + ", " - ") or, as a last resort,
/// between factors (a space); never inside braces. Breaks inside a function's argument
/// (\cos\left( ... \right)) are last resorts too.
struct Break {
  std::size_t at;   // the break: the next line starts at `at` (its sign or factor)
  int depth;        // \left ... \right pairs open there
  bool term;        // a term's sign outside function arguments (preferred)
  bool sign;        // a term's sign (else a break between factors)
};

std::vector<Break> breaks_of(const std::string& f) {
  std::vector<Break> out;
  std::vector<bool> left;  // open \left groups: true for a function's argument
  int braces = 0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    const char c = f[i];
    if (c == '\\') {
      const std::string word = command_at(f, i);
      if (word.empty()) {
        ++i;
        continue;
      }
      if (word == "left") left.push_back(i > 0 && (is_letter(f[i - 1]) || f[i - 1] == '}'));
      if (word == "right" && !left.empty()) left.pop_back();
      i += word.size();
      continue;
    }
    if (c == '{') ++braces;
    if (c == '}') --braces;
    if (c != ' ' || braces != 0 || i == 0 || i + 1 >= f.size()) continue;
    bool in_function = false;
    for (bool l : left) in_function = in_function || l;
    const int depth = static_cast<int>(left.size());
    const bool sign = (f[i + 1] == '+' || f[i + 1] == '-') && i + 2 < f.size() && f[i + 2] == ' ';
    if (sign) {
      out.push_back({i + 1, depth, !in_function, true});
      continue;
    }
    // A space between factors: not around a sign or a slash, not an escaped space.
    const char before = f[i - 1];
    if (before == '+' || before == '-' || before == '/' || before == '\\' || before == '=' || f[i + 1] == '/' ||
        f[i + 1] == '=')
      continue;
    out.push_back({i + 1, depth, false, false});
  }
  return out;
}

std::string repeat(const std::string& s, int n) {
  std::string out;
  for (int k = 0; k < n; ++k) out += s;
  return out;
}

/// A brace group starting at f[i] == '{': its end (one past the '}').
std::size_t group_end(const std::string& f, std::size_t i) {
  int depth = 0;
  for (std::size_t k = i; k < f.size(); ++k) {
    if (f[k] == '\\') {
      ++k;
      continue;
    }
    if (f[k] == '{') ++depth;
    if (f[k] == '}' && --depth == 0) return k + 1;
  }
  return f.size();
}

/// `text` is one \left( ... \right) pair from its start to its end.
bool wrapped(const std::string& text) {
  if (text.rfind("\\left(", 0) != 0 || text.size() < 13 || text.compare(text.size() - 7, 7, "\\right)") != 0) return false;
  int depth = 0;
  for (std::size_t k = 0; k + 7 <= text.size(); ++k) {
    if (text.compare(k, 5, "\\left") == 0) ++depth;
    if (text.compare(k, 6, "\\right") == 0 && --depth == 0) return k + 7 == text.size();
  }
  return false;
}

/// `text` in \left( \right) unless it is one atom (no space at the top level) or wrapped already.
std::string parenthesised(const std::string& text) {
  int braces = 0;
  bool spaced = false;
  for (std::size_t k = 0; k < text.size(); ++k) {
    if (text[k] == '\\') {
      ++k;
      continue;
    }
    braces += text[k] == '{' ? 1 : text[k] == '}' ? -1 : 0;
    spaced = spaced || (braces == 0 && text[k] == ' ');
  }
  if (!spaced || wrapped(text)) return text;
  return "\\left(" + text + "\\right)";
}

}  // namespace

double latex_points(const std::string& latex) { return Measure(latex).all(); }

std::string unfold_wide(const std::string& f, double points) {
  std::string out;
  std::size_t i = 0;
  while (i < f.size()) {
    const bool frac = f.compare(i, 6, "\\frac{") == 0;
    const bool root = f.compare(i, 6, "\\sqrt{") == 0;
    if (!frac && !root) {
      if (f[i] == '\\') {  // a command or control symbol, whole
        const std::size_t n = std::max<std::size_t>(command_at(f, i).size(), 1);
        out += f.substr(i, n + 1);
        i += n + 1;
        continue;
      }
      out += f[i++];
      continue;
    }
    const std::size_t a = i + 5, a_end = group_end(f, a);
    const std::size_t b_end = frac ? group_end(f, a_end) : a_end;
    const std::string whole = f.substr(i, b_end - i);
    if (latex_points(whole) <= points) {
      out += whole;
    } else if (root) {
      out += "\\left(" + unfold_wide(f.substr(a + 1, a_end - a - 2), points) + "\\right)^{1/2}";
    } else {
      const std::string num = unfold_wide(f.substr(a + 1, a_end - a - 2), points);
      const std::string den = unfold_wide(f.substr(a_end + 1, b_end - a_end - 2), points);
      out += parenthesised(num) + " / " + parenthesised(den);
    }
    i = b_end;
  }
  return out;
}

std::vector<std::string> break_terms(const std::string& f, double first, double rest) {
  const std::vector<Break> all = breaks_of(f);
  // Widths of the pieces between consecutive breaks (prefix sums), the end a break too.
  std::vector<Break> cuts{{0, 0, true, true}};
  cuts.insert(cuts.end(), all.begin(), all.end());
  cuts.push_back({f.size(), 0, true, true});
  std::vector<double> at(cuts.size(), 0.0);
  for (std::size_t k = 1; k < cuts.size(); ++k) at[k] = at[k - 1] + latex_points(f.substr(cuts[k - 1].at, cuts[k].at - cuts[k - 1].at));
  auto width = [&](std::size_t a, std::size_t b) { return at[b] - at[a] + 1.2 * (cuts[a].depth + cuts[b].depth); };
  // Greedy: the farthest term break that fits and fills the line well, among those the
  // least deep in parentheses (not "(y_{D}" | "- y_{R})" when a break outside them fills
  // the line too); else the farthest break of any kind that fits, else the first one
  // (too wide, unavoidably).
  std::vector<std::size_t> starts{0};
  std::size_t a = 0;
  while (a + 1 < cuts.size()) {
    const double room = starts.size() == 1 ? first : rest;
    std::size_t term = 0, any = 0, shallow = 0;
    int least = 1 << 30;
    std::size_t b = a + 1;
    for (; b < cuts.size() && width(a, b) <= room; ++b) {
      any = b;
      if (!cuts[b].term) continue;
      term = b;
      if (width(a, b) >= 0.5 * room) least = std::min(least, cuts[b].depth);
    }
    for (std::size_t c = a + 1; c < b; ++c)
      if (cuts[c].term && cuts[c].depth == least && width(a, c) >= 0.5 * room) shallow = c;
    std::size_t next = shallow != 0 ? shallow : term != 0 && (width(a, term) >= 0.4 * room || term == any) ? term : any;
    if (next == 0) next = a + 1;
    if (next + 1 < cuts.size()) starts.push_back(next);
    a = next;
  }
  // A short last line (a lone "- \tau_{3}"): balance it with the line before, or join them.
  if (starts.size() >= 2) {
    const std::size_t p = starts[starts.size() - 2], l = starts.back(), end = cuts.size() - 1;
    const double room = starts.size() == 2 ? first : rest;
    if (width(l, end) < 0.25 * rest) {
      if (width(p, end) <= room + 12.0) {
        starts.pop_back();
      } else {
        std::size_t best = l;
        double score = std::min(width(p, l), width(l, end));
        for (std::size_t b = p + 1; b < l; ++b) {
          if (!cuts[b].term || width(p, b) > room || width(b, end) > rest) continue;
          const double s = std::min(width(p, b), width(b, end));
          if (s > score) score = s, best = b;
        }
        starts.back() = best;
      }
    }
  }
  std::vector<std::string> lines;
  for (std::size_t k = 0; k < starts.size(); ++k) {
    const std::size_t s = starts[k], e = k + 1 < starts.size() ? starts[k + 1] : cuts.size() - 1;
    std::string line = repeat("\\left. ", cuts[s].depth) + f.substr(cuts[s].at, cuts[e].at - cuts[s].at);
    while (!line.empty() && line.back() == ' ') line.pop_back();
    line += repeat(" \\right.", cuts[e].depth);
    if (!cuts[s].sign && s != 0) line = "\\cdot " + line;  // a product goes on
    lines.push_back(line);
  }
  return lines;
}

}  // namespace mbsc::print::latex_layout_detail
