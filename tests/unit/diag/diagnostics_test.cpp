// SPDX-License-Identifier: GPL-2.0-or-later
// Unit tests of the diagnostics: terminal-safe text, and the cap on printed messages.
#include <catch2/catch.hpp>

#include <string>

#include "mbsc/diag/diagnostics.hpp"

using mbsc::Diagnostics;
using mbsc::printable;
using mbsc::SourcePos;

TEST_CASE("printable keeps valid UTF-8 and escapes control characters and bad bytes", "[diag]") {
  CHECK(printable("plain text, 1.5 m/s") == "plain text, 1.5 m/s");
  CHECK(printable("θ and ω, 日本, 😀") == "θ and ω, 日本, 😀");
  CHECK(printable(std::string("a\0b", 3)) == "a\\x00b");
  CHECK(printable("\x1b]0;title\x07\x1b[2J") == "\\x1B]0;title\\x07\\x1B[2J");
  CHECK(printable("tab\there\nline\r") == "tab\\x09here\\x0Aline\\x0D");
  CHECK(printable("del\x7f") == "del\\x7F");
  // C1 controls (U+0080..U+009F, e.g. the 8-bit CSI U+009B) act on some terminals.
  CHECK(printable("\xc2\x9b" "2J") == "\\xC2\\x9B2J");
  // Not UTF-8: a lone continuation byte, a truncated sequence, an overlong form, a surrogate.
  CHECK(printable("\x80") == "\\x80");
  CHECK(printable("\xe2\x82") == "\\xE2\\x82");
  CHECK(printable("\xc0\xaf") == "\\xC0\\xAF");
  CHECK(printable("\xed\xa0\x80") == "\\xED\\xA0\\x80");
  CHECK(printable("\xf4\x90\x80\x80") == "\\xF4\\x90\\x80\\x80");
}

TEST_CASE("diagnostics print escaped text and at most kMaxShown messages", "[diag]") {
  Diagnostics d;
  d.error(SourcePos{"a\x1b.mbs", 2, 3}, "bad \x07 bell");
  CHECK(d.format() == "a\\x1B.mbs:2:3: error: bad \\x07 bell\n");
  for (int i = 0; i < 250; ++i) d.error(SourcePos{"f", i + 1, 1}, "e");
  CHECK(d.error_count() == 251);
  CHECK(d.all().size() == Diagnostics::kMaxShown);
  const std::string text = d.format();
  CHECK(text.find("mbsc: 151 more diagnostic(s) not shown\n") != std::string::npos);
  CHECK(text.find("f:99:1: error") != std::string::npos);
  CHECK(text.find("f:100:1: error") == std::string::npos);
}

TEST_CASE("the same warning at the same place is kept once", "[diag]") {
  // A derivation runs once per independent set: its warnings must not repeat.
  Diagnostics d;
  d.warning(SourcePos{"f", 9, 1}, "singular");
  d.warning(SourcePos{"f", 9, 1}, "singular");
  d.warning(SourcePos{"f", 10, 1}, "singular");
  d.warning(SourcePos{"f", 9, 1}, "other");
  CHECK(d.all().size() == 3);
  CHECK(d.format() == "f:9:1: warning: singular\nf:10:1: warning: singular\nf:9:1: warning: other\n");
  CHECK_FALSE(d.has_errors());
}
