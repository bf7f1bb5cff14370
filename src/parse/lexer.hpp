// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Private to src/parse: the tokens of the model language and the lexer that makes them.
#include <string>
#include <vector>

#include "mbsc/diag/diagnostics.hpp"

namespace mbsc::parse {

enum class TokenKind {
  Ident,      // [A-Za-z_][A-Za-z0-9_]* that is not a keyword
  Keyword,    // a reserved word (see is_keyword)
  Number,     // 1, 0.5, .5, 1e-3, 2.5E+2 (text as written)
  String,     // "..." (text without the quotes)
  Newline,    // end of a line that held a token; consecutive blank/comment lines collapse
  Semicolon,  // ;
  Comma,      // ,
  Colon,      // :
  Dot,        // .
  LParen,     // (
  RParen,     // )
  LBrace,     // {
  RBrace,     // }
  LBracket,   // [  (indices, expanded away by loop_expansion before parsing)
  RBracket,   // ]
  Plus,       // +
  Minus,      // -
  Star,       // *
  Slash,      // /
  Caret,      // ^
  Equals,     // =
  Prime,      // '
  Invalid,    // a lexical error; text holds the message to report
  End,        // end of the text (always the last token)
};

struct Token {
  TokenKind kind = TokenKind::End;
  std::string text;
  SourcePos pos;
};

/// Splits model text into tokens. Never fails: lexical errors become Invalid tokens
/// (the parser reports them when it reaches them). The result always ends with End.
std::vector<Token> lex(const std::string& text, const std::string& file);

/// True for every reserved word of the language.
bool is_keyword(const std::string& word);

/// True for the keywords that begin a statement ("model", "mass", ...).
bool is_statement_keyword(const std::string& word);

/// Every statement keyword, in a fixed order (for "did you mean" suggestions).
std::vector<std::string> statement_keyword_list();

/// Every keyword, statement keywords first (docs/language_syntax.md lists them all).
std::vector<std::string> keyword_list();

/// How a token is named in "found ..." parts of messages: "newline", "end of file",
/// "'theta'", "keyword 'mass'", "number '1.5'", "string \"a.mbs\"", "')'".
std::string describe(const Token& tok);

}  // namespace mbsc::parse
