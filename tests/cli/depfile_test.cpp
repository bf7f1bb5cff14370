// SPDX-License-Identifier: GPL-2.0-or-later
// generate --depfile: what the depfile says, that make reads it as meant (a real make
// run), and that it is written all or nothing with the generated folder.
#include <catch2/catch.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "run_command.hpp"

using namespace mbsc_test;
namespace fs = std::filesystem;

namespace {

const std::string kMbsc = MBSC_BINARY;

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// A pendulum whose data comes from "my data.mbs", which includes lib/more.mbs.
void write_model(const fs::path& dir) {
  write(dir / "main.mbs",
        "model pend\n"
        "include \"my data.mbs\"\n"
        "gravity (0, -g)\n"
        "body bob : particle2d { mass m }\n"
        "coordinate th\n"
        "speed w = th'\n"
        "constraint position {\n"
        "  bx: bob.x = l*sin(th)\n"
        "  by: bob.y = -l*cos(th)\n"
        "}\n"
        "independent w\n");
  write(dir / "my data.mbs", "parameter m = 1, l = 2\ninclude \"lib/more.mbs\"\n");
  write(dir / "lib" / "more.mbs", "parameter g = 9.81\n");
}

std::string in(const fs::path& dir, const std::string& command) { return "cd " + quote(dir.string()) + " && " + command; }

}  // namespace

TEST_CASE("generate --depfile lists the model and every file it includes", "[cli][depfile]") {
  const fs::path dir = fresh_dir("depfile");
  write_model(dir);
  auto r = run(in(dir, kMbsc + " generate main.mbs -o out --depfile deps/pend.d --quiet"));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(read(dir / "deps" / "pend.d") ==
        "out/pend/pend.hpp out/pend/pend.cpp: main.mbs \\\n"
        "  my\\ data.mbs \\\n"
        "  lib/more.mbs\n"
        "\n"
        "my\\ data.mbs:\n"
        "\n"
        "lib/more.mbs:\n");
  CHECK(fs::exists(dir / "out" / "pend" / "pend.cpp"));
  for (const auto& e : fs::directory_iterator(dir / "deps")) CHECK(e.path().filename() == "pend.d");

  // --name renames the targets; the sources stay.
  r = run(in(dir, kMbsc + " generate main.mbs -o out --name other --depfile deps/other.d --quiet"));
  REQUIRE(r.exit_code == 0);
  CHECK(read(dir / "deps" / "other.d").rfind("out/other/other.hpp out/other/other.cpp: main.mbs \\\n", 0) == 0);
  fs::remove_all(dir);
}

TEST_CASE("generate --depfile: make reads it (a changed or removed include makes the code stale)", "[cli][depfile]") {
  const fs::path dir = fresh_dir("depfile_make");
  write_model(dir);
  REQUIRE(run(in(dir, kMbsc + " generate main.mbs -o out --depfile out/pend.d --quiet")).exit_code == 0);
  write(dir / "Makefile", "out/pend/pend.cpp: ; @echo regenerate\ninclude out/pend.d\n");
  const std::string make_q = in(dir, "make -q out/pend/pend.cpp");
  CHECK(run(make_q).exit_code == 0);  // up to date
  const auto now = fs::last_write_time(dir / "lib" / "more.mbs");
  fs::last_write_time(dir / "lib" / "more.mbs", now + std::chrono::hours(1));
  CHECK(run(make_q).exit_code == 1);  // the file two includes deep changed: stale
  fs::last_write_time(dir / "lib" / "more.mbs", now);
  CHECK(run(make_q).exit_code == 0);
  const auto when = fs::last_write_time(dir / "my data.mbs");
  fs::last_write_time(dir / "my data.mbs", when + std::chrono::hours(1));  // the path with a space
  CHECK(run(make_q).exit_code == 1);
  fs::last_write_time(dir / "my data.mbs", when);
  // An include that is gone: stale, not make's "No rule to make target" (exit 2).
  fs::remove(dir / "lib" / "more.mbs");
  auto r = run(make_q);
  INFO(r.output);
  CHECK(r.exit_code == 1);
  fs::remove_all(dir);
}

TEST_CASE("generate --depfile is written with the code or not at all", "[cli][depfile]") {
  const fs::path dir = fresh_dir("depfile_fail");
  write_model(dir);
  write(dir / "old.d", "previous contents\n");
  // An error in an included file: exit 1, the old depfile untouched, nothing new.
  write(dir / "lib" / "more.mbs", "parameter g = \n");
  auto r = run(in(dir, kMbsc + " generate main.mbs -o out --depfile old.d --quiet"));
  CHECK(r.exit_code == 1);
  CHECK(read(dir / "old.d") == "previous contents\n");
  CHECK_FALSE(fs::exists(dir / "out" / "pend"));
  // The output folder refused (not mbsc's): the depfile is not written either.
  write(dir / "lib" / "more.mbs", "parameter g = 9.81\n");
  write(dir / "out" / "pend" / "mine.txt", "a user's file\n");
  r = run(in(dir, kMbsc + " generate main.mbs -o out --depfile new.d --quiet"));
  CHECK(r.exit_code == 1);
  CHECK_FALSE(fs::exists(dir / "new.d"));
  fs::remove_all(dir / "out");
  // A depfile that would overwrite a source or a generated file, or is a folder.
  r = run(in(dir, kMbsc + " generate main.mbs -o out --depfile 'my data.mbs' --quiet"));
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("is the model or a file it includes") != std::string::npos);
  CHECK(read(dir / "my data.mbs") == "parameter m = 1, l = 2\ninclude \"lib/more.mbs\"\n");
  r = run(in(dir, kMbsc + " generate main.mbs -o out --depfile out/pend/pend.cpp --quiet"));
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("is one of the files generate writes") != std::string::npos);
  r = run(in(dir, kMbsc + " generate main.mbs -o out --depfile lib --quiet"));
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("names a folder") != std::string::npos);
  // A ';' in a path would start a recipe: make would run what follows as a command.
  fs::create_directories(dir / "a;touch PWNED");
  r = run(in(dir, kMbsc + " generate main.mbs -o 'a;touch PWNED' --depfile x.d --quiet"));
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("starts a recipe") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "x.d"));
  CHECK_FALSE(fs::exists(dir / "PWNED"));
  fs::remove_all(dir / "a;touch PWNED");
  CHECK_FALSE(fs::exists(dir / "out" / "pend"));
  // No temporary file left anywhere.
  for (const auto& e : fs::recursive_directory_iterator(dir))
    CHECK(e.path().filename().string().find("mbsc-tmp") == std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("generate --depfile inside OUT/NAME is refused before anything is created, in either order", "[cli][depfile]") {
  const fs::path dir = fresh_dir("depfile_inside");
  write_model(dir);
  // First use, nothing there yet: refused, and no folder left to block the next run.
  auto r = run(in(dir, kMbsc + " generate main.mbs -o out --depfile out/pend/pend.d --quiet"));
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("--depfile 'out/pend/pend.d' is inside the output folder 'out/pend'") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "out"));
  r = run(in(dir, kMbsc + " generate main.mbs -o out --quiet"));
  CHECK(r.exit_code == 0);
  const std::string code = read(dir / "out" / "pend" / "pend.cpp");
  // The folder written first: refused the same way (deeper too), the folder as it was.
  r = run(in(dir, kMbsc + " generate main.mbs -o out --depfile out/pend/deps/pend.d --quiet"));
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("is inside the output folder") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "out" / "pend" / "deps"));
  CHECK(read(dir / "out" / "pend" / "pend.cpp") == code);
  CHECK(run(in(dir, kMbsc + " generate main.mbs -o out --depfile out/pend.d --quiet")).exit_code == 0);
  CHECK(fs::exists(dir / "out" / "pend.d"));
  fs::remove_all(dir);
}

TEST_CASE("generate --depfile: a refused output folder leaves no depfile folder behind", "[cli][depfile]") {
  const fs::path dir = fresh_dir("depfile_no_folder");
  write_model(dir);
  write(dir / "out" / "pend" / "mine.txt", "a user's file\n");  // not mbsc's: refused
  const auto r = run(in(dir, kMbsc + " generate main.mbs -o out --depfile deps/sub/pend.d --quiet"));
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("was not written by mbsc") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "deps"));
  fs::remove_all(dir);
}

TEST_CASE("generate --depfile that is a hard link of the model is refused", "[cli][depfile]") {
  const fs::path dir = fresh_dir("depfile_hard_link");
  write_model(dir);
  fs::create_hard_link(dir / "lib" / "more.mbs", dir / "deps.d");
  const auto r = run(in(dir, kMbsc + " generate main.mbs -o out --depfile deps.d --quiet"));
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("--depfile 'deps.d' is the model or a file it includes") != std::string::npos);
  CHECK(read(dir / "lib" / "more.mbs") == "parameter g = 9.81\n");
  CHECK_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}
