// SPDX-License-Identifier: GPL-2.0-or-later
/// Recursive-descent parser of the model language (grammar: docs/language_syntax.md).
///
/// Errors are reported into Diagnostics and then thrown as SyntaxError, which the
/// nearest statement (or constraint row) loop catches; it skips to the end of that
/// statement and goes on, so one run reports every independent mistake.
#include <memory>
#include <utility>

#include "lexer.hpp"
#include "mbsc/diag/name_suggestions.hpp"
#include "mbsc/diag/activity.hpp"
#include "mbsc/diag/limits.hpp"
#include "loop_expansion.hpp"
#include "mbsc/parse/latex_text.hpp"
#include "mbsc/parse/parse.hpp"
#include "parser_internal.hpp"

namespace mbsc::parse {

namespace {

using ast::Expr;
using ast::ExprPtr;
using ast::Statement;
using ast::StatementPtr;
using TK = TokenKind;

/// Thrown after an error has been reported; unwinds to the statement loop.
struct SyntaxError {};

/// Expressions and blocks nested deeper than this are rejected (keeps the stack bounded).
constexpr int max_nesting = limits::kMaxNesting;

std::string pos_text(const SourcePos& pos) { return std::to_string(pos.line) + ":" + std::to_string(pos.col); }

class Parser {
 public:
  Parser(std::vector<Token> tokens, Diagnostics& diags) : toks_(std::move(tokens)), diags_(diags) {}

  // expression := expr End (an option's value; false when it was reported)
  ExprPtr parse_lone_expression() {
    try {
      ExprPtr e = parse_expr();
      while (toks_[i_].kind == TK::Newline) ++i_;
      if (!at(TK::End)) fail_expected("the end of the expression");
      return e;
    } catch (const SyntaxError&) {
      return nullptr;
    }
  }

  // file := stmt*
  std::vector<StatementPtr> parse_file() {
    std::vector<StatementPtr> out;
    parse_statements(out, /*top_level=*/true, nullptr, "");
    return out;
  }

 private:
  // ---------------------------------------------------------------- tokens

  /// Can an unfinished statement go on over the newline at toks_[j]? Not when the next
  /// line starts with a keyword or '}', nor at the end of the file.
  bool continues_after_newline(std::size_t j) const {
    while (toks_[j].kind == TK::Newline) ++j;
    const TK next = toks_[j].kind;
    return !(next == TK::End || next == TK::RBrace || next == TK::Keyword);
  }

  /// A newline is "soft" (skipped) inside an open '(' or after a binary operator, '='
  /// or ',' -- unless continues_after_newline says no: then the statement is really
  /// unfinished and the newline is reported as what was found.
  bool newline_is_soft() const { return (paren_depth_ > 0 || continuation_) && continues_after_newline(i_); }

  const Token& peek() {
    while (toks_[i_].kind == TK::Newline && newline_is_soft()) ++i_;
    return toks_[i_];
  }

  bool at(TK kind) { return peek().kind == kind; }

  bool at_keyword(const char* word) {
    const Token& t = peek();
    return t.kind == TK::Keyword && t.text == word;
  }

  Token take() {
    Token t = peek();
    if (t.kind != TK::End) ++i_;
    if (t.kind == TK::LParen) ++paren_depth_;
    if (t.kind == TK::RParen && paren_depth_ > 0) --paren_depth_;
    continuation_ = t.kind == TK::Plus || t.kind == TK::Minus || t.kind == TK::Star || t.kind == TK::Slash ||
                    t.kind == TK::Caret || t.kind == TK::Equals || t.kind == TK::Comma;
    last_ = t;
    return t;
  }

  bool accept(TK kind) {
    if (!at(kind)) return false;
    take();
    return true;
  }

  [[noreturn]] void fail(const SourcePos& pos, const std::string& message) {
    diags_.error(pos, message);
    throw SyntaxError{};
  }

  /// "unknown statement 'intertia' (did you mean 'inertia'?)" at an identifier where a
  /// statement begins.
  [[noreturn]] void fail_unknown_statement(const Token& t) {
    fail(t.pos, "unknown statement '" + t.text + "'" + did_you_mean(t.text, statement_keyword_list()));
  }

  /// "expected <what>, found <current token>" at the current token. A lexical error
  /// token is reported with its own message instead.
  [[noreturn]] void fail_expected(const std::string& what) {
    const Token& t = peek();
    if (t.kind == TK::Invalid) fail(t.pos, t.text);
    fail(t.pos, "expected " + what + ", found " + describe(t));
  }

  Token expect(TK kind, const std::string& what) {
    if (!at(kind)) fail_expected(what);
    return take();
  }

  /// The last consumed token quoted for "after ..." phrases.
  std::string after_last() const {
    if (last_.kind == TK::Number || last_.kind == TK::String) return describe(last_);
    return "'" + last_.text + "'";
  }

  /// NAME := IDENT (keywords are reserved and rejected with their own message)
  Token expect_name(const std::string& what) {
    const Token& t = peek();
    if (t.kind == TK::Keyword) fail(t.pos, "'" + t.text + "' is a keyword and cannot be used as a name");
    return expect(TK::Ident, what);
  }

  /// Skips raw newlines if a '{' follows them (a block may open on the next line).
  bool at_brace_past_newlines() {
    std::size_t j = i_;
    while (toks_[j].kind == TK::Newline) ++j;
    if (toks_[j].kind != TK::LBrace) return false;
    i_ = j;
    return true;
  }

  bool at_statement_end() {
    const Token& t = peek();
    return t.kind == TK::Newline || t.kind == TK::Semicolon || t.kind == TK::RBrace || t.kind == TK::End ||
           (t.kind == TK::Keyword && is_statement_keyword(t.text));
  }

  /// A statement ends at a newline or ';' (consumed), before '}' or the end of the
  /// file, or before a keyword that begins the next statement ("mass m  inertia J").
  void end_statement(const std::string& after, bool in_list = false) {
    if (!at_statement_end()) {
      // `{ mass 1  intertia J }`: a misspelt keyword that would have begun the next
      // statement reads as that statement's mistake, as it does on a line of its own.
      const Token& t = peek();
      if (t.kind == TK::Ident && closest_name(t.text, statement_keyword_list())) fail_unknown_statement(t);
      fail_expected(std::string(in_list ? "',' or " : "") + "end of statement after " + after);
    }
    if (at(TK::Newline) || at(TK::Semicolon)) take();
  }

  struct DepthGuard {
    Parser& p;
    explicit DepthGuard(Parser& parser, const SourcePos& pos) : p(parser) {
      if (++p.depth_ > max_nesting) {
        --p.depth_;
        p.fail(pos, "nesting too deep (more than " + std::to_string(max_nesting) + " levels)");
      }
    }
    ~DepthGuard() { --p.depth_; }
    DepthGuard(const DepthGuard&) = delete;
    DepthGuard& operator=(const DepthGuard&) = delete;
  };

  /// Error recovery: skips to the end of the current statement -- a newline or ';'
  /// outside braces and parentheses (consumed), or a '}' closing the enclosing block
  /// (left for the block), or the end of the file. A '{...}' group is skipped whole.
  void recover() {
    continuation_ = false;
    int braces = 0;
    for (;;) {
      const Token& t = toks_[i_];
      if (t.kind == TK::End) break;
      if (t.kind == TK::Newline) {
        ++i_;
        if (braces == 0 && (paren_depth_ == 0 || !continues_after_newline(i_))) break;
        continue;
      }
      if (t.kind == TK::Semicolon && braces == 0) {
        ++i_;
        break;
      }
      if (t.kind == TK::RBrace) {
        if (braces == 0) break;
        --braces;
      }
      if (t.kind == TK::LBrace) ++braces;
      if (t.kind == TK::LParen) ++paren_depth_;
      if (t.kind == TK::RParen && paren_depth_ > 0) --paren_depth_;
      ++i_;
    }
    paren_depth_ = 0;
    continuation_ = false;
  }

  // ------------------------------------------------------------ statements

  // stmt* up to '}' (blocks) or the end of the file (top level)
  void parse_statements(std::vector<StatementPtr>& out, bool top_level, const Token* open, const std::string& what) {
    for (;;) {
      while (toks_[i_].kind == TK::Newline || toks_[i_].kind == TK::Semicolon) ++i_;
      const Token& t = toks_[i_];
      if (t.kind == TK::End) {
        if (open)
          diags_.error(t.pos, "missing '}' to close " + what + " opened at " + pos_text(open->pos));
        return;
      }
      if (t.kind == TK::RBrace) {
        if (open) {
          take();
          return;
        }
        diags_.error(t.pos, "unmatched '}'");
        ++i_;
        continue;
      }
      const std::size_t before = i_;
      // Top-level statements report how far through the (expanded) tokens parsing is.
      if (top_level) checkpoint("parsing", "tokens", t.pos, i_, toks_.size());
      paren_depth_ = 0;
      continuation_ = false;
      try {
        parse_statement(out, top_level);
      } catch (const SyntaxError&) {
        recover();
      }
      if (i_ == before && toks_[i_].kind != TK::End && toks_[i_].kind != TK::RBrace) ++i_;  // always progress
    }
  }

  Statement begin(Statement::Kind kind, const Token& keyword) {
    Statement st;
    st.kind = kind;
    st.pos = keyword.pos;
    return st;
  }

  static void push(std::vector<StatementPtr>& out, Statement st) {
    out.push_back(std::make_shared<const Statement>(std::move(st)));
  }

  // stmt := one of the statements below, chosen by its leading keyword
  void parse_statement(std::vector<StatementPtr>& out, bool top_level) {
    const Token& t = peek();
    // `torque` begins a statement only here: elsewhere it stays a name (a joint's
    // `torque` option, a parameter called torque).
    if (t.kind == TK::Ident && t.text == "torque") return parse_torque(out, take());
    if (t.kind == TK::Ident) fail_unknown_statement(t);
    if (t.kind == TK::Invalid) fail(t.pos, t.text);
    if (t.kind != TK::Keyword || !is_statement_keyword(t.text)) fail_expected("a statement");
    const Token kw = take();
    const std::string& k = kw.text;
    if (k == "model") return parse_named(out, kw, Statement::Kind::Model, "model name after 'model'");
    if (k == "parametrization")
      return parse_named(out, kw, Statement::Kind::Parametrization, "'absolute' or 'nodal' after 'parametrization'");
    if (k == "parameter") return parse_valued_names(out, kw, Statement::Kind::Parameter);
    if (k == "speed") return parse_valued_names(out, kw, Statement::Kind::Speed);
    if (k == "input") return parse_names(out, kw, Statement::Kind::Input);
    if (k == "coordinate") return parse_names(out, kw, Statement::Kind::Coordinate);
    if (k == "gravity") return parse_gravity(out, kw);
    if (k == "include") return parse_include(out, kw, top_level);
    if (k == "component") return parse_component(out, kw);
    if (k == "subsystem" || k == "body") return parse_subsystem(out, kw);
    if (k == "constraint") return parse_constraint(out, kw);
    if (k == "force") return parse_force(out, kw);
    if (k == "mass") return parse_valued(out, kw, Statement::Kind::Mass);
    if (k == "inertia") return parse_inertia(out, kw);
    if (k == "attitude") return parse_attitude(out, kw);
    if (k == "kinetic") return parse_valued(out, kw, Statement::Kind::Kinetic);
    if (k == "potential") return parse_valued(out, kw, Statement::Kind::Potential);
    if (k == "independent") return parse_independent(out, kw, Statement::Kind::Independent);
    if (k == "alternative") return parse_independent(out, kw, Statement::Kind::Alternative);
    if (k == "output") return parse_output(out, kw);
    if (k == "let") return parse_let(out, kw);
    if (k == "point") return parse_point(out, kw);
    if (k == "com") return parse_com(out, kw);
    if (k == "axis") return parse_axis(out, kw);
    if (k == "ground") return parse_ground(out, kw);
    if (k == "joint") return parse_joint(out, kw);
    if (k == "spring" || k == "damper") return parse_spring(out, kw);
    if (k == "latex") return parse_latex(out, kw);
    if (k == "initial") return parse_initial(out, kw);
    fail(kw.pos, "unknown statement '" + k + "'");  // unreachable: every statement keyword is handled
  }

  // KEYWORD IDENT, for 'model NAME' and 'parametrization (absolute | nodal)'.
  void parse_named(std::vector<StatementPtr>& out, const Token& kw, Statement::Kind kind, const std::string& expected) {
    Statement st = begin(kind, kw);
    const Token name = expect_name(expected);
    st.name = name.text;
    st.name_pos = name.pos;
    end_statement(kw.text + " '" + name.text + "'");
    push(out, std::move(st));
  }

  // 'parameter' IDENT ['=' expr] (',' IDENT ['=' expr])*
  // 'speed'     IDENT ['=' expr] (',' IDENT ['=' expr])*
  void parse_valued_names(std::vector<StatementPtr>& out, const Token& kw, Statement::Kind kind) {
    std::vector<Statement> items;
    for (;;) {
      Statement st = begin(kind, kw);
      const Token name = expect_name(kw.text + " name after " + after_last());
      st.name = name.text;
      st.name_pos = name.pos;
      if (accept(TK::Equals)) st.value = parse_expr();
      items.push_back(std::move(st));
      if (!accept(TK::Comma)) break;
    }
    end_statement(kw.text + " '" + items.back().name + "'", /*in_list=*/true);
    for (auto& st : items) push(out, std::move(st));
  }

  // 'input' IDENT (',' IDENT)*  |  'coordinate' IDENT (',' IDENT)*
  void parse_names(std::vector<StatementPtr>& out, const Token& kw, Statement::Kind kind) {
    std::vector<Statement> items;
    for (;;) {
      Statement st = begin(kind, kw);
      const Token name = expect_name(kw.text + " name after " + after_last());
      st.name = name.text;
      st.name_pos = name.pos;
      items.push_back(std::move(st));
      if (!accept(TK::Comma)) break;
    }
    end_statement(kw.text + " '" + items.back().name + "'", /*in_list=*/true);
    for (auto& st : items) push(out, std::move(st));
  }

  // 'gravity' '(' expr ',' expr [',' expr] ')'
  void parse_gravity(std::vector<StatementPtr>& out, const Token& kw) {
    Statement st = begin(Statement::Kind::Gravity, kw);
    expect(TK::LParen, "'(' after 'gravity'");
    for (;;) {
      if (st.exprs.size() == 3) fail(peek().pos, "gravity has 2 or 3 components, found more");
      st.exprs.push_back(parse_expr());
      if (!accept(TK::Comma)) break;
    }
    if (!at(TK::RParen)) fail_expected("',' or ')' after gravity component");
    if (st.exprs.size() < 2) fail(peek().pos, "gravity has 2 or 3 components, found 1 (expected ',')");
    take();
    end_statement("gravity");
    push(out, std::move(st));
  }

  // 'include' STRING
  void parse_include(std::vector<StatementPtr>& out, const Token& kw, bool top_level) {
    Statement st = begin(Statement::Kind::Include, kw);
    const Token file = expect(TK::String, "file name in double quotes after 'include'");
    if (file.text.empty()) fail(file.pos, "empty file name in include");
    st.name = file.text;
    st.name_pos = file.pos;
    end_statement("include \"" + file.text + "\"");
    if (!top_level) {
      diags_.error(kw.pos, "include is only allowed at the top level of a file");
      return;
    }
    push(out, std::move(st));
  }

  // 'component' IDENT '(' [IDENT (',' IDENT)*] ')' '{' stmt* '}'
  void parse_component(std::vector<StatementPtr>& out, const Token& kw) {
    Statement st = begin(Statement::Kind::Component, kw);
    const Token name = expect_name("component name after 'component'");
    st.name = name.text;
    st.name_pos = name.pos;
    expect(TK::LParen, "'(' after component name '" + name.text + "'");
    if (!at(TK::RParen)) {
      for (;;) {
        const Token formal = expect_name("parameter name in component '" + name.text + "'");
        st.formals.push_back(formal.text);
        st.formal_pos.push_back(formal.pos);
        if (!accept(TK::Comma)) break;
      }
    }
    expect(TK::RParen, "')' after the parameters of component '" + name.text + "'");
    if (!at_brace_past_newlines()) fail_expected("'{' to begin the body of component '" + name.text + "'");
    parse_block(st, "component '" + name.text + "'");
    end_statement("the body of component '" + name.text + "'");
    push(out, std::move(st));
  }

  // 'subsystem' IDENT [':' IDENT ['(' [expr (',' expr)*] ')']] ['{' stmt* '}']   ('body' alike)
  void parse_subsystem(std::vector<StatementPtr>& out, const Token& kw) {
    Statement st = begin(Statement::Kind::Subsystem, kw);
    const Token name = expect_name(kw.text + " name after '" + kw.text + "'");
    st.name = name.text;
    st.name_pos = name.pos;
    const std::string what = kw.text + " '" + name.text + "'";
    if (accept(TK::Colon)) {
      const Token kind = expect_name("kind or component name after ':' in " + what);
      st.kind_name = kind.text;
      st.kind_pos = kind.pos;
      if (accept(TK::LParen)) {
        if (!at(TK::RParen)) {
          for (;;) {
            st.exprs.push_back(parse_expr());
            if (!accept(TK::Comma)) break;
          }
        }
        expect(TK::RParen, "')' after the arguments of " + what);
      }
    } else if (at(TK::LParen)) {
      fail(peek().pos, what + " has arguments but no kind (expected ': KIND' before '(')");
    }
    if (at_brace_past_newlines()) {
      parse_block(st, what);
      end_statement("the body of " + what);
    } else {
      end_statement(what);
    }
    push(out, std::move(st));
  }

  // '{' stmt* '}'
  void parse_block(Statement& st, const std::string& what) {
    DepthGuard guard(*this, peek().pos);  // on failure the '{' is still ahead: recovery skips the block
    const Token open = take();            // '{'

    st.has_body = true;
    parse_statements(st.body, /*top_level=*/false, &open, what);
  }

  // 'constraint' ('position'|'velocity') ['nonlinear'] '{' equation* '}'
  void parse_constraint(std::vector<StatementPtr>& out, const Token& kw) {
    Statement st = begin(Statement::Kind::Constraint, kw);
    if (!at_keyword("position") && !at_keyword("velocity"))
      fail_expected("'position' or 'velocity' after 'constraint'");
    const Token level = take();
    st.level = level.text;
    st.name_pos = level.pos;
    if (at_keyword("nonlinear")) {
      take();
      st.nonlinear = true;
    }
    if (!at_brace_past_newlines()) fail_expected("'{' to begin the " + st.level + " constraint block");
    const Token open = take();
    parse_rows(st, open);
    end_statement("the " + st.level + " constraint block");
    push(out, std::move(st));
  }

  // equation* '}'   (rows separated by newlines or ';')
  void parse_rows(Statement& st, const Token& open) {
    const std::string what = st.level + " constraint block";
    for (;;) {
      while (toks_[i_].kind == TK::Newline || toks_[i_].kind == TK::Semicolon) ++i_;
      const Token& t = toks_[i_];
      if (t.kind == TK::RBrace) {
        take();
        return;
      }
      if (t.kind == TK::End || starts_statement_in_rows()) {
        // The block was left open; treat it as closed here so the statement that
        // follows is still parsed (and checked) normally.
        diags_.error(t.pos, "missing '}' to close " + what + " opened at " + pos_text(open.pos));
        return;
      }
      const std::size_t before = i_;
      paren_depth_ = 0;
      continuation_ = false;
      try {
        st.equations.push_back(parse_equation());
      } catch (const SyntaxError&) {
        recover();
      }
      if (i_ == before && toks_[i_].kind != TK::End && toks_[i_].kind != TK::RBrace) ++i_;
    }
  }

  /// In a constraint block: does a statement (rather than a row) begin here? A statement
  /// keyword followed by something that cannot follow a name in a row ("mass m1") means
  /// the block was not closed; "mass = 1" is a row misusing a keyword.
  bool starts_statement_in_rows() const {
    const Token& t = toks_[i_];
    if (t.kind != TK::Keyword || !is_statement_keyword(t.text)) return false;
    switch (toks_[i_ + 1].kind) {
      case TK::Equals:
      case TK::Dot:
      case TK::Prime:
      case TK::Star:
      case TK::Slash:
      case TK::Caret: return false;
      default: return true;
    }
  }

  // equation := [IDENT ':'] expr '=' expr
  ast::Equation parse_equation() {
    ast::Equation eq;
    eq.pos = peek().pos;
    if (toks_[i_].kind == TK::Ident && toks_[i_ + 1].kind == TK::Colon) {
      eq.label = take().text;
      take();  // ':'
    }
    eq.lhs = parse_expr();
    if (!at(TK::Equals)) {
      const TK k = peek().kind;
      if (k == TK::Newline || k == TK::Semicolon || k == TK::RBrace || k == TK::End)
        fail(eq.pos, "constraint row is not an equation (expected '=')");
      fail_expected("'=' in constraint row");
    }
    take();
    eq.rhs = parse_expr();
    const TK k = peek().kind;
    if (k == TK::Newline || k == TK::Semicolon)
      take();
    else if (k != TK::RBrace && k != TK::End)
      fail_expected("end of constraint row");
    return eq;
  }

  // 'force' path ':' expr
  void parse_force(std::vector<StatementPtr>& out, const Token& kw) {
    Statement st = begin(Statement::Kind::Force, kw);
    st.path = parse_path("force target after 'force'");
    expect(TK::Colon, "':' after force target '" + st.path.text + "'");
    st.value = parse_expr();
    end_statement("force on '" + st.path.text + "'");
    push(out, std::move(st));
  }

  // '(' expr ',' expr [',' expr] ')'  (two components in the plane, three in space)
  void parse_pair(std::vector<ExprPtr>& into, const std::string& what) {
    expect(TK::LParen, "'(' before " + what);
    into.push_back(parse_expr());
    expect(TK::Comma, "',' between the components of " + what);
    into.push_back(parse_expr());
    if (accept(TK::Comma)) into.push_back(parse_expr());
    expect(TK::RParen, "')' after " + what);
  }

  // 'inertia' expr  |  'inertia' '(' expr (',' expr)+ ')'  (a rigid3d body's tensor entries)
  void parse_inertia(std::vector<StatementPtr>& out, const Token& kw) {
    Statement st = begin(Statement::Kind::Inertia, kw);
    const std::size_t start = i_;
    const int depth = paren_depth_;
    bool list = false;
    if (at(TK::LParen)) {
      take();
      parse_expr();
      list = at(TK::Comma);
      i_ = start;  // read again below, as a list or as one expression
      paren_depth_ = depth;
    }
    if (list) {
      take();  // '('
      st.exprs.push_back(parse_expr());
      while (accept(TK::Comma)) st.exprs.push_back(parse_expr());
      expect(TK::RParen, "')' after the inertia tensor entries");
    } else {
      st.value = parse_expr();
    }
    end_statement("inertia expression");
    push(out, std::move(st));
  }

  // 'torque' ['body' | 'space'] '(' expr ',' expr ',' expr ')'
  void parse_torque(std::vector<StatementPtr>& out, const Token& kw) {
    Statement st = begin(Statement::Kind::Torque, kw);
    if (at_keyword("body") || (at(TK::Ident) && peek().text == "space")) {
      const Token frame = take();
      st.option2 = ast::Path{frame.text, frame.pos};
    }
    parse_pair(st.exprs, "the torque's components");
    if (st.exprs.size() != 3) fail(kw.pos, "a torque has three components: torque (Tx, Ty, Tz)");
    end_statement("torque");
    push(out, std::move(st));
  }

  // 'attitude' ('quaternion' | 'euler' SEQ) ['body' | 'space']: how a rigid3d body's
  // attitude is parametrized and in which frame its angular speeds are measured.
  void parse_attitude(std::vector<StatementPtr>& out, const Token& kw) {
    Statement st = begin(Statement::Kind::Attitude, kw);
    const Token kind = expect_name("'quaternion' or 'euler' after 'attitude'");
    st.name = kind.text;
    st.name_pos = kind.pos;
    if (kind.text == "euler") {
      const Token seq = expect_name("the axis sequence after 'attitude euler' (e.g. zyx)");
      st.path = ast::Path{seq.text, seq.pos};
    }
    if (at_keyword("body") || (at(TK::Ident) && peek().text == "space")) {
      const Token frame = take();
      st.option2 = ast::Path{frame.text, frame.pos};
    }
    end_statement("attitude '" + kind.text + "'");
    push(out, std::move(st));
  }

  // 'point' IDENT '(' expr ',' expr ')'
  void parse_point(std::vector<StatementPtr>& out, const Token& kw) {
    Statement st = begin(Statement::Kind::Point, kw);
    const Token name = expect_name("point name after 'point'");
    st.name = name.text;
    st.name_pos = name.pos;
    parse_pair(st.exprs, "the body coordinates of point '" + name.text + "'");
    end_statement("point '" + name.text + "'");
    push(out, std::move(st));
  }

  // 'com' '(' expr ',' expr ')'
  void parse_com(std::vector<StatementPtr>& out, const Token& kw) {
    Statement st = begin(Statement::Kind::Com, kw);
    parse_pair(st.exprs, "the body coordinates of the mass centre");
    end_statement("com");
    push(out, std::move(st));
  }

  // 'axis' IDENT '(' expr ',' expr ')' '(' expr ',' expr ')'
  void parse_axis(std::vector<StatementPtr>& out, const Token& kw) {
    Statement st = begin(Statement::Kind::Axis, kw);
    const Token name = expect_name("axis name after 'axis'");
    st.name = name.text;
    st.name_pos = name.pos;
    parse_pair(st.exprs, "the point of axis '" + name.text + "'");
    parse_pair(st.exprs, "the direction of axis '" + name.text + "'");
    end_statement("axis '" + name.text + "'");
    push(out, std::move(st));
  }

  // 'ground' '{' (point | axis)* '}'
  void parse_ground(std::vector<StatementPtr>& out, const Token& kw) {
    Statement st = begin(Statement::Kind::Ground, kw);
    if (!at_brace_past_newlines()) fail_expected("'{' after 'ground'");
    parse_block(st, "ground");
    end_statement("the body of ground");
    push(out, std::move(st));
  }

  // 'joint' [IDENT ':'] IDENT PATH PATH [IDENT expr [IDENT expr]]
  void parse_joint(std::vector<StatementPtr>& out, const Token& kw) {
    Statement st = begin(Statement::Kind::Joint, kw);
    Token kind = expect_name("joint kind (revolute, prismatic, weld) or 'NAME :' after 'joint'");
    if (accept(TK::Colon)) {
      st.name = kind.text;
      st.name_pos = kind.pos;
      kind = expect_name("joint kind (revolute, prismatic, weld) after 'joint " + st.name + " :'");
    }
    st.kind_name = kind.text;
    st.kind_pos = kind.pos;
    const std::string what = "joint" + (st.name.empty() ? std::string() : " '" + st.name + "'");
    if (st.kind_name == "knife_edge") return parse_knife_edge(out, std::move(st), what);
    if (st.kind_name == "rolling_sphere") {
      // 'rolling_sphere' BODY 'radius' r 'surface' (gamma): one end, the sphere's body.
      st.paths.push_back(parse_path("body (the sphere) of " + what));
      st.paths.push_back(ast::Path{"", kind.pos});
    } else {
      st.paths.push_back(parse_path("first point or axis of " + what));
      st.paths.push_back(parse_path("second point of " + what));
    }
    parse_joint_coordinate(st, what);
    // An option word ("force" is also a statement keyword, so test it before the end).
    const Token& opt = peek();
    if (opt.kind == TK::Ident || (opt.kind == TK::Keyword && opt.text == "force")) {
      st.path = ast::Path{opt.text, opt.pos};  // the option keyword and where it is
      st.level = take().text;
      st.value = parse_expr();
      // A second option (rolling_inside: 'radius r ring R'; cylindrical: 'force F torque T').
      if (peek().kind == TK::Ident || (peek().kind == TK::Keyword && peek().text == "force")) {
        st.option2 = ast::Path{peek().text, peek().pos};
        take();
        st.exprs.push_back(parse_expr());
      }
    }
    parse_joint_coordinate(st, what);
    end_statement(what);
    push(out, std::move(st));
  }

  // ['coordinate' IDENT {',' IDENT} ['speed' IDENT {',' IDENT}] ['euler' SEQ | 'quaternion']]:
  // the joint's relative coordinates and their rates (a spherical joint's three angles
  // name their Euler sequence; its four quaternion entries say `quaternion`), before or
  // after the actuator option.
  void parse_joint_coordinate(Statement& st, const std::string& what) {
    if (!at_keyword("coordinate")) return;
    const Token word = take();
    if (!st.joint_coordinates.empty()) fail(word.pos, what + ": 'coordinate' given twice");
    auto names = [&](std::vector<ast::Path>& into, const char* noun, const char* after) {
      do {
        const Token name = expect_name(std::string("name of the joint's ") + noun + " after '" + after + "'");
        into.push_back(ast::Path{name.text, name.pos});
      } while (accept(TK::Comma));
    };
    names(st.joint_coordinates, "coordinate", "coordinate");
    if (at_keyword("speed")) {
      take();
      names(st.joint_speeds, "speed", "speed");
    }
    if (peek().kind == TK::Ident && peek().text == "euler") {
      take();
      const Token seq = expect_name("Euler sequence after 'euler' (three axes of x, y, z, e.g. zyx)");
      st.joint_sequence = ast::Path{seq.text, seq.pos};
    } else if (peek().kind == TK::Ident && peek().text == "quaternion") {
      const Token word = take();
      st.joint_sequence = ast::Path{word.text, word.pos};
    }
  }

  // ... 'knife_edge' PATH ['point' IDENT] ['axis' IDENT]   (the blade's body, point and direction)
  void parse_knife_edge(std::vector<StatementPtr>& out, Statement st, const std::string& what) {
    st.paths.push_back(parse_path("body of " + what));
    st.paths.resize(3);  // {BODY, point, axis}; empty text when not given
    for (int k = 0; k < 2 && (at_keyword("point") || at_keyword("axis")); ++k) {
      const Token word = take();
      ast::Path& slot = st.paths[word.text == "point" ? 1 : 2];
      if (!slot.text.empty()) fail(word.pos, what + ": '" + word.text + "' given twice");
      slot = parse_path(word.text + " name of the blade's body after '" + word.text + "'");
    }
    end_statement(what);
    push(out, std::move(st));
  }

  // 'spring' IDENT ['rotational'] PATH PATH 'stiffness' expr [('length' | 'angle') expr]
  // 'damper' IDENT ['rotational'] PATH PATH 'coefficient' expr
  void parse_spring(std::vector<StatementPtr>& out, const Token& kw) {
    const bool spring = kw.text == "spring";
    Statement st = begin(spring ? Statement::Kind::Spring : Statement::Kind::Damper, kw);
    const Token name = expect_name(kw.text + " name after '" + kw.text + "'");
    st.name = name.text;
    st.name_pos = name.pos;
    const std::string what = kw.text + " '" + name.text + "'";
    if (peek().kind == TK::Ident && peek().text == "rotational") {
      take();
      st.kind_name = "rotational";  // between two bodies' angles, not two points
    }
    st.paths.push_back(parse_path("first point of " + what));
    st.paths.push_back(parse_path("second point of " + what));
    const char* main_word = spring ? "stiffness" : "coefficient";
    if (!(peek().kind == TK::Ident && peek().text == main_word)) fail_expected(std::string("'") + main_word + "' after the points of " + what);
    take();
    st.value = parse_expr();
    const char* rest_word = st.kind_name == "rotational" ? "angle" : "length";
    if (spring && peek().kind == TK::Ident && peek().text == rest_word) {
      take();
      st.exprs.push_back(parse_expr());
    }
    end_statement(what);
    push(out, std::move(st));
  }

  // 'latex' path STRING: the symbol `mbsc print --latex` writes for a name. The text must
  // be safe in a formula (latex_text.hpp); whether the name exists is the model's to say.
  // 'initial' ['guess'] PATH '=' expr (',' PATH '=' expr)*
  void parse_initial(std::vector<StatementPtr>& out, const Token& kw) {
    std::vector<Statement> items;
    // `guess` is a word here only when a name follows it (a variable may be called guess).
    const bool guess = at(TK::Ident) && peek().text == "guess" && i_ + 1 < toks_.size() && toks_[i_ + 1].kind == TK::Ident;
    if (guess) take();
    for (;;) {
      Statement st = begin(Statement::Kind::Initial, kw);
      if (guess) st.level = "guess";
      st.path = parse_path("coordinate or speed after " + after_last());
      expect(TK::Equals, "'=' and a value after 'initial " + st.path.text + "'");
      st.value = parse_expr();
      items.push_back(std::move(st));
      if (!accept(TK::Comma)) break;
    }
    end_statement("initial value of '" + items.back().path.text + "'", /*in_list=*/true);
    for (auto& st : items) push(out, std::move(st));
  }

  void parse_latex(std::vector<StatementPtr>& out, const Token& kw) {
    Statement st = begin(Statement::Kind::Latex, kw);
    st.path = parse_path("name after 'latex'");
    const std::string what = "latex symbol of '" + st.path.text + "'";
    const std::string expected = "LaTeX text in double quotes after 'latex " + st.path.text + "'";
    if (at(TK::Invalid)) {
      const Token& bad = peek();  // a string with a control character, or no string (latex th1 \theta)
      fail(bad.pos, bad.text.find("string") != std::string::npos ? what + ": " + bad.text
                                                                 : "expected " + expected + ", found " + bad.text);
    }
    const Token text = expect(TK::String, expected);
    if (const std::string why = latex_text_problem(text.text); !why.empty())
      fail(text.pos, what + " is not safe LaTeX: " + why);
    st.name = text.text;
    st.name_pos = text.pos;
    end_statement(what);
    push(out, std::move(st));
  }

  // 'mass' expr | 'inertia' expr | 'kinetic' expr | 'potential' expr
  void parse_valued(std::vector<StatementPtr>& out, const Token& kw, Statement::Kind kind) {
    Statement st = begin(kind, kw);
    st.value = parse_expr();
    end_statement(kw.text + " expression");
    push(out, std::move(st));
  }

  // ('independent' | 'alternative') path (',' path)*
  void parse_independent(std::vector<StatementPtr>& out, const Token& kw, Statement::Kind kind) {
    Statement st = begin(kind, kw);
    for (;;) {
      st.paths.push_back(parse_path("name after " + after_last()));
      if (!accept(TK::Comma)) break;
    }
    end_statement(kw.text + " '" + st.paths.back().text + "'", /*in_list=*/true);
    push(out, std::move(st));
  }

  // 'output' IDENT '=' expr | 'output' 'energy'
  void parse_output(std::vector<StatementPtr>& out, const Token& kw) {
    Statement st = begin(Statement::Kind::Output, kw);
    if (at_keyword("energy")) {
      const Token e = take();
      st.name = e.text;
      st.name_pos = e.pos;
      end_statement("output energy");
      push(out, std::move(st));
      return;
    }
    const Token name = expect_name("output name or 'energy' after 'output'");
    st.name = name.text;
    st.name_pos = name.pos;
    expect(TK::Equals, "'=' after output name '" + name.text + "'");
    st.value = parse_expr();
    end_statement("output '" + name.text + "'");
    push(out, std::move(st));
  }

  // 'let' IDENT '=' expr
  void parse_let(std::vector<StatementPtr>& out, const Token& kw) {
    Statement st = begin(Statement::Kind::Let, kw);
    const Token name = expect_name("name after 'let'");
    st.name = name.text;
    st.name_pos = name.pos;
    expect(TK::Equals, "'=' after 'let " + name.text + "'");
    st.value = parse_expr();
    end_statement("let '" + name.text + "'");
    push(out, std::move(st));
  }

  // path := IDENT ('.' IDENT)*
  ast::Path parse_path(const std::string& what) {
    const Token first = at_keyword("ground") ? take() : expect_name(what);
    ast::Path p;
    p.text = first.text;
    p.pos = first.pos;
    while (accept(TK::Dot)) p.text += "." + expect_name("name after '.' in '" + p.text + ".'").text;
    return p;
  }

  // ----------------------------------------------------------- expressions

  static ExprPtr make(Expr::Kind kind, std::string text, std::vector<ExprPtr> args, const SourcePos& pos) {
    auto e = std::make_shared<Expr>();
    e->kind = kind;
    e->text = std::move(text);
    e->args = std::move(args);
    e->pos = pos;
    return e;
  }

  // expr := term (('+'|'-') term)*
  ExprPtr parse_expr() { return parse_chain(Expr::Kind::Sum, TK::Plus, TK::Minus); }

  // term := unary (('*'|'/') unary)*
  ExprPtr parse_term() { return parse_chain(Expr::Kind::Product, TK::Star, TK::Slash); }

  /// One flat Sum or Product node for a chain of operands (see ast::Expr); a single
  /// operand is returned as it is.
  ExprPtr parse_chain(Expr::Kind kind, TK op1, TK op2) {
    const SourcePos start = peek().pos;
    std::vector<ExprPtr> operands{kind == Expr::Kind::Sum ? parse_term() : parse_unary()};
    std::string ops;
    while (at(op1) || at(op2)) {
      const Token op = take();
      if (operands.size() >= limits::kMaxOperands)
        fail(op.pos, std::string("more than ") + std::to_string(limits::kMaxOperands) + " operands in one " +
                         (kind == Expr::Kind::Sum ? "sum" : "product"));
      ops += op.text;
      operands.push_back(kind == Expr::Kind::Sum ? parse_term() : parse_unary());
    }
    if (operands.size() == 1) return operands.front();
    return make(kind, std::move(ops), std::move(operands), start);
  }

  // unary := ('-'|'+') unary | power
  ExprPtr parse_unary() {
    DepthGuard guard(*this, peek().pos);
    if (at(TK::Minus) || at(TK::Plus)) {
      const Token op = take();
      ExprPtr operand = parse_unary();
      return make(Expr::Kind::Unary, op.text, {operand}, op.pos);
    }
    return parse_power();
  }

  // power := postfix ['^' unary]        (right associative: a^b^c = a^(b^c), -x^2 = -(x^2))
  ExprPtr parse_power() {
    const SourcePos start = peek().pos;
    ExprPtr base = parse_postfix();
    if (!at(TK::Caret)) return base;
    take();
    ExprPtr exponent = parse_unary();
    return make(Expr::Kind::Binary, "^", {base, exponent}, start);
  }

  // postfix := primary ("'")*            (a prime only right after a name or a prime)
  ExprPtr parse_postfix() {
    ExprPtr e = parse_primary();
    int primes = 0;  // each prime is a level of the tree: bounded like any nesting
    while (at(TK::Prime)) {
      if (++primes + depth_ > max_nesting)
        fail(peek().pos, "nesting too deep (more than " + std::to_string(max_nesting) + " levels)");
      if (last_.kind != TK::Ident && last_.kind != TK::Prime)
        fail(peek().pos, "a prime (time derivative) can only follow a name, found it after " + after_last());
      take();
      const SourcePos pos = e->pos;
      e = make(Expr::Kind::Prime, "", {e}, pos);
    }
    return e;
  }

  // primary := NUMBER | path | IDENT '(' [expr (',' expr)*] ')' | '(' expr ')'
  ExprPtr parse_primary() {
    const Token& t = peek();
    switch (t.kind) {
      case TK::Number: {
        const Token num = take();
        return make(Expr::Kind::Number, num.text, {}, num.pos);
      }
      case TK::Ident: {
        const ast::Path path = parse_path("name");
        if (!at(TK::LParen)) return make(Expr::Kind::Name, path.text, {}, path.pos);
        if (path.text.find('.') != std::string::npos)
          fail(path.pos, "'" + path.text + "' is not a function name (only plain names can be called)");
        return parse_call_args(path);
      }
      case TK::LParen: {
        const Token open = take();
        ExprPtr inner = parse_expr();
        expect(TK::RParen, "')' to close '(' opened at " + pos_text(open.pos));
        return inner;
      }
      case TK::Keyword:
        fail(t.pos, "'" + t.text + "' is a keyword and cannot be used in an expression");
      default:
        fail_expected("expression after " + after_last());
    }
  }

  // IDENT '(' [expr (',' expr)*] ')'
  ExprPtr parse_call_args(const ast::Path& fn) {
    take();  // '('
    std::vector<ExprPtr> args;
    if (!at(TK::RParen)) {
      for (;;) {
        args.push_back(parse_expr());
        if (!accept(TK::Comma)) break;
      }
    }
    expect(TK::RParen, "')' after arguments of '" + fn.text + "'");
    return make(Expr::Kind::Call, fn.text, std::move(args), fn.pos);
  }

  std::vector<Token> toks_;
  Diagnostics& diags_;
  std::size_t i_ = 0;
  int paren_depth_ = 0;        // '(' consumed and not yet closed in this statement
  bool continuation_ = false;  // the last token was a binary operator, '=' or ','
  int depth_ = 0;              // nesting depth of expressions and blocks
  Token last_;                 // the last consumed token
};

}  // namespace

bool parse_source(const std::string& text, const std::string& file, Diagnostics& diags, ast::File& out,
                  const std::map<std::string, double>& overrides) {
  const int errors_before = diags.error_count();
  auto tokens = expand_loops(lex(text, file), diags, overrides, out.structural);
  out.token_count = tokens.size();
  if (diags.error_count() != errors_before) return false;
  Parser parser(std::move(tokens), diags);
  out.path = file;
  out.statements = parser.parse_file();
  return diags.error_count() == errors_before;
}

ast::ExprPtr parse_expression(const std::string& text, const std::string& origin, Diagnostics& diags) {
  const int errors_before = diags.error_count();
  auto tokens = lex(text, origin);
  if (diags.error_count() != errors_before) return nullptr;
  Parser parser(std::move(tokens), diags);
  ast::ExprPtr e = parser.parse_lone_expression();
  return diags.error_count() == errors_before ? e : nullptr;
}

std::optional<ast::File> parse_text(const std::string& text, const std::string& file, Diagnostics& diags,
                                    const std::map<std::string, double>& overrides) {
  ast::File out;
  if (!parse_source(text, file, diags, out, overrides)) return std::nullopt;
  return out;
}

}  // namespace mbsc::parse
