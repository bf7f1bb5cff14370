// SPDX-License-Identifier: GPL-2.0-or-later
// Hostile and mistaken input that cannot live in tests/data/bad as a plain file (it is
// huge, binary, made of many files, or about the command line and the output folder).
// The contract for each: a clear error (file:line:col where there is a line), exit code
// 1, nothing written, within seconds. Every command runs under `timeout`, so a hang
// fails the test instead of stalling the suite.
#include <sys/stat.h>

#include <catch2/catch.hpp>
#include <algorithm>
#include <fstream>
#include <regex>
#include <sstream>

#include "run_command.hpp"

namespace fs = std::filesystem;
using namespace mbsc_test;

namespace {

const std::string kMbsc = std::string("timeout 120 ") + MBSC_BINARY;


std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

const std::string kBody = "body b : particle2d { mass 1 }\n";

/// Everything below `dir`, as relative paths (to see that nothing else was written).
std::vector<std::string> listing(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) out.push_back(fs::relative(e.path(), dir).string());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

TEST_CASE("generate never destroys a folder it did not write", "[cli][robust][output]") {
  const fs::path dir = fresh_dir("out_safety");
  write(dir / "src.mbs", "model src\n" + kBody);
  // The user's own src/ with their code in it.
  fs::create_directories(dir / "src");
  write(dir / "src" / "main.cpp", "int main() {}\n");
  const std::string cmd = kMbsc + " generate " + quote((dir / "src.mbs").string()) + " -o " + quote(dir.string());

  auto r = run(cmd);
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("was not written by mbsc") != std::string::npos);
  CHECK(r.output.find("--force") != std::string::npos);
  CHECK(slurp(dir / "src" / "main.cpp") == "int main() {}\n");
  CHECK(listing(dir) == std::vector<std::string>{"src", "src.mbs", "src/main.cpp"});

  // --force writes mbsc's files into it and removes nothing.
  r = run(cmd + " --force");
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(slurp(dir / "src" / "main.cpp") == "int main() {}\n");
  CHECK(fs::exists(dir / "src" / "src.hpp"));
  CHECK(fs::exists(dir / "src" / "src.cpp"));
  CHECK(fs::exists(dir / "src" / ".mbsc-generated"));

  // Now the folder carries the marker: generating again replaces only mbsc's files.
  write(dir / "src" / "src.cpp", "stale");
  r = run(cmd);
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(slurp(dir / "src" / "src.cpp") != "stale");
  CHECK(slurp(dir / "src" / "main.cpp") == "int main() {}\n");
  CHECK(listing(dir) ==
        std::vector<std::string>{"src", "src.mbs", "src/.mbsc-generated", "src/main.cpp", "src/src.cpp", "src/src.hpp"});
  fs::remove_all(dir);
}

TEST_CASE("generate replaces exactly the files its marker lists", "[cli][robust][output]") {
  const fs::path dir = fresh_dir("out_marker");
  write(dir / "m.mbs", "model m\n" + kBody);
  const std::string cmd = kMbsc + " generate " + quote((dir / "m.mbs").string()) + " -o " + quote(dir.string());
  REQUIRE(run(cmd).exit_code == 0);
  const std::string marker = slurp(dir / "m" / ".mbsc-generated");
  CHECK(marker.find("\nm.hpp\nm.cpp\n") != std::string::npos);
  // A file an earlier version wrote (listed) goes; files the user added (not listed)
  // and entries that would leave the folder are left alone.
  write(dir / "m" / "old.cpp", "old");
  write(dir / "m" / "mine.cpp", "mine");
  write(dir / "keep.txt", "keep");
  write(dir / "m" / ".mbsc-generated", marker + "old.cpp\n../keep.txt\n/etc/passwd\n");
  auto r = run(cmd);
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK_FALSE(fs::exists(dir / "m" / "old.cpp"));
  CHECK(slurp(dir / "m" / "mine.cpp") == "mine");
  CHECK(slurp(dir / "keep.txt") == "keep");
  CHECK(slurp(dir / "m" / ".mbsc-generated") == marker);
  // No temporary folder is left next to it.
  for (const auto& e : fs::directory_iterator(dir)) CHECK(e.path().filename().string().find("mbsc-tmp") == std::string::npos);
  // One left by an interrupted run is cleared, unless it holds something mbsc never writes.
  fs::create_directories(dir / ".m.mbsc-tmp-a1B2c3");
  write(dir / ".m.mbsc-tmp-a1B2c3" / "m.cpp", "half");
  fs::create_directories(dir / ".m.mbsc-tmp-zzzzzz");
  write(dir / ".m.mbsc-tmp-zzzzzz" / "notes.txt", "mine");
  r = run(cmd);
  CHECK(r.exit_code == 0);
  CHECK_FALSE(fs::exists(dir / ".m.mbsc-tmp-a1B2c3"));
  CHECK(slurp(dir / ".m.mbsc-tmp-zzzzzz" / "notes.txt") == "mine");
  fs::remove_all(dir);
}

TEST_CASE("generate refuses a target that is a file or a link", "[cli][robust][output]") {
  const fs::path dir = fresh_dir("out_kinds");
  write(dir / "m.mbs", "model m\n" + kBody);
  const std::string cmd = kMbsc + " generate " + quote((dir / "m.mbs").string()) + " -o " + quote(dir.string());
  write(dir / "m", "a file the user wrote");
  for (const char* extra : {"", " --force"}) {
    auto r = run(cmd + extra);
    INFO(r.output);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("exists and is not a folder") != std::string::npos);
    CHECK(slurp(dir / "m") == "a file the user wrote");
  }
  fs::remove(dir / "m");
  fs::create_directories(dir / "elsewhere");
  fs::create_directory_symlink(dir / "elsewhere", dir / "m");
  auto r = run(cmd);
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("symbolic link") != std::string::npos);
  CHECK(fs::is_empty(dir / "elsewhere"));
  // An output folder that is a file.
  write(dir / "file", "x");
  r = run(kMbsc + " generate " + quote((dir / "m.mbs").string()) + " -o " + quote((dir / "file").string()));
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(slurp(dir / "file") == "x");
  fs::remove_all(dir);
}

TEST_CASE("long flat sums are fine; nesting and operand counts have limits", "[cli][robust]") {
  const fs::path dir = fresh_dir("long_expr");
  // 60 000 terms used to overflow the stack: a flat sum is linear work now.
  std::string sum = "1";
  for (int i = 1; i < 60000; ++i) sum += "+1";
  write(dir / "sum.mbs", "model s\nparameter a = " + sum + "\nbody b : particle2d { mass a }\n");
  auto r = run(kMbsc + " check " + quote((dir / "sum.mbs").string()));
  INFO(r.output.substr(0, 2000));
  CHECK(r.exit_code == 0);

  std::string many = "x";
  for (int i = 1; i < 100002; ++i) many += "*x";
  write(dir / "many.mbs", "model s\ncoordinate x\nspeed u = x'\noutput y = " + many + "\n");
  r = run(kMbsc + " check " + quote((dir / "many.mbs").string()));
  INFO(r.output.substr(0, 2000));
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("many.mbs:4:") != std::string::npos);
  CHECK(r.output.find("more than 100000 operands in one product") != std::string::npos);

  for (const std::string& deep : {std::string(100000, '(') + "1" + std::string(100000, ')'), std::string(100000, '-') + "1",
                                  "2" + std::string(50000, '^') + "2"}) {
    write(dir / "deep.mbs", "model s\nparameter a = " + deep + "\n" + kBody);
    r = run(kMbsc + " check " + quote((dir / "deep.mbs").string()));
    INFO(r.output.substr(0, 2000));
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("deep.mbs:2:") != std::string::npos);
  }
  // The same inside a loop bound and an index (the loop expander has its own evaluator).
  write(dir / "loop.mbs", "model s\nfor i = 1 to " + std::string(100000, '-') + "1 { }\n" + kBody);
  r = run(kMbsc + " check " + quote((dir / "loop.mbs").string()));
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("nests more than") != std::string::npos);
  write(dir / "index.mbs", "model s\noutput y = x[" + std::string(100000, '(') + "1" + std::string(100000, ')') + "]\n" + kBody);
  r = run(kMbsc + " check " + quote((dir / "index.mbs").string()));
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("index.mbs:2:") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("reading is bounded: devices, pipes, huge and unreadable files", "[cli][robust][read]") {
  const fs::path dir = fresh_dir("reading");
  auto r = run(kMbsc + " check /dev/zero");
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("/dev/zero: error: cannot read file '/dev/zero': is not a regular file") != std::string::npos);

  // A named pipe with no writer: opening it must not wait.
  REQUIRE(::mkfifo((dir / "pipe.mbs").c_str(), 0600) == 0);
  write(dir / "m.mbs", "model m\ninclude \"pipe.mbs\"\n" + kBody);
  r = run(kMbsc + " check " + quote((dir / "m.mbs").string()));
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("m.mbs:2:1: error: cannot read file") != std::string::npos);

  // A file larger than the limit, included.
  {
    std::ofstream big(dir / "big.mbs", std::ios::binary);
    const std::string line(1023, '#');
    for (int i = 0; i < 17 * 1024; ++i) big << line << '\n';
  }
  write(dir / "m.mbs", "model m\ninclude \"big.mbs\"\n" + kBody);
  r = run(kMbsc + " check " + quote((dir / "m.mbs").string()));
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("m.mbs:2:1: error: cannot read file") != std::string::npos);
  CHECK(r.output.find("is larger than the limit of 16 MiB") != std::string::npos);

  // A read error is an error, never an empty file.
  r = run(kMbsc + " check /proc/self/mem");
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("cannot read file '/proc/self/mem'") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("includes are bounded in total, not only in depth", "[cli][robust][read]") {
  const fs::path dir = fresh_dir("include_bomb");
  // 41 files, each including the next one twice: 2^40 splices without a total budget.
  for (int i = 0; i < 40; ++i)
    write(dir / ("f" + std::to_string(i) + ".mbs"),
          "include \"f" + std::to_string(i + 1) + ".mbs\"\ninclude \"f" + std::to_string(i + 1) + ".mbs\"\n");
  write(dir / "f40.mbs", "# empty\n");
  write(dir / "m.mbs", "model m\n" + kBody + "include \"f0.mbs\"\n");
  auto r = run(kMbsc + " check " + quote((dir / "m.mbs").string()));
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("more than 10000 includes spliced in all") != std::string::npos);
  // One message, not one per remaining include.
  CHECK(std::count(r.output.begin(), r.output.end(), '\n') <= 3);
  fs::remove_all(dir);
}

TEST_CASE("component instances are bounded in number, not only in depth", "[cli][robust]") {
  const fs::path dir = fresh_dir("component_bomb");
  // Each component holds two instances of the one before: 2^40 subsystems.
  std::string text = "model comps\ncomponent C0() { body p : particle2d { mass 1 } }\n";
  for (int i = 1; i <= 40; ++i)
    text += "component C" + std::to_string(i) + "() { subsystem a : C" + std::to_string(i - 1) + "()\n subsystem b : C" +
            std::to_string(i - 1) + "() }\n";
  write(dir / "m.mbs", text + "subsystem top : C40()\n");
  auto r = run(kMbsc + " check " + quote((dir / "m.mbs").string()));
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("m.mbs:2:23: error: the model has more than 100000 subsystems") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("file names and strings with control bytes never reach the terminal raw", "[cli][robust][read]") {
  const fs::path dir = fresh_dir("control_bytes");
  write(dir / "nul.mbs", std::string("model m\ninclude \"a\0b.mbs\"\n", 26) + kBody);
  auto r = run(kMbsc + " check " + quote((dir / "nul.mbs").string()));
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("nul.mbs:2:9: error: control character '\\x00' in a string") != std::string::npos);

  write(dir / "esc.mbs", "model m\ninclude \"\x1b]0;pwned\x07\x1b[2J.mbs\"\n" + kBody);
  r = run(kMbsc + " check " + quote((dir / "esc.mbs").string()));
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("esc.mbs:2:9: error: control character '\\x1B' in a string") != std::string::npos);
  CHECK(r.output.find('\x1b') == std::string::npos);
  CHECK(r.output.find('\x07') == std::string::npos);

  // A file whose own name holds an escape: the message escapes it.
  const fs::path odd = dir / "odd\x1b[31m.mbs";
  write(odd, "model m\nbody b : particle2d { mass -1 }\n");
  r = run(kMbsc + " check " + quote(odd.string()));
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("odd\\x1B[31m.mbs:2:28: error: mass of body 'b' is negative") != std::string::npos);
  CHECK(r.output.find('\x1b') == std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("a UTF-8 byte-order mark is accepted and changes nothing", "[cli][robust][read]") {
  const fs::path dir = fresh_dir("bom");
  const std::string model = slurp(fs::path(MBSC_SOURCE_DIR) / "models" / "double_pendulum.mbs");
  write(dir / "double_pendulum.mbs", "\xEF\xBB\xBF" + model);
  auto r = run(kMbsc + " generate " + quote((dir / "double_pendulum.mbs").string()) + " -o " + quote((dir / "out").string()));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  // Same code as the golden, but for the banner's hash of the source text.
  auto body = [](const std::string& text) { return text.substr(text.find('\n')); };
  CHECK(body(slurp(dir / "out" / "double_pendulum" / "double_pendulum.cpp")) ==
        body(slurp(fs::path(MBSC_SOURCE_DIR) / "generated" / "double_pendulum" / "double_pendulum.cpp")));
  // Columns are not shifted by it.
  write(dir / "bad.mbs", "\xEF\xBB\xBFmodel m\nbody b : particle2d { mass zz }\n");
  r = run(kMbsc + " check " + quote((dir / "bad.mbs").string()));
  CHECK(r.output.find("bad.mbs:2:28: error: unknown name 'zz'") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("--freeze takes finite numbers only, and frozen values are checked like defaults", "[cli][robust][flags]") {
  const std::string model = quote(std::string(MBSC_SOURCE_DIR) + "/models/double_pendulum.mbs");
  const fs::path out = fresh_dir("freeze");
  for (const char* bad : {"g=nan", "g=inf", "g=-inf", "g=0x10", "g=", "g=1,5"}) {
    auto r = run(kMbsc + " generate " + model + " -o " + quote(out.string()) + " --freeze " + bad);
    INFO(bad << "\n" << r.output);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("--freeze expects name=value with a finite number") != std::string::npos);
    CHECK(r.output.find("internal error") == std::string::npos);
  }
  // A number a double does not hold (1e-320 is finite, but subnormal): the model
  // language's message for such a literal.
  for (const std::string bad : {"1e400", "1e-400", "1e-320", "-2.5e-315"}) {
    auto r = run(kMbsc + " generate " + model + " -o " + quote(out.string()) + " --freeze g=" + bad);
    INFO(bad << "\n" << r.output);
    CHECK(r.exit_code == 1);
    const std::string literal = bad[0] == '-' ? bad.substr(1) : bad;
    CHECK(r.output.find("mbsc: error: --freeze g: number '" + literal + "' is too " + (bad.find("e-") != std::string::npos ? "small" : "large") +
                        " for a double") != std::string::npos);
    CHECK(r.output.find("not finite") == std::string::npos);
  }
  // The language rejects a negative mass; so does a frozen one, at the mass statement.
  // A frozen zero mass is a massless body, an error here because it leaves M singular.
  auto r = run(kMbsc + " generate " + model + " -o " + quote(out.string()) + " --freeze m1=-1");
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("double_pendulum.mbs:10:29: error: mass of body 'b1' is negative (-1), with --freeze m1=-1") !=
        std::string::npos);
  r = run(kMbsc + " check " + model + " --freeze m2=0");
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("double_pendulum.mbs:11:29: error: body 'b2' is massless (mass 0, with --freeze m2=0) and the "
                      "reduced mass matrix is singular: the motion along w2 moves it (b2.u, b2.v)") != std::string::npos);
  CHECK(fs::is_empty(out));
  fs::remove_all(out);
}

TEST_CASE("a frozen value that makes an expression undefined is an error at it", "[cli][robust][flags]") {
  const fs::path dir = fresh_dir("freeze_zero");
  write(dir / "m.mbs", "model m\nparameter l = 1\ncoordinate th\nspeed w = th'\nforce w : -1/l\n" + kBody);
  auto r = run(kMbsc + " generate " + quote((dir / "m.mbs").string()) + " -o " + quote((dir / "out").string()) +
               " --freeze l=0");
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("m.mbs:5:1: error: the force on 'w' is undefined with --freeze l=0") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}

TEST_CASE("--name must make a usable C++ namespace, and rescues a model name that does not", "[cli][robust][flags]") {
  const fs::path dir = fresh_dir("names");
  write(dir / "int.mbs", "model int\n" + kBody);
  for (const char* bad : {"int", "std", "a__b", "_Abc", "NAN", "RAND_MAX", "EOF", "stdin", "SIGINT", "unix", "1x", "a-b", "../up"}) {
    auto r = run(kMbsc + " generate " + quote((dir / "int.mbs").string()) + " -o " + quote((dir / "out").string()) +
                 " --name '" + bad + "'");
    INFO(bad << "\n" << r.output);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("--name") != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "out"));
    CHECK_FALSE(fs::exists(dir / "up"));
  }
  auto r = run(kMbsc + " generate " + quote((dir / "int.mbs").string()) + " -o " + quote((dir / "out").string()) +
               " --name integer_model");
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(fs::exists(dir / "out" / "integer_model" / "integer_model.hpp"));
  fs::remove_all(dir);
}

TEST_CASE("the symbolic-work budget stops a model that is too big, naming what it was doing", "[cli][robust][budget]") {
  const fs::path out = fresh_dir("budget");
  const std::string chain = quote(std::string(MBSC_SOURCE_DIR) + "/models/parallelogram_chain.mbs");
  // N = 1000 windows takes minutes (N = 150 did before the front end became near-linear,
  // tests/cli/front_end_scale_test.cpp); one second of budget ends it within the grace period.
  auto r = run(kMbsc + " generate " + chain + " --freeze N=1000 --budget 1 --quiet -o " + quote(out.string()));
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("parallelogram_chain.mbs:") != std::string::npos);
  CHECK(r.output.find("error: the symbolic work took more than the time budget of 1 s while ") != std::string::npos);
  CHECK(r.output.find("--budget SECONDS") != std::string::npos);
  CHECK(fs::is_empty(out));
  // --progress shows the stage and the count of elements.
  r = run(kMbsc + " check " + chain + " --freeze N=1000 --budget 2.5 --progress");
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("mbsc: ") != std::string::npos);
  // Which stage the budget catches depends on the machine's speed; any stage will do, as
  // long as it is named and counted ("mbsc:   1.0 s solving ... [####....] 301/302", or
  // on a slow sanitizer machine "mbsc:   1.0 s parsing [####....] 61234/98765 tokens")
  // or names the element it is at ("mbsc:   2.0 s declaring subsystem 'crank_207'").
  CHECK(std::regex_search(r.output, std::regex(R"(mbsc: +[0-9.]+ s [a-z][a-z '-]*( \[[#.]+\] [0-9]+/[0-9]+|'[^']+'))")));
  // On a terminal (script(1) gives the command one) the line is redrawn in place, and
  // cleared before the error is printed.
  r = run("script -qec \"" + kMbsc + " check " + chain + " --freeze N=1000 --budget 2.5\" /dev/null");
  INFO(r.output);
  CHECK(r.output.find("\r\x1b[K" "mbsc: ") != std::string::npos);
  CHECK(r.output.find("\r\x1b[K" + std::string(MBSC_SOURCE_DIR) + "/models/parallelogram_chain.mbs") != std::string::npos);
  // --quiet wins over --progress; nothing on a pipe by default.
  r = run(kMbsc + " check " + chain + " --freeze N=1000 --budget 1.5 --progress --quiet");
  CHECK(r.output.find("mbsc: ") == std::string::npos);
  fs::remove_all(out);
}

TEST_CASE("the memory budget stops the work at once", "[cli][robust][budget]") {
  const fs::path dir = fresh_dir("memory");
  // 1000 free particles: a legitimate model whose derivation needs over 100 MiB today.
  write(dir / "m.mbs", "model free_particles\nparameter m = 1, g = 9.81\ngravity (0, -g)\n"
                       "for i = 1 to 1000 { body b[i] : particle2d { mass m } }\n");
  auto r = run(kMbsc + " generate " + quote((dir / "m.mbs").string()) + " --max-memory 100 --quiet -o " +
               quote((dir / "out").string()));
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("m.mbs:") != std::string::npos);
  CHECK(r.output.find("error: the symbolic work took more than the memory budget of 100 MiB while ") != std::string::npos);
  CHECK(r.output.find("--max-memory MIB") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}

TEST_CASE("large exact constants are refused before GiNaC computes them", "[cli][robust]") {
  const fs::path dir = fresh_dir("exact");
  // A product of 100 000 factors of 1e300 would fold to a 1e8-bit constant.
  std::string product = "1e300";
  for (int i = 1; i < 100000; ++i) product += "*1e300";
  write(dir / "p.mbs", "model m\nparameter a = " + product + "\n" + kBody);
  auto r = run(kMbsc + " check " + quote((dir / "p.mbs").string()));
  INFO(r.output.substr(0, 2000));
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("p.mbs:2:15: error: this product cannot be folded exactly") != std::string::npos);
  // Many different denominators in one sum: their product is the common denominator.
  std::string sum = "1/2";
  for (int i = 3; i < 40000; i += 2) sum += "+1/" + std::to_string(i);
  write(dir / "s.mbs", "model m\nparameter a = " + sum + "\n" + kBody);
  r = run(kMbsc + " check " + quote((dir / "s.mbs").string()));
  INFO(r.output.substr(0, 2000));
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("s.mbs:2:15: error: this sum cannot be folded exactly") != std::string::npos);
  // A frozen exponent reaches the same guard.
  write(dir / "f.mbs", "model m\nparameter a = 3, n = 2\ncoordinate x\nspeed u = x'\nforce u : -a^n*x\n" + kBody);
  r = run(kMbsc + " generate " + quote((dir / "f.mbs").string()) + " --freeze a=3 --freeze n=1e12 -o " +
          quote((dir / "out").string()));
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("f.mbs:5:1: error: the force on 'u' is undefined with --freeze a=3 n=1000000000000 (its exact "
                      "value would need about") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "out"));
  // A coefficient with a huge expansion is solved without expanding it.
  write(dir / "e.mbs", "model wide_speed\nparameter a = 1, b = 1, c = 1, d = 1, e = 1, f = 1, g = 1, h = 1\n"
                       "subsystem s : custom {\n  coordinate th\n  speed w = (a + b + c + d + e + f + g + h + th)^40*th'\n"
                       "  force w : -w'\n}\n");
  r = run(kMbsc + " generate " + quote((dir / "e.mbs").string()) + " --budget 30 -o " + quote((dir / "out").string()));
  INFO(r.output);
  CHECK(r.exit_code == 0);
  fs::remove_all(dir);
}

namespace {
/// A model whose lets a1..an each use the one before twice, sin(a) + cos(a): a shared
/// graph of 2n nodes standing for a tree of 6*2^n - 3, put in a position constraint so
/// that the derivation differentiates it.
std::string let_chain(int n) {
  std::string m = "model let_chain\nparameter m = 1, g = 9.81\ngravity (0, -g)\nbody bob : particle2d { mass m }\n"
                  "let a0 = bob.x + 1\n";
  for (int i = 1; i <= n; ++i)
    m += "let a" + std::to_string(i) + " = sin(a" + std::to_string(i - 1) + ") + cos(a" + std::to_string(i - 1) + ")\n";
  return m + "constraint position { c: bob.y = a" + std::to_string(n) + " }\n";
}
}  // namespace

TEST_CASE("lets: the longest chain under the node limit derives quickly, one more is an error", "[cli][robust][let]") {
  const fs::path dir = fresh_dir("let_chain");
  // a10 stands for 6141 nodes, a11 for 12285 (limits::kMaxLetNodes = 10000).
  write(dir / "ok.mbs", let_chain(10));
  for (const char* command : {" check ", " generate "}) {
    const std::string out = command == std::string(" generate ") ? " -o " + quote((dir / "out").string()) : "";
    // (SCALE_BUDGET: 30 s, ten times that in the sanitizer build.)
    auto r = run("timeout " + std::string(SCALE_BUDGET) + " " + std::string(MBSC_BINARY) + command +
                 quote((dir / "ok.mbs").string()) + out);
    INFO(command << r.output.substr(0, 2000));
    CHECK(r.exit_code == 0);
  }
  CHECK(fs::exists(dir / "out" / "let_chain" / "let_chain.cpp"));
  write(dir / "over.mbs", let_chain(11));
  auto r = run(kMbsc + " check " + quote((dir / "over.mbs").string()));
  INFO(r.output.substr(0, 2000));
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("over.mbs:16:5: error: let 'a11' expands to more than 10000 nodes") != std::string::npos);
  // Forty lines (a tree of 10^13 nodes): refused at a11 at once, the lines after it silent.
  write(dir / "forty.mbs", let_chain(40));
  r = run("timeout 10 " + std::string(MBSC_BINARY) + " check " + quote((dir / "forty.mbs").string()));
  CHECK(r.exit_code == 1);
  CHECK(std::count(r.output.begin(), r.output.end(), '\n') == 1);
  fs::remove_all(dir);
}

TEST_CASE("lets used before their definitions across includes: an error, not a stack overflow", "[cli][robust][let]") {
  // f0 uses a1 from f1, which uses a2 from f2, ...: each file is included after the one that
  // uses it, so converting a0 reaches every let of the chain before its statement.
  const fs::path dir = fresh_dir("let_includes");
  constexpr int kFiles = 300;
  std::string main = "model m\n" + kBody;
  for (int i = 0; i < kFiles; ++i) {
    main += "include \"f" + std::to_string(i) + ".mbs\"\n";
    write(dir / ("f" + std::to_string(i) + ".mbs"),
          i + 1 < kFiles ? "let a" + std::to_string(i) + " = a" + std::to_string(i + 1) + " + 1\n"
                         : "let a" + std::to_string(i) + " = 1\n");
  }
  write(dir / "m.mbs", main + "output o = a0\n");
  auto r = run(kMbsc + " check " + quote((dir / "m.mbs").string()));
  INFO(r.output.substr(0, 2000));
  CHECK(r.exit_code == 1);
  CHECK(r.output.find((dir / "f32.mbs").string() + ":1:5: error: let 'a32' is reached through more than 32 lets used "
                      "before their definitions") != std::string::npos);
  CHECK(std::count(r.output.begin(), r.output.end(), '\n') == 1);  // once, not again from a201
  // Twenty lets, each 190 calls deep: the converter's levels are bounded too (a stack
  // overflow at a few hundred such files before; under ASan at 200 shallow lets).
  const std::string deep = "model d\n" + kBody;
  std::string includes;
  for (int i = 0; i < 20; ++i) {
    const std::string inner = i + 1 < 20 ? "a" + std::to_string(i + 1) : "1";
    std::string e = inner;
    for (int k = 0; k < 190; ++k) e = "sin(" + e + ")";
    write(dir / ("d" + std::to_string(i) + ".mbs"), "let a" + std::to_string(i) + " = " + e + "\n");
    includes += "include \"d" + std::to_string(i) + ".mbs\"\n";
  }
  write(dir / "d.mbs", deep + includes + "output o = a0\n");
  r = run(kMbsc + " check " + quote((dir / "d.mbs").string()));
  INFO(r.output.substr(0, 2000));
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("levels of their expressions)") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("big legitimate inputs stay well inside the limits", "[cli][robust][budget]") {
  const fs::path dir = fresh_dir("big_ok");
  std::string params = "model many_parameters\n";
  for (int i = 0; i < 10000; ++i) params += "parameter p" + std::to_string(i) + " = " + std::to_string(i) + ".5\n";
  write(dir / "p.mbs", params + "body b : particle2d { mass p9999 }\n");
  auto r = run(kMbsc + " check " + quote((dir / "p.mbs").string()) + " --budget 20");
  INFO(r.output.substr(0, 2000));
  CHECK(r.exit_code == 0);
  std::string free = "model free_particles\nparameter m = 1, g = 9.81\ngravity (0, -g)\nfor i = 1 to 300 { body b[i] : particle2d { mass m } }\n";
  write(dir / "f.mbs", free);
  r = run(kMbsc + " check " + quote((dir / "f.mbs").string()) + " --budget 90");
  INFO(r.output.substr(0, 2000));
  CHECK(r.exit_code == 0);
  fs::remove_all(dir);
}

TEST_CASE("every name the namespace check lets through compiles, even where it meets the code's own", "[cli][robust][flags]") {
  const fs::path dir = fresh_dir("name_clash");
  const std::string model = quote(std::string(MBSC_SOURCE_DIR) + "/models/four_bar.mbs");
  // Names of the generated code's helpers, arguments, standard functions and types.
  for (const std::string name : {"sin", "rhs", "lu_solve", "all_finite", "OUT", "size_t", "memcpy", "in_"}) {
    INFO(name);
    auto r = run(kMbsc + " generate " + model + " --name " + name + " -q -o " + quote(dir.string()));
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    write(dir / "main.cpp", "#include \"" + name + "/" + name + ".hpp\"\nint main() {\n  double x[64] = {0}, p[64] = {0}, o[64];\n"
                            "  return mbsc_gen::" + name + "::rhs(0, x, nullptr, p, o) >= 0 ? 0 : 1;\n}\n");
    r = run("g++ -std=gnu++17 -Wall -Wextra -Werror -I" + quote(dir.string()) + " " + quote((dir / "main.cpp").string()) + " " +
            quote((dir / name / (name + ".cpp")).string()) + " -o " + quote((dir / "main").string()));
    INFO(r.output);
    CHECK(r.exit_code == 0);
  }
  fs::remove_all(dir);
}

TEST_CASE("names the standard headers define as macros compile, or are refused", "[cli][robust][flags]") {
  // Parameters, inputs, lets, bodies, coordinates, speeds, constraints and outputs named
  // like macros of <cstdlib>, <cstdio>, <cmath>, <cerrno> and <climits>: the names reach
  // the generated code as strings, or as local variables renamed away from the macros
  // (the dependent speed EXIT_FAILURE is a local in rhs); the model name must not be one.
  const fs::path dir = fresh_dir("macro_names");
  write(dir / "macro_names.mbs",
        "model macro_names\n"
        "parameter RAND_MAX = 1, EOF = 9.81, INT_MAX = 2\n"
        "input SIGINT\n"
        "gravity (0, -EOF)\n"
        "let EXIT_SUCCESS = INT_MAX*RAND_MAX\n"
        "body stdin : particle2d { mass RAND_MAX }\n"
        "coordinate M_PI, BUFSIZ\n"
        "speed errno = M_PI', EXIT_FAILURE = BUFSIZ'\n"
        "constraint position {\n"
        "  assert: stdin.x = EXIT_SUCCESS*cos(M_PI)\n"
        "  NULL: stdin.y = EXIT_SUCCESS*sin(M_PI)\n"
        "  CHAR_BIT: BUFSIZ = stdin.x*stdin.y\n"
        "}\n"
        "independent errno\n"
        "force errno : SIGINT\n"
        "output FILENAME_MAX = stdin.x + M_PI\n");
  auto r = run(kMbsc + " generate " + quote((dir / "macro_names.mbs").string()) + " -q -o " + quote(dir.string()));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const std::string headers = "#include <cstdlib>\n#include <cstdio>\n#include <cmath>\n#include <cerrno>\n#include <climits>\n";
  write(dir / "main.cpp", headers + "#include \"macro_names/macro_names.hpp\"\nint main() {\n"
                          "  double x[64] = {0}, u[8] = {0}, p[64] = {0}, o[64];\n"
                          "  return mbsc_gen::macro_names::rhs(0, x, u, p, o) >= 0 ? 0 : 1;\n}\n");
  write(dir / "impl.cpp", headers + "#include \"macro_names/macro_names.cpp\"\n");
  r = run("g++ -std=gnu++17 -Wall -Wextra -Werror -I" + quote(dir.string()) + " " + quote((dir / "main.cpp").string()) + " " +
          quote((dir / "impl.cpp").string()) + " -o " + quote((dir / "main").string()));
  INFO(r.output);
  CHECK(r.exit_code == 0);
  // The model name itself cannot be renamed: refused by check and generate alike.
  write(dir / "rand.mbs", "model RAND_MAX\n" + kBody);
  for (const std::string command : {std::string(" check "), " generate -o " + quote((dir / "out").string()) + " "}) {
    r = run(kMbsc + command + quote((dir / "rand.mbs").string()));
    INFO(r.output);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("rand.mbs:1:7: error: model name 'RAND_MAX' is a macro") != std::string::npos);
  }
  CHECK_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}

TEST_CASE("an empty model file is named in its error", "[cli][robust][read]") {
  const fs::path dir = fresh_dir("empty");
  write(dir / "empty.mbs", "");
  write(dir / "comment.mbs", "# nothing but a comment\n");
  for (const char* name : {"empty.mbs", "comment.mbs"}) {
    const auto r = run(kMbsc + " check " + quote((dir / name).string()));
    INFO(r.output);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find((dir / name).string() + ":1:1: error: missing 'model NAME' statement") != std::string::npos);
    CHECK(r.output.find("<input>") == std::string::npos);
  }
  fs::remove_all(dir);
}
