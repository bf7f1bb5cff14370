// SPDX-License-Identifier: GPL-2.0-or-later
/// The lexer of the model language: text -> tokens with 1-based line/column positions.
#include "lexer.hpp"

#include <array>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "mbsc/diag/limits.hpp"
#include "mbsc/parse/parse.hpp"

namespace mbsc::parse {

namespace {

constexpr std::array<const char*, 31> statement_keywords = {
    "model",      "parameter", "input",   "gravity", "include", "component",   "subsystem", "body",   "coordinate",
    "speed",      "constraint", "force",  "mass",    "inertia", "kinetic",     "potential", "independent", "alternative",
    "output",     "point",      "com",    "axis",    "ground",  "joint",       "spring",    "damper", "parametrization",
    "latex", "let", "initial", "attitude"};

constexpr std::array<const char*, 5> other_keywords = {"position", "velocity", "nonlinear", "energy", "for"};

bool is_ident_start(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; }
bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_ident_char(char c) { return is_ident_start(c) || is_digit(c); }

/// Walks the text byte by byte, keeping the line and column of the next byte.
/// Columns count characters: UTF-8 continuation bytes do not advance the column.
class Lexer {
 public:
  Lexer(const std::string& text, const std::string& file) : text_(text), file_(file) {}

  std::vector<Token> run() {
    // A UTF-8 byte-order mark (some editors write one) is not part of the text.
    if (text_.compare(0, 3, "\xEF\xBB\xBF") == 0) i_ = 3;
    while (i_ < text_.size()) {
      const char c = text_[i_];
      if (c == '\n') {
        if (!tokens_.empty() && tokens_.back().kind != TokenKind::Newline) {
          SourcePos pos = here();
          if (i_ > 0 && text_[i_ - 1] == '\r') --pos.col;  // CRLF: the line ends at the '\r'
          add(TokenKind::Newline, "", pos);
        }
        advance();
      } else if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
        advance();
      } else if (c == '#') {
        while (i_ < text_.size() && text_[i_] != '\n') advance();
      } else if (is_ident_start(c)) {
        lex_word();
      } else if (is_digit(c) || (c == '.' && i_ + 1 < text_.size() && is_digit(text_[i_ + 1]))) {
        lex_number();
      } else if (c == '"') {
        lex_string();
      } else {
        lex_punct();
      }
    }
    add(TokenKind::End, "", here());
    return std::move(tokens_);
  }

 private:
  SourcePos here() const { return SourcePos{file_, line_, col_}; }

  void advance() {
    const unsigned char c = static_cast<unsigned char>(text_[i_++]);
    if (c == '\n') {
      ++line_;
      col_ = 1;
    } else if ((c & 0xC0) != 0x80) {
      ++col_;
    }
  }

  void add(TokenKind kind, std::string text, const SourcePos& pos) { tokens_.push_back({kind, std::move(text), pos}); }

  void lex_word() {
    const SourcePos pos = here();
    const std::size_t start = i_;
    while (i_ < text_.size() && is_ident_char(text_[i_])) advance();
    std::string word = text_.substr(start, i_ - start);
    const TokenKind kind = is_keyword(word) ? TokenKind::Keyword : TokenKind::Ident;
    add(kind, std::move(word), pos);
  }

  // NUMBER := digits ['.' digits*] [exponent] | '.' digits [exponent]
  // exponent := ('e'|'E') ['+'|'-'] digits
  void lex_number() {
    const SourcePos pos = here();
    const std::size_t start = i_;
    bool ok = true;
    while (i_ < text_.size() && is_digit(text_[i_])) advance();
    if (i_ < text_.size() && text_[i_] == '.') {
      advance();
      while (i_ < text_.size() && is_digit(text_[i_])) advance();
    }
    if (i_ < text_.size() && (text_[i_] == 'e' || text_[i_] == 'E')) {
      advance();
      if (i_ < text_.size() && (text_[i_] == '+' || text_[i_] == '-')) advance();
      if (i_ < text_.size() && is_digit(text_[i_])) {
        while (i_ < text_.size() && is_digit(text_[i_])) advance();
      } else {
        ok = false;
      }
    }
    // A number glued to a name ("2x", "1e3b") is one malformed token, not two.
    while (i_ < text_.size() && (is_ident_char(text_[i_]) || (!ok && text_[i_] == '.'))) {
      ok = false;
      advance();
    }
    std::string lit = text_.substr(start, i_ - start);
    if (!ok) {
      add(TokenKind::Invalid, "malformed number '" + shorten(lit) + "'", pos);
    } else if (lit.size() > limits::kMaxNumberChars) {
      add(TokenKind::Invalid, "number '" + shorten(lit) + "' is longer than " + std::to_string(limits::kMaxNumberChars) +
                                  " characters",
          pos);
    } else if (const char* why = literal_out_of_double_range(lit)) {
      add(TokenKind::Invalid, "number '" + lit + "' " + why, pos);
    } else {
      add(TokenKind::Number, std::move(lit), pos);
    }
  }

  /// A long literal shown in a message: its start and its length.
  static std::string shorten(const std::string& lit) {
    if (lit.size() <= 40) return lit;
    return lit.substr(0, 32) + "... (" + std::to_string(lit.size()) + " characters)";
  }

  // STRING := '"' any character except '"' and newline '"'   (no escapes)
  void lex_string() {
    const SourcePos pos = here();
    advance();  // opening quote
    const std::size_t start = i_;
    while (i_ < text_.size() && text_[i_] != '"' && text_[i_] != '\n') advance();
    if (i_ >= text_.size() || text_[i_] != '"') {
      add(TokenKind::Invalid, "unterminated string", pos);
      return;
    }
    std::string body = text_.substr(start, i_ - start);
    // Control bytes (a NUL would cut a file name short; escapes would reach a terminal).
    for (const char c : body) {
      const unsigned char u = static_cast<unsigned char>(c);
      if (u < 0x20 || u == 0x7F) {
        advance();  // closing quote
        add(TokenKind::Invalid, "control character '" + printable(std::string(1, c)) + "' in a string", pos);
        return;
      }
    }
    advance();  // closing quote
    add(TokenKind::String, std::move(body), pos);
  }

  void lex_punct() {
    const SourcePos pos = here();
    const char c = text_[i_];
    TokenKind kind = TokenKind::Invalid;
    switch (c) {
      case ';': kind = TokenKind::Semicolon; break;
      case ',': kind = TokenKind::Comma; break;
      case ':': kind = TokenKind::Colon; break;
      case '.': kind = TokenKind::Dot; break;
      case '(': kind = TokenKind::LParen; break;
      case ')': kind = TokenKind::RParen; break;
      case '{': kind = TokenKind::LBrace; break;
      case '[': kind = TokenKind::LBracket; break;
      case ']': kind = TokenKind::RBracket; break;
      case '}': kind = TokenKind::RBrace; break;
      case '+': kind = TokenKind::Plus; break;
      case '-': kind = TokenKind::Minus; break;
      case '*': kind = TokenKind::Star; break;
      case '/': kind = TokenKind::Slash; break;
      case '^': kind = TokenKind::Caret; break;
      case '=': kind = TokenKind::Equals; break;
      case '\'': kind = TokenKind::Prime; break;
      default: break;
    }
    if (kind != TokenKind::Invalid) {
      advance();
      add(kind, std::string(1, c), pos);
      return;
    }
    // Unexpected character: take a whole UTF-8 sequence so the message shows it intact.
    const unsigned char u = static_cast<unsigned char>(c);
    std::string shown;
    if (u >= 0xC0) {
      const std::size_t start = i_;
      advance();
      while (i_ < text_.size() && (static_cast<unsigned char>(text_[i_]) & 0xC0) == 0x80) advance();
      shown = text_.substr(start, i_ - start);
    } else {
      advance();
      if (u < 0x20 || u >= 0x7F) {
        char buf[8];
        std::snprintf(buf, sizeof buf, "\\x%02X", static_cast<unsigned>(u));
        shown = buf;
      } else {
        shown = std::string(1, c);
      }
    }
    add(TokenKind::Invalid, "unexpected character '" + shown + "'", pos);
  }

  const std::string& text_;
  const std::string& file_;
  std::size_t i_ = 0;
  int line_ = 1;
  int col_ = 1;
  std::vector<Token> tokens_;
};

}  // namespace

std::vector<Token> lex(const std::string& text, const std::string& file) { return Lexer(text, file).run(); }

const char* literal_out_of_double_range(const std::string& literal) {
  // Model numbers are exact, but the generated code computes in double: a literal a
  // double cannot hold is a mistake (and 1e999999999 would be a huge exact integer).
  const double v = std::strtod(literal.c_str(), nullptr);
  if (std::isinf(v)) return "is too large for a double (at most about 1.8e308)";
  const bool nonzero = literal.find_first_of("123456789") < literal.find_first_of("eE");
  if (nonzero && std::fabs(v) < DBL_MIN) return "is too small for a double (nonzero, but below about 2.2e-308)";
  return nullptr;
}

bool is_statement_keyword(const std::string& word) {
  for (const char* k : statement_keywords)
    if (word == k) return true;
  return false;
}

std::vector<std::string> statement_keyword_list() { return {statement_keywords.begin(), statement_keywords.end()}; }

std::vector<std::string> keyword_list() {
  std::vector<std::string> all = statement_keyword_list();
  all.insert(all.end(), other_keywords.begin(), other_keywords.end());
  return all;
}

bool is_keyword(const std::string& word) {
  if (is_statement_keyword(word)) return true;
  for (const char* k : other_keywords)
    if (word == k) return true;
  return false;
}

std::string describe(const Token& tok) {
  switch (tok.kind) {
    case TokenKind::Ident: return "'" + tok.text + "'";
    case TokenKind::Keyword: return "keyword '" + tok.text + "'";
    case TokenKind::Number: return "number '" + tok.text + "'";
    case TokenKind::String: return "string \"" + tok.text + "\"";
    case TokenKind::Newline: return "newline";
    case TokenKind::End: return "end of file";
    case TokenKind::Invalid: return tok.text;
    default: return "'" + tok.text + "'";
  }
}

}  // namespace mbsc::parse
