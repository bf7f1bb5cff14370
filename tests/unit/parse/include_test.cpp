// SPDX-License-Identifier: GPL-2.0-or-later
// Unit tests of parse_file: reading files and splicing includes.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "mbsc/parse/parse.hpp"

namespace fs = std::filesystem;
using mbsc::Diagnostics;
using Kind = mbsc::ast::Statement::Kind;

namespace {

/// A fresh folder under the system temp folder, removed at the end of the test.
class TempDir {
 public:
  TempDir() {
    std::random_device rd;
    path_ = fs::temp_directory_path() / ("mbsc_parse_test_" + std::to_string(rd()) + std::to_string(rd()));
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  /// Writes `text` to `rel` (folders created) and returns its full path as a string.
  std::string write(const std::string& rel, const std::string& text) const {
    const fs::path p = path_ / rel;
    fs::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }
  std::string at(const std::string& rel) const { return (path_ / rel).string(); }

 private:
  fs::path path_;
};

std::vector<std::string> names(const mbsc::ast::File& f) {
  std::vector<std::string> out;
  for (const auto& s : f.statements) out.push_back(s->name);
  return out;
}

}  // namespace

TEST_CASE("include: statements are spliced in place, recursively and relative to the includer",
          "[parse][include]") {
  TempDir dir;
  const std::string main = dir.write("main.mbs",
                                     "model m\n"
                                     "include \"lib/params.mbs\"\n"
                                     "output energy\n");
  dir.write("lib/params.mbs",
            "parameter a\n"
            "include \"more/extra.mbs\"   # relative to lib/\n"
            "parameter b\n");
  dir.write("lib/more/extra.mbs", "input u\nsubsystem s : k { mass a }\n");

  Diagnostics diags;
  const auto file = mbsc::parse::parse_file(main, diags);
  INFO(diags.format());
  REQUIRE(file.has_value());
  CHECK(file->path == main);
  CHECK(names(*file) == std::vector<std::string>{"m", "a", "u", "s", "b", "energy"});
  const auto& s = file->statements;
  CHECK(s[0]->pos.file == main);
  CHECK(s[1]->pos.file == dir.at("lib/params.mbs"));
  CHECK(s[1]->pos.line == 1);
  CHECK(s[2]->kind == Kind::Input);
  CHECK(s[2]->pos.file == dir.at("lib/more/extra.mbs"));
  CHECK(s[3]->body.at(0)->value->pos.file == dir.at("lib/more/extra.mbs"));
  CHECK(s[4]->pos.file == dir.at("lib/params.mbs"));
  CHECK(s[4]->pos.line == 3);
  CHECK(s[5]->pos.file == main);
  for (const auto& st : s) CHECK(st->kind != Kind::Include);
}

TEST_CASE("include: the same file may be included twice when it is not a cycle", "[parse][include]") {
  TempDir dir;
  const std::string main = dir.write("main.mbs", "include \"p.mbs\"\ninclude \"./p.mbs\"\n");
  dir.write("p.mbs", "parameter a\n");
  Diagnostics diags;
  const auto file = mbsc::parse::parse_file(main, diags);
  REQUIRE(file.has_value());
  CHECK(names(*file) == std::vector<std::string>{"a", "a"});
}

TEST_CASE("include: a cycle is an error at the include statement that closes it", "[parse][include]") {
  TempDir dir;
  const std::string a = dir.write("a.mbs", "model m\ninclude \"sub/b.mbs\"\n");
  const std::string b = dir.write("sub/b.mbs", "parameter p\n\n  include \"../a.mbs\"\n");
  Diagnostics diags;
  CHECK_FALSE(mbsc::parse::parse_file(a, diags).has_value());
  REQUIRE(diags.all().size() == 1);
  const auto& d = diags.all()[0];
  CHECK(d.message == "cyclic include of '../a.mbs'");
  CHECK(d.pos.file == b);
  CHECK(d.pos.line == 3);
  CHECK(d.pos.col == 3);
}

TEST_CASE("include: a file including itself is a cycle", "[parse][include]") {
  TempDir dir;
  const std::string a = dir.write("self.mbs", "include \"self.mbs\"\n");
  Diagnostics diags;
  CHECK_FALSE(mbsc::parse::parse_file(a, diags).has_value());
  REQUIRE(diags.all().size() == 1);
  CHECK(diags.all()[0].message == "cyclic include of 'self.mbs'");
  CHECK(mbsc::to_string(diags.all()[0].pos) == a + ":1:1");
}

TEST_CASE("include: a missing included file is an error at the include statement", "[parse][include]") {
  TempDir dir;
  const std::string main = dir.write("main.mbs", "model m\n  include \"nope.mbs\"\ninclude \"lib\"\nmass )\n");
  fs::create_directories(dir.at("lib"));
  Diagnostics diags;
  CHECK_FALSE(mbsc::parse::parse_file(main, diags).has_value());
  REQUIRE(diags.all().size() == 3);
  // The syntax error of the file itself is reported first, then the includes in order.
  CHECK(mbsc::to_string(diags.all()[0].pos) == main + ":4:6");
  CHECK(mbsc::to_string(diags.all()[1].pos) == main + ":2:3");
  CHECK(diags.all()[1].message.find("cannot read file") == 0);
  CHECK(diags.all()[1].message.find("nope.mbs': no such file") != std::string::npos);
  CHECK(mbsc::to_string(diags.all()[2].pos) == main + ":3:1");
  CHECK(diags.all()[2].message.find("cannot read file") == 0);
  CHECK(diags.all()[2].message.find("is a folder") != std::string::npos);
}

TEST_CASE("include: a missing top file is an error without a line", "[parse][include]") {
  TempDir dir;
  const std::string missing = dir.at("missing.mbs");
  Diagnostics diags;
  CHECK_FALSE(mbsc::parse::parse_file(missing, diags).has_value());
  REQUIRE(diags.all().size() == 1);
  CHECK(diags.all()[0].pos.file == missing);
  CHECK(diags.all()[0].pos.line == 0);
  CHECK(diags.all()[0].pos.col == 0);
  CHECK(diags.all()[0].message.find("cannot read file") == 0);
  CHECK(diags.format() == missing + ": error: cannot read file '" + missing + "': no such file\n");
}

TEST_CASE("include: syntax errors in included files carry their own path", "[parse][include]") {
  TempDir dir;
  const std::string main = dir.write("main.mbs", "include \"x.mbs\"\nmass @\n");
  dir.write("x.mbs", "model m\nbodyy b\n");
  Diagnostics diags;
  CHECK_FALSE(mbsc::parse::parse_file(main, diags).has_value());
  REQUIRE(diags.all().size() == 2);
  CHECK(mbsc::to_string(diags.all()[0].pos) == main + ":2:6");
  CHECK(mbsc::to_string(diags.all()[1].pos) == dir.at("x.mbs") + ":2:1");
  CHECK(diags.all()[1].message == "unknown statement 'bodyy' (did you mean 'body'?)");
}

TEST_CASE("include: relative paths given to parse_file work", "[parse][include]") {
  TempDir dir;
  dir.write("m/main.mbs", "include \"p.mbs\"\n");
  dir.write("m/p.mbs", "parameter a\n");
  const fs::path old = fs::current_path();
  fs::current_path(dir.at(""));
  Diagnostics diags;
  const auto file = mbsc::parse::parse_file("m/main.mbs", diags);
  fs::current_path(old);
  INFO(diags.format());
  REQUIRE(file.has_value());
  CHECK(file->path == "m/main.mbs");
  REQUIRE(file->statements.size() == 1);
  CHECK(file->statements[0]->pos.file == "m/p.mbs");
}

TEST_CASE("include: the file lists every file read, once, as opened (for --depfile)", "[parse][include]") {
  TempDir dir;
  const std::string main = dir.write("main.mbs",
                                     "model m\n"
                                     "include \"lib/params.mbs\"\n"
                                     "include \"./lib/params.mbs\"   # the same file again\n"
                                     "include \"my data.mbs\"\n");
  dir.write("lib/params.mbs", "parameter a\ninclude \"more/extra.mbs\"\n");
  dir.write("lib/more/extra.mbs", "input u\n");
  dir.write("my data.mbs", "parameter b\n");
  Diagnostics diags;
  const auto file = mbsc::parse::parse_file(main, diags);
  INFO(diags.format());
  REQUIRE(file.has_value());
  CHECK(file->sources == std::vector<std::string>{main, dir.at("lib/params.mbs"), dir.at("lib/more/extra.mbs"),
                                                  dir.at("my data.mbs")});
}
