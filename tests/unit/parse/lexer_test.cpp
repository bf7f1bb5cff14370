// SPDX-License-Identifier: GPL-2.0-or-later
// Unit tests of the model-language lexer (a private header of src/parse).
#include <catch2/catch.hpp>

#include <fstream>
#include <iterator>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "../../../src/parse/lexer.hpp"

using mbsc::parse::describe;
using mbsc::parse::lex;
using mbsc::parse::Token;
using mbsc::parse::TokenKind;

namespace {

/// "kind:text@line:col" for every token, space separated (End included).
std::string dump(const std::vector<Token>& toks) {
  std::string out;
  for (const auto& t : toks) {
    if (!out.empty()) out += ' ';
    switch (t.kind) {
      case TokenKind::Ident: out += "id:" + t.text; break;
      case TokenKind::Keyword: out += "kw:" + t.text; break;
      case TokenKind::Number: out += "num:" + t.text; break;
      case TokenKind::String: out += "str:" + t.text; break;
      case TokenKind::Newline: out += "NL"; break;
      case TokenKind::Invalid: out += "bad:" + t.text; break;
      case TokenKind::End: out += "END"; break;
      default: out += t.text; break;
    }
    out += "@" + std::to_string(t.pos.line) + ":" + std::to_string(t.pos.col);
  }
  return out;
}

}  // namespace

TEST_CASE("lexer: names, keywords, punctuation and positions", "[parse][lexer]") {
  const auto toks = lex("model m1\nmass m*R.u^2 + x' ; input _t0", "f.mbs");
  CHECK(dump(toks) ==
        "kw:model@1:1 id:m1@1:7 NL@1:9 kw:mass@2:1 id:m@2:6 *@2:7 id:R@2:8 .@2:9 id:u@2:10 ^@2:11 num:2@2:12 "
        "+@2:14 id:x@2:16 '@2:17 ;@2:19 kw:input@2:21 id:_t0@2:27 END@2:30");
  CHECK(toks.front().pos.file == "f.mbs");
}

TEST_CASE("lexer: all punctuation", "[parse][lexer]") {
  CHECK(dump(lex("();,:.{}+-*/^='", "f")) ==
        "(@1:1 )@1:2 ;@1:3 ,@1:4 :@1:5 .@1:6 {@1:7 }@1:8 +@1:9 -@1:10 *@1:11 /@1:12 ^@1:13 =@1:14 '@1:15 "
        "END@1:16");
}

TEST_CASE("lexer: numbers as written", "[parse][lexer]") {
  CHECK(dump(lex("1 0.5 .5 1e-3 2.5E+2 1. 10e5 007", "f")) ==
        "num:1@1:1 num:0.5@1:3 num:.5@1:7 num:1e-3@1:10 num:2.5E+2@1:15 num:1.@1:22 num:10e5@1:25 num:007@1:30 "
        "END@1:33");
}

TEST_CASE("lexer: malformed numbers are single invalid tokens", "[parse][lexer]") {
  CHECK(dump(lex("2x 1e 1e+ 3.4e5q", "f")) ==
        "bad:malformed number '2x'@1:1 bad:malformed number '1e'@1:4 bad:malformed number '1e+'@1:7 "
        "bad:malformed number '3.4e5q'@1:11 END@1:17");
}

TEST_CASE("lexer: every reserved word is a keyword", "[parse][lexer]") {
  for (const char* w : {"model", "parameter", "input", "gravity", "include", "component", "subsystem", "body",
                        "coordinate", "speed", "constraint", "position", "velocity", "nonlinear", "force", "mass",
                        "inertia", "kinetic", "potential", "independent", "output", "energy"}) {
    INFO(w);
    const auto toks = lex(w, "f");
    REQUIRE(toks.size() == 2);
    CHECK(toks[0].kind == TokenKind::Keyword);
  }
  CHECK(lex("masses", "f")[0].kind == TokenKind::Ident);
  CHECK(lex("Mass", "f")[0].kind == TokenKind::Ident);
  CHECK(mbsc::parse::is_statement_keyword("mass"));
  CHECK_FALSE(mbsc::parse::is_statement_keyword("energy"));
}

TEST_CASE("lexer: comments, blank lines and CRLF collapse into one newline", "[parse][lexer]") {
  CHECK(dump(lex("# head\n\na # tail\r\n\n  # only a comment\n\nb\n", "f")) == "id:a@3:1 NL@3:9 id:b@7:1 NL@7:2 END@8:1");
  CHECK(dump(lex("", "f")) == "END@1:1");
  CHECK(dump(lex("\n\n# x", "f")) == "END@3:4");
}

TEST_CASE("lexer: strings", "[parse][lexer]") {
  CHECK(dump(lex("include \"lib/arm.mbs\"", "f")) == "kw:include@1:1 str:lib/arm.mbs@1:9 END@1:22");
  CHECK(dump(lex("include \"\"", "f")) == "kw:include@1:1 str:@1:9 END@1:11");
  CHECK(dump(lex("include \"abc\nx", "f")) == "kw:include@1:1 bad:unterminated string@1:9 NL@1:13 id:x@2:1 END@2:2");
}

TEST_CASE("lexer: unexpected characters", "[parse][lexer]") {
  CHECK(dump(lex("a @ b", "f")) == "id:a@1:1 bad:unexpected character '@'@1:3 id:b@1:5 END@1:6");
  CHECK(dump(lex("a\x01", "f")) == "id:a@1:1 bad:unexpected character '\\x01'@1:2 END@1:3");
  // A UTF-8 character is shown whole and counts as one column.
  CHECK(dump(lex("\xCE\xB8 = 1", "f")) == "bad:unexpected character '\xCE\xB8'@1:1 =@1:3 num:1@1:5 END@1:6");
  CHECK(dump(lex("# \xCE\xB8\xCE\xB8\nx \xE2\x82\xAC y", "f")) ==
        "id:x@2:1 bad:unexpected character '\xE2\x82\xAC'@2:3 id:y@2:5 END@2:6");
}

TEST_CASE("lexer: tokens are described for messages", "[parse][lexer]") {
  const auto toks = lex("x mass 1.5 \"a\" )\n", "f");
  CHECK(describe(toks[0]) == "'x'");
  CHECK(describe(toks[1]) == "keyword 'mass'");
  CHECK(describe(toks[2]) == "number '1.5'");
  CHECK(describe(toks[3]) == "string \"a\"");
  CHECK(describe(toks[4]) == "')'");
  CHECK(describe(toks[5]) == "newline");
  CHECK(describe(toks[6]) == "end of file");
}

TEST_CASE("lexer: number literals a double cannot hold are errors at their token", "[parse][lexer]") {
  CHECK(dump(lex("1e308 1.7976931348623157e308 2.2250738585072014e-308 0e99999999999999999999", "f")) ==
        "num:1e308@1:1 num:1.7976931348623157e308@1:7 num:2.2250738585072014e-308@1:30 "
        "num:0e99999999999999999999@1:54 END@1:76");
  CHECK(dump(lex("1e309", "f")) == "bad:number '1e309' is too large for a double (at most about 1.8e308)@1:1 END@1:6");
  CHECK(dump(lex("x 1e-400", "f")) ==
        "id:x@1:1 bad:number '1e-400' is too small for a double (nonzero, but below about 2.2e-308)@1:3 END@1:9");
  // Subnormal values are refused too: below the smallest normal double.
  CHECK(dump(lex("4e-320", "f")).find("too small for a double") != std::string::npos);
  const std::string long_literal = "0." + std::string(120, '1');
  CHECK(dump(lex(long_literal, "f")).find("is longer than 100 characters") != std::string::npos);
}

TEST_CASE("lexer: strings refuse control characters; a byte-order mark is skipped", "[parse][lexer]") {
  CHECK(dump(lex(std::string("include \"a\0b\"", 13), "f")) ==
        "kw:include@1:1 bad:control character '\\x00' in a string@1:9 END@1:14");
  CHECK(dump(lex("include \"a\x1b[2Jb\"", "f")) ==
        "kw:include@1:1 bad:control character '\\x1B' in a string@1:9 END@1:17");
  CHECK(dump(lex("\xEF\xBB\xBFmodel m", "f")) == "kw:model@1:1 id:m@1:7 END@1:8");
  // Only at the very start: elsewhere it is an unexpected character.
  CHECK(dump(lex("m \xEF\xBB\xBF", "f")).find("bad:unexpected character") != std::string::npos);
}

TEST_CASE("lexer: docs/language_syntax.md lists every keyword", "[lexer]") {
  std::ifstream in(std::string(MBSC_SOURCE_DIR) + "/docs/language_syntax.md");
  REQUIRE(in);
  const std::string doc((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // The fenced block after "**Keywords**": its words, and nothing but keywords in it.
  const auto heading = doc.find("**Keywords**");
  REQUIRE(heading != std::string::npos);
  const auto open = doc.find("```\n", heading), close = doc.find("```", open + 4);
  REQUIRE(close != std::string::npos);
  std::istringstream block(doc.substr(open + 4, close - open - 4));
  std::set<std::string> listed;
  for (std::string w; block >> w;) {
    INFO("listed as a keyword: " << w);
    CHECK(mbsc::parse::is_keyword(w));
    listed.insert(w);
  }
  for (const std::string& k : mbsc::parse::keyword_list()) {
    INFO("keyword missing from the list: " << k);
    CHECK(listed.count(k) == 1);
  }
}
