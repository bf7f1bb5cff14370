// SPDX-License-Identifier: GPL-2.0-or-later
// `for` loops and `name[index]`, expanded on tokens (see loop_expansion.hpp).
#include "loop_expansion.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>

#include "mbsc/diag/activity.hpp"
#include "mbsc/diag/limits.hpp"

namespace mbsc::parse {
namespace {

constexpr long kMaxIterations = 10000;   // one loop
constexpr long kMaxExpanded = 100000;    // all loops together (nested ones multiply)
constexpr long kMaxValue = 1000000000;   // bounds, indices and every value on the way

bool ends_statement(TokenKind k) {
  return k == TokenKind::Comma || k == TokenKind::Newline || k == TokenKind::Semicolon || k == TokenKind::End ||
         k == TokenKind::RBrace;
}

class Expander {
 public:
  Expander(const std::vector<Token>& t, Diagnostics& d, const std::map<std::string, double>& overrides,
           std::map<std::string, double>& structural)
      : t_(t), diags_(d), overrides_(overrides), structural_(structural) {}

  std::vector<Token> run() {
    match_brackets();
    collect_parameters();
    std::vector<Token> out;
    if (!expand(0, t_.size() - 1, {}, out)) return t_;  // errors reported; the parse stops
    out.push_back(t_.back());                             // End
    return out;
  }

 private:
  using Env = std::map<std::string, long>;

  /// `parameter a = <number>, ...`: the parameters a bound or an index may use.
  void collect_parameters() {
    for (std::size_t i = 0; i + 1 < t_.size(); ++i) {
      if (t_[i].kind != TokenKind::Keyword || t_[i].text != "parameter") continue;
      std::size_t j = i + 1;
      while (j + 2 < t_.size() && t_[j].kind == TokenKind::Ident && t_[j + 1].kind == TokenKind::Equals) {
        std::size_t k = j + 2;
        const double sign = t_[k].kind == TokenKind::Minus ? -1.0 : 1.0;
        if (sign < 0) ++k;
        const auto ov = overrides_.find(t_[j].text);
        if (ov != overrides_.end()) params_[t_[j].text] = ov->second;
        else if (t_[k].kind == TokenKind::Number && k + 1 < t_.size() && ends_statement(t_[k + 1].kind))
          params_[t_[j].text] = sign * std::strtod(t_[k].text.c_str(), nullptr);  // inf when out of range
        // Skip to the next ',' of this statement (parentheses may hold commas).
        int depth = 0;
        while (k < t_.size() && !(depth == 0 && ends_statement(t_[k].kind))) {
          depth += t_[k].kind == TokenKind::LParen ? 1 : t_[k].kind == TokenKind::RParen ? -1 : 0;
          ++k;
        }
        if (k >= t_.size() || t_[k].kind != TokenKind::Comma) break;
        j = k + 1;
      }
    }
  }

  void emit(std::vector<Token>& out, Token tok) {
    // Repeated bodies meet at line ends: one newline is enough.
    if (tok.kind == TokenKind::Newline && !out.empty() && out.back().kind == TokenKind::Newline) return;
    if (out.size() >= limits::kMaxExpandedTokens) {
      if (!too_long_)
        diags_.error(tok.pos, fmt::format("the loops expand this file to more than {} tokens",
                                          limits::kMaxExpandedTokens));
      too_long_ = true;
      return;
    }
    out.push_back(std::move(tok));
  }

  void emit_number(std::vector<Token>& out, long v, const SourcePos& pos) {
    if (v >= 0) return emit(out, {TokenKind::Number, std::to_string(v), pos});
    emit(out, {TokenKind::LParen, "(", pos});
    emit(out, {TokenKind::Minus, "-", pos});
    emit(out, {TokenKind::Number, std::to_string(-v), pos});
    emit(out, {TokenKind::RParen, ")", pos});
  }

  /// Adds `steps` tokens of scanning to the work done; false (reported once) past the limit.
  bool spend(std::size_t steps, const Token& at) {
    work_ += steps;
    if (work_ <= 4 * limits::kMaxExpandedTokens) return true;
    if (!too_long_)
      diags_.error(at.pos, fmt::format("the loops of this file take more than {} steps to expand",
                                       4 * limits::kMaxExpandedTokens));
    too_long_ = true;
    return false;
  }

  /// Pairs every '[' with its ']' and every '{' with its '}' once (each kind on its own,
  /// as a scan from the opening token would), so that a loop nested in loops is not
  /// rescanned on every repetition of the outer ones.
  void match_brackets() {
    match_.assign(t_.size(), std::string::npos);
    std::vector<std::size_t> brackets, braces;
    for (std::size_t i = 0; i < t_.size(); ++i) {
      const TokenKind k = t_[i].kind;
      if (k == TokenKind::LBracket) brackets.push_back(i);
      if (k == TokenKind::LBrace) braces.push_back(i);
      if (k == TokenKind::RBracket && !brackets.empty()) {
        match_[brackets.back()] = i;
        brackets.pop_back();
      }
      if (k == TokenKind::RBrace && !braces.empty()) {
        match_[braces.back()] = i;
        braces.pop_back();
      }
    }
  }

  /// The index of the token closing the bracket or brace opened at `open` before `end`, or npos.
  std::size_t closing(std::size_t open, std::size_t end) const {
    const std::size_t c = match_[open];
    return c < end ? c : std::string::npos;
  }

  bool expand(std::size_t b, std::size_t e, const Env& env, std::vector<Token>& out) {
    for (std::size_t i = b; i < e;) {
      if (too_long_) return false;
      const Token& tok = t_[i];
      if (tok.kind == TokenKind::Keyword && tok.text == "for") {
        const std::size_t next = expand_for(i, e, env, out);
        if (next == std::string::npos) return false;
        i = next;
        continue;
      }
      if (tok.kind == TokenKind::Ident && i + 1 < e && t_[i + 1].kind == TokenKind::LBracket) {
        const std::size_t close = closing(i + 1, e);
        if (close == std::string::npos) {
          diags_.error(t_[i + 1].pos, fmt::format("'[' after '{}' is not closed with ']'", tok.text));
          return false;
        }
        if (!spend(close - i, tok)) return false;
        auto v = evaluate(i + 2, close, env, fmt::format("index of '{}'", tok.text), t_[i + 1].pos);
        if (!v) return false;
        emit(out, {TokenKind::Ident, fmt::format("{}_{}", tok.text, *v), tok.pos});
        i = close + 1;
        continue;
      }
      if (tok.kind == TokenKind::LBracket && i > 0 && t_[i - 1].kind == TokenKind::Keyword) {
        // `body mass[i]`: the name is a keyword, which an index does not make a name.
        diags_.error(t_[i - 1].pos, fmt::format("'{}' is a keyword and cannot be used as a name, indexed or not",
                                                t_[i - 1].text));
        return false;
      }
      if (tok.kind == TokenKind::LBracket || tok.kind == TokenKind::RBracket) {
        diags_.error(tok.pos, fmt::format("'{}' belongs after a name, as in crank[i]", tok.text));
        return false;
      }
      const bool after_dot = i > 0 && t_[i - 1].kind == TokenKind::Dot;
      if (tok.kind == TokenKind::Ident && !after_dot) {
        auto it = env.find(tok.text);
        if (it != env.end()) {
          emit_number(out, it->second, tok.pos);
          ++i;
          continue;
        }
      }
      emit(out, tok);
      ++i;
    }
    return !too_long_;
  }

  // 'for' IDENT '=' intexpr 'to' intexpr '{' tokens '}'
  std::size_t expand_for(std::size_t i, std::size_t e, const Env& env, std::vector<Token>& out) {
    const Token& kw = t_[i];
    if (i + 2 >= e || t_[i + 1].kind != TokenKind::Ident || t_[i + 2].kind != TokenKind::Equals) {
      diags_.error(kw.pos, "expected 'for NAME = FIRST to LAST { ... }'");
      return std::string::npos;
    }
    const std::string var = t_[i + 1].text;
    if (loop_depth_ >= limits::kMaxLoopNesting) {
      diags_.error(kw.pos, fmt::format("loop over '{}': loops nest more than {} deep", var, limits::kMaxLoopNesting));
      return std::string::npos;
    }
    std::size_t to = i + 3, open = std::string::npos;
    while (to < e && !(t_[to].kind == TokenKind::Ident && t_[to].text == "to") && t_[to].kind != TokenKind::LBrace &&
           t_[to].kind != TokenKind::Newline)
      ++to;
    if (to >= e || t_[to].kind != TokenKind::Ident) {
      diags_.error(kw.pos, fmt::format("loop over '{}': expected 'for {} = FIRST to LAST {{ ... }}'", var, var));
      return std::string::npos;
    }
    open = to + 1;
    while (open < e && t_[open].kind != TokenKind::LBrace && t_[open].kind != TokenKind::Newline) ++open;
    if (open >= e || t_[open].kind != TokenKind::LBrace) {
      diags_.error(kw.pos, fmt::format("loop over '{}': expected '{{' after the last value", var));
      return std::string::npos;
    }
    const std::size_t close = closing(open, e);
    if (close == std::string::npos) {
      diags_.error(t_[open].pos, fmt::format("loop over '{}': '{{' is not closed with '}}'", var));
      return std::string::npos;
    }
    // The head (FIRST to LAST) is scanned and evaluated on every repetition of the loops
    // around it: count that work too, or a long head in a long loop would take forever.
    if (!spend(open - i, kw)) return std::string::npos;
    auto first = evaluate(i + 3, to, env, fmt::format("first value of '{}'", var), t_[i + 2].pos);
    auto last = first ? evaluate(to + 1, open, env, fmt::format("last value of '{}'", var), t_[to].pos) : std::nullopt;
    if (!first || !last) return std::string::npos;
    if (*last - *first >= kMaxIterations) {
      diags_.error(kw.pos, fmt::format("loop over '{}' runs {} times; at most {} are allowed", var, *last - *first + 1,
                                       kMaxIterations));
      return std::string::npos;
    }
    // A loop that runs no time still counts once: skipping it is work too.
    if ((expanded_ += std::max(1L, *last - *first + 1)) > kMaxExpanded) {
      diags_.error(kw.pos, fmt::format("loop over '{}': the loops expand to more than {} repetitions in all", var,
                                       kMaxExpanded));
      return std::string::npos;
    }
    ++loop_depth_;
    for (long v = *first; v <= *last; ++v) {
      // Outer loops report their progress (and meet the time budget) once per repetition.
      if (loop_depth_ == 1)
        checkpoint("expanding", fmt::format("loop over '{}'", var), kw.pos, static_cast<std::size_t>(v - *first),
                   static_cast<std::size_t>(*last - *first + 1));
      Env inner = env;
      inner[var] = v;
      if (!expand(open + 1, close, inner, out)) {
        --loop_depth_;
        return std::string::npos;
      }
    }
    --loop_depth_;
    return close + 1;
  }

  // ---- integer expressions: + - * / ( ), numbers, loop variables, parameters ----

  std::optional<long> evaluate(std::size_t b, std::size_t e, const Env& env, const std::string& what, const SourcePos& at) {
    if (b >= e) {
      diags_.error(at, fmt::format("the {} is missing", what));
      return std::nullopt;
    }
    pos_ = b;
    end_ = e;
    env_ = &env;
    what_ = what;
    failed_ = false;
    depth_ = 0;
    const long v = sum();
    if (!failed_ && pos_ != end_) fail(t_[pos_], fmt::format("unexpected {}", describe(t_[pos_])));
    if (failed_) return std::nullopt;
    return v;
  }

  void fail(const Token& at, const std::string& why) {
    if (!failed_)
      diags_.error(at.pos, fmt::format("the {} must be a whole number made of numbers, loop variables and parameters "
                                       "with a number default: {}",
                                       what_, why));
    failed_ = true;
  }

  /// Every value stays within +-1e9, so sums and products of two never overflow.
  long bounded(long v, const Token& at) {
    if (v > kMaxValue || v < -kMaxValue) {
      fail(at, fmt::format("{} is out of range (at most {} in magnitude)", v, kMaxValue));
      return 0;
    }
    return v;
  }

  long sum() {
    long v = product();
    while (!failed_ && pos_ < end_ && (t_[pos_].kind == TokenKind::Plus || t_[pos_].kind == TokenKind::Minus)) {
      const Token& op = t_[pos_++];
      const long r = product();
      v = bounded(op.kind == TokenKind::Plus ? v + r : v - r, op);
    }
    return v;
  }

  long product() {
    long v = factor();
    while (!failed_ && pos_ < end_ && (t_[pos_].kind == TokenKind::Star || t_[pos_].kind == TokenKind::Slash)) {
      const Token& op = t_[pos_++];
      const long r = factor();
      if (op.kind == TokenKind::Star) {
        v = bounded(v * r, op);
      } else if (r == 0 || v % r != 0) {
        fail(op, fmt::format("{} / {} is not a whole number", v, r));
      } else {
        v /= r;
      }
    }
    return v;
  }

  long factor() {
    if (pos_ >= end_) {
      fail(t_[end_ - 1], "it ends early");
      return 0;
    }
    const Token& tok = t_[pos_++];
    if (depth_ >= limits::kMaxNesting) {
      fail(tok, fmt::format("it nests more than {} deep", limits::kMaxNesting));
      return 0;
    }
    struct Deeper {
      int& d;
      explicit Deeper(int& depth) : d(++depth) {}
      ~Deeper() { --d; }
    } deeper(depth_);
    switch (tok.kind) {
      case TokenKind::Minus:
        return -factor();
      case TokenKind::LParen: {
        const long v = sum();
        if (pos_ >= end_ || t_[pos_].kind != TokenKind::RParen) fail(tok, "'(' is not closed");
        else ++pos_;
        return v;
      }
      case TokenKind::Number: {
        const double d = std::strtod(tok.text.c_str(), nullptr);  // inf when out of range: not whole
        if (d != std::floor(d) || std::abs(d) > static_cast<double>(kMaxValue)) {
          fail(tok, fmt::format("{} is not a whole number of at most {} in magnitude", tok.text, kMaxValue));
          return 0;
        }
        return static_cast<long>(d);
      }
      case TokenKind::Ident: {
        if (auto it = env_->find(tok.text); it != env_->end()) return it->second;
        if (auto it = params_.find(tok.text); it != params_.end()) {
          if (it->second != std::floor(it->second) || std::abs(it->second) > static_cast<double>(kMaxValue)) {
            fail(tok, fmt::format("parameter '{}' is {}", tok.text, it->second));
            return 0;
          }
          structural_[tok.text] = it->second;
          return static_cast<long>(it->second);
        }
        fail(tok, fmt::format("'{}' is not a loop variable or a parameter with a number default declared in this file",
                              tok.text));
        return 0;
      }
      case TokenKind::Invalid:  // a lexical error: its own message
        fail(tok, tok.text);
        return 0;
      default:
        fail(tok, fmt::format("unexpected {}", describe(tok)));
        return 0;
    }
  }

  const std::vector<Token>& t_;
  Diagnostics& diags_;
  const std::map<std::string, double>& overrides_;
  std::map<std::string, double>& structural_;
  std::map<std::string, double> params_;
  std::vector<std::size_t> match_;  // index of the matching ']' or '}' of each '[' and '{'
  long expanded_ = 0;  // repetitions made so far, over all loops
  std::size_t work_ = 0;  // tokens of loop heads and indices scanned so far
  int loop_depth_ = 0;   // `for` loops open around the tokens being expanded
  bool too_long_ = false;  // the output reached limits::kMaxExpandedTokens (reported)
  // State of the expression being evaluated.
  std::size_t pos_ = 0, end_ = 0;
  const Env* env_ = nullptr;
  std::string what_;
  bool failed_ = false;
  int depth_ = 0;  // nesting of '(' and unary '-' in the expression being evaluated
};

}  // namespace

std::vector<Token> expand_loops(const std::vector<Token>& tokens, Diagnostics& diags,
                                const std::map<std::string, double>& overrides,
                                std::map<std::string, double>& structural) {
  return Expander(tokens, diags, overrides, structural).run();
}

}  // namespace mbsc::parse
