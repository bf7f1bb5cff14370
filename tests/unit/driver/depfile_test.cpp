// SPDX-License-Identifier: GPL-2.0-or-later
// Unit tests of the depfile text (generate --depfile): make's escaping rules, and the
// rule layout make and ninja read.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "mbsc/driver/depfile.hpp"

using mbsc::driver::depfile_text;
using mbsc::driver::make_escaped;

TEST_CASE("depfile: paths are escaped as make reads them", "[driver][depfile]") {
  CHECK(make_escaped("models/plain.mbs") == "models/plain.mbs");
  CHECK(make_escaped("my models/a b.mbs") == "my\\ models/a\\ b.mbs");
  CHECK(make_escaped("tab\there") == "tab\\\there");
  CHECK(make_escaped("issue#9.mbs") == "issue\\#9.mbs");
  CHECK(make_escaped("cost$1.mbs") == "cost$$1.mbs");
  // Backslashes right before an escaped character are doubled (else make would read
  // "\\ " as an escaped backslash and a separator); others stay as they are.
  CHECK(make_escaped("a\\ b") == "a\\\\\\ b");
  CHECK(make_escaped("a\\b") == "a\\b");
  CHECK(make_escaped("a\\\t") == "a\\\\\\\t");
}

TEST_CASE("depfile: a path with a colon, or a backslash before '#', is refused, naming it", "[driver][depfile]") {
  std::string text = "unchanged", error;
  CHECK_FALSE(depfile_text({"o/x/x.hpp"}, {"x.mbs", "lib/a:b.mbs"}, text, error));
  CHECK(error.find("'lib/a:b.mbs' holds ':'") != std::string::npos);
  CHECK_FALSE(depfile_text({"o:/x/x.hpp"}, {"x.mbs"}, text, error));
  CHECK(error.find("'o:/x/x.hpp' holds ':'") != std::string::npos);
  // A path a\#b: make reads a depfile's a\\\#b as a\#b, ninja as a\\#b; ninja reads a\\#b
  // as a\#b, make as a\ and a comment.
  CHECK_FALSE(depfile_text({"o/x/x.hpp"}, {"x.mbs", "lib/a\\#b.mbs"}, text, error));
  CHECK(error.find("'lib/a\\#b.mbs' has a '\\' before a '#'") != std::string::npos);
  CHECK(text == "unchanged");
}

TEST_CASE("depfile: one rule for every target, and an empty rule per included file", "[driver][depfile]") {
  std::string text, error;
  REQUIRE(depfile_text({"out/m/m.hpp", "out/m/m.cpp"}, {"dir/m.mbs", "dir/lib/a b.mbs", "dir/c.mbs"}, text, error));
  CHECK(text ==
        "out/m/m.hpp out/m/m.cpp: dir/m.mbs \\\n"
        "  dir/lib/a\\ b.mbs \\\n"
        "  dir/c.mbs\n"
        "\n"
        "dir/lib/a\\ b.mbs:\n"
        "\n"
        "dir/c.mbs:\n");
  // A model without includes: the rule alone.
  REQUIRE(depfile_text({"o/x/x.hpp", "o/x/x.cpp"}, {"x.mbs"}, text, error));
  CHECK(text == "o/x/x.hpp o/x/x.cpp: x.mbs\n");
}

TEST_CASE("depfile: a path with a line break is refused, naming it", "[driver][depfile]") {
  std::string text = "unchanged", error;
  CHECK_FALSE(depfile_text({"o/x/x.hpp"}, {"x.mbs", "bad\nname.mbs"}, text, error));
  CHECK(error.find("line break") != std::string::npos);
  CHECK(error.find("bad\\x0Aname.mbs") != std::string::npos);
  CHECK_FALSE(depfile_text({"o/\rx/x.hpp"}, {"x.mbs"}, text, error));
}

TEST_CASE("depfile: every character make or ninja would read as syntax is refused, naming it", "[driver][depfile]") {
  // ';' starts a recipe (a command make runs), '=' a target-specific variable, '|'
  // order-only prerequisites, '%' a pattern rule, '&' grouped targets, parentheses an
  // archive member, wildcards a glob; control characters end the rule.
  for (const char c : std::string(";=|%&()*?[]\n\r\x01\x7f")) {
    const std::string path = std::string("dir/a") + c + "b.mbs";
    std::string text = "unchanged", error;
    INFO(static_cast<int>(c));
    CHECK_FALSE(depfile_text({"o/x/x.hpp"}, {"x.mbs", path}, text, error));
    CHECK(text == "unchanged");
    CHECK(error.find("a depfile cannot hold it") != std::string::npos);
    CHECK_FALSE(depfile_text({"o/x" + std::string(1, c) + "/x.hpp"}, {"x.mbs"}, text, error));
  }
  // What has an escape stays allowed: spaces, tabs, '#', '$'.
  std::string text, error;
  CHECK(depfile_text({"o/x y/x.hpp"}, {"a b.mbs", "c\td.mbs", "e#f.mbs", "g$h.mbs"}, text, error));
}
