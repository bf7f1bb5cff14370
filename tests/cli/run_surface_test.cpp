// SPDX-License-Identifier: GPL-2.0-or-later
// The run surface attacked as a hostile local user and a careless one would (issue 24):
// the compile cache loads only objects this run can vouch for, mbsc's children end with
// it, output names never become commands, nothing the user owns is deleted or emptied,
// rows are never silently wrong, and every option's expression and the whole command
// are bounded. Each case is a reproducer that failed before the fix.
#include <catch2/catch.hpp>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>
#include <thread>

#include "run_command.hpp"

namespace fs = std::filesystem;
using namespace mbsc_test;

namespace {

const std::string kMbsc = MBSC_BINARY;


std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// A pendulum on a rod (one constraint pair), an output that stops being finite where
/// the bob rises above the pivot's level minus a quarter rod (sqrt of a negative), energy.
const char* kPendulum =
    "model pend\nparameter l = 1.5, m = 2, g = 9.81\ngravity (0, -g)\n"
    "body b : particle2d { mass m }\nsubsystem arm {\n  coordinate th\n  speed w = th'\n}\n"
    "constraint position { b.x - l*sin(arm.th) = 0; b.y + l*cos(arm.th) = 0 }\n"
    "independent arm.w\ninitial arm.th = 0.5\noutput angle = arm.th\noutput depth = sqrt(-b.y - l/4)\noutput energy\n";

std::string model_in(const fs::path& dir, const std::string& tag = "") {
  write(dir / "pend.mbs", std::string(kPendulum) + (tag.empty() ? "" : "# " + tag + "\n"));
  return quote((dir / "pend.mbs").string());
}

/// A word for the shell, whatever it holds (quote() assumes no single quote).
std::string shell_word(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

/// `mbsc run` of the pendulum with the cache in `cache` (one second unless `args` says).
std::string run_cmd(const fs::path& dir, const fs::path& cache, const std::string& args) {
  return kMbsc + " run " + quote((dir / "pend.mbs").string()) + " --cache-dir " + quote(cache.string()) + " " +
         (args.find("--t-end") == std::string::npos ? "--t-end 1 " : "") + args;
}

/// A shared object whose constructor leaves a file: the code an attacker wants loaded.
fs::path evil_object(const fs::path& dir, const fs::path& marker) {
  write(dir / "evil.cpp", "#include <fstream>\nstruct Evil { Evil() { std::ofstream(\"" + marker.string() +
                              "\") << \"loaded\"; } } evil;\nextern \"C\" int mbsc_run_sizes(int*) { return 0; }\n");
  const auto r = run("c++ -shared -fPIC -o " + quote((dir / "evil.so").string()) + " " + quote((dir / "evil.cpp").string()));
  REQUIRE(r.exit_code == 0);
  return dir / "evil.so";
}

/// The one entry folder of a cache.
fs::path entry_of(const fs::path& cache) {
  for (const auto& e : fs::directory_iterator(cache))
    if (e.is_directory() && e.path().filename().string()[0] != '.') return e.path();
  return {};
}

mode_t mode_of(const fs::path& p) {
  struct stat st {};
  REQUIRE(::lstat(p.c_str(), &st) == 0);
  return st.st_mode & 07777;
}

/// A process that has ended (gone, or a zombie nobody reaped).
bool ended(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (!std::getline(stat, line)) return true;
  const auto close = line.rfind(')');
  return close != std::string::npos && close + 2 < line.size() && line[close + 2] == 'Z';
}

}  // namespace

TEST_CASE("run cache: a folder that is a link, another user's or writable by others is refused", "[surface]") {
  const fs::path dir = fresh_dir("surface_root");
  model_in(dir);
  // No $HOME: the cache is $TMPDIR/mbsc-cache-UID, where another user could have put a link.
  fs::create_directories(dir / "tmp");
  fs::create_directories(dir / "theirs");
  const fs::path root = dir / "tmp" / ("mbsc-cache-" + std::to_string(::getuid()));
  fs::create_directory_symlink(dir / "theirs", root);
  const std::string no_home = "env -u HOME -u XDG_CACHE_HOME -u MBSC_CACHE_DIR TMPDIR=" + quote((dir / "tmp").string()) +
                              " " + kMbsc + " run " + quote((dir / "pend.mbs").string()) + " --t-end 0.1 -o " +
                              quote((dir / "a.csv").string());
  auto r = run(no_home);
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("symbolic link") != std::string::npos);
  CHECK(fs::is_empty(dir / "theirs"));
  CHECK_FALSE(fs::exists(dir / "a.csv"));
  // Writable by others, or another user's (root can make one for the test).
  fs::remove(root);
  fs::create_directory(root);
  ::chmod(root.c_str(), 0777);
  r = run(no_home);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("writable by others") != std::string::npos);
  if (::geteuid() == 0) {
    ::chmod(root.c_str(), 0700);
    REQUIRE(::chown(root.c_str(), 65534, 65534) == 0);
    r = run(no_home);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("another user") != std::string::npos);
  }
  fs::remove_all(dir);
}

TEST_CASE("run cache: only an object this run can vouch for is loaded; a damaged one is rebuilt", "[surface]") {
  const fs::path dir = fresh_dir("surface_entry");
  model_in(dir);
  const fs::path cache = dir / "cache", marker = dir / "PWNED";
  const fs::path evil = evil_object(dir, marker);
  const std::string csv = " -q -o " + quote((dir / "a.csv").string());
  auto r = run(run_cmd(dir, cache, csv));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const fs::path entry = entry_of(cache);
  REQUIRE(fs::exists(entry / "lib.so"));
  REQUIRE(fs::exists(entry / "mbsc-entry"));
  const std::string good = read(entry / "lib.so");

  SECTION("truncated: rebuilt with a warning, no crash (was SIGBUS)") {
    fs::resize_file(entry / "lib.so", 4000);
    r = run(run_cmd(dir, cache, csv));
    INFO(r.output);
    CHECK(r.exit_code == 0);
    CHECK(r.output.find("does not match the record") != std::string::npos);
    CHECK(read(entry / "lib.so") == good);
  }
  SECTION("replaced by another object of the same user and mode: its hash differs, it is not loaded") {
    fs::copy_file(evil, entry / "lib.so", fs::copy_options::overwrite_existing);
    ::chmod((entry / "lib.so").c_str(), 0600);
    r = run(run_cmd(dir, cache, csv));
    INFO(r.output);
    CHECK(r.exit_code == 0);
    CHECK_FALSE(fs::exists(marker));
  }
  SECTION("replaced by a link to another object: not followed") {
    fs::remove(entry / "lib.so");
    fs::create_symlink(evil, entry / "lib.so");
    r = run(run_cmd(dir, cache, csv));
    INFO(r.output);
    CHECK(r.exit_code == 0);
    CHECK_FALSE(fs::exists(marker));
    CHECK_FALSE(fs::is_symlink(entry / "lib.so"));
  }
  SECTION("the entry folder replaced by a link to a copy holding another object: not followed") {
    const fs::path copy = dir / "copy";
    fs::copy(entry, copy);
    fs::copy_file(evil, copy / "lib.so", fs::copy_options::overwrite_existing);
    fs::remove_all(entry);
    fs::create_directory_symlink(copy, entry);
    r = run(run_cmd(dir, cache, csv));
    INFO(r.output);
    CHECK(r.exit_code == 0);
    CHECK_FALSE(fs::exists(marker));
  }
  SECTION("a compiler whose output is a link to another object: refused, nothing loaded") {
    write(dir / "linker.sh", "#!/bin/sh\nif [ \"$1\" = --version ]; then echo linker 1; exit 0; fi\nln -s " +
                                 quote(evil.string()) + " lib.so\n");
    fs::permissions(dir / "linker.sh", fs::perms::owner_all);
    model_in(dir, "another text");
    r = run("MBSC_CXX=" + quote((dir / "linker.sh").string()) + " " + run_cmd(dir, cache, csv));
    INFO(r.output);
    CHECK(r.exit_code == 1);
    CHECK_FALSE(fs::exists(marker));
  }
  fs::remove_all(dir);
}

TEST_CASE("run cache: private whatever the umask, and its own cache is used again", "[surface]") {
  const fs::path dir = fresh_dir("surface_umask");
  model_in(dir);
  const fs::path cache = dir / "deep" / "cache";
  auto r = run("umask 000 && " + run_cmd(dir, cache, "-o " + quote((dir / "a.csv").string())));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(mode_of(cache) == 0700);
  CHECK(mode_of(dir / "deep") == 0700);
  const fs::path entry = entry_of(cache);
  CHECK(mode_of(entry) == 0700);
  CHECK(mode_of(entry / "lib.so") == 0600);
  r = run("umask 000 && " + run_cmd(dir, cache, "-o " + quote((dir / "a.csv").string())));
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("compiled") == std::string::npos);  // from the cache
  fs::remove_all(dir);
}

TEST_CASE("run cache: clean-up removes only what mbsc made, never a user's folders", "[surface]") {
  const fs::path dir = fresh_dir("surface_tidy");
  model_in(dir);
  const fs::path project = dir / "project";
  // A user's folders with names like the temporaries of older versions, and one like a
  // work folder of ours but without its marker; each holds a file of the user's.
  for (const char* name : {".thesis.tmp4000000", ".backup.tmp123", ".mbsc-work-4000000-000000000000"}) {
    fs::create_directories(project / name);
    write(project / name / "notes.txt", "mine");
  }
  // A work folder a killed run of ours left (its process, 4000001, is gone).
  const fs::path stale = project / ".mbsc-work-4000001-aaaaaaaaaaaa";
  fs::create_directories(stale / "model_0123456789abcdef");
  write(stale / ".mbsc-work", "mbsc compile work folder of process 4000001\n");
  write(stale / "model_0123456789abcdef" / "shim.cpp", "// shim\n");
  ::chmod(project.c_str(), 0755);
  auto r = run(run_cmd(dir, project, "-o " + quote((dir / "a.csv").string())));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  for (const char* name : {".thesis.tmp4000000", ".backup.tmp123", ".mbsc-work-4000000-000000000000"})
    CHECK(read(project / name / "notes.txt") == "mine");
  CHECK_FALSE(fs::exists(stale));
  // The cache is pruned by age: an entry unused for longer than MBSC_CACHE_MAX_DAYS goes.
  const fs::path entry = entry_of(project);
  REQUIRE(fs::exists(entry));
  model_in(dir, "a second model text");
  r = run("touch -d '40 days ago' " + quote((entry / "mbsc-entry").string()) + " && " +
          run_cmd(dir, project, "-q -o " + quote((dir / "a.csv").string())));
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK_FALSE(fs::exists(entry));
  CHECK(read(project / ".backup.tmp123" / "notes.txt") == "mine");
  fs::remove_all(dir);
}

TEST_CASE("run: the compiler and all it started end with mbsc, and run under the memory budget", "[surface]") {
  const fs::path dir = fresh_dir("surface_kill");
  model_in(dir);
  // A "compiler" that starts a child of its own (as g++ starts cc1plus) and waits.
  write(dir / "slow.sh", "#!/bin/sh\nif [ \"$1\" = --version ]; then echo slow 1; exit 0; fi\nsleep 300 &\necho $! > " +
                             quote((dir / "child.pid").string()) + "\nwait\n");
  fs::permissions(dir / "slow.sh", fs::perms::owner_all);
  for (int signal : {SIGKILL, SIGTERM}) {
    fs::remove(dir / "child.pid");
    const std::string cmd = "MBSC_CXX=" + quote((dir / "slow.sh").string()) + " exec " +
                            run_cmd(dir, dir / "cache", "-o " + quote((dir / "a.csv").string()));
    const pid_t mbsc = ::fork();
    REQUIRE(mbsc >= 0);
    if (mbsc == 0) {
      ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
    pid_t child = 0;
    for (int i = 0; i < 300 && child == 0; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      std::ifstream(dir / "child.pid") >> child;
    }
    REQUIRE(child > 0);
    CHECK_FALSE(ended(child));
    ::kill(mbsc, signal);
    int status = 0;
    ::waitpid(mbsc, &status, 0);
    bool gone = false;
    for (int i = 0; i < 100 && !gone; ++i) {
      gone = ended(child);
      if (!gone) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    INFO("signal " << signal);
    CHECK(gone);
    if (!gone) ::kill(child, SIGKILL);
  }
  // The compiler runs under --max-memory: its data segment is limited (RLIMIT_DATA).
  write(dir / "limits.sh", "#!/bin/sh\nif [ \"$1\" = --version ]; then echo limits 1; exit 0; fi\necho data limit "
                           "$(ulimit -d)\nexit 1\n");
  fs::permissions(dir / "limits.sh", fs::perms::owner_all);
  const auto r = run("MBSC_CXX=" + quote((dir / "limits.sh").string()) + " " +
                     run_cmd(dir, dir / "cache", "--max-memory 300 -o " + quote((dir / "a.csv").string())));
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("data limit 307200") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("run: output names never become commands, plots go through no predictable file", "[surface]") {
  const fs::path dir = fresh_dir("surface_names");
  model_in(dir);
  const fs::path cache = dir / "cache";
  // A newline and system("...") in -o: gnuplot would have run it.
  const std::string evil_name = (dir / "x\nsystem(\"touch PWNED\")\n.csv").string();
  auto r = run("cd " + quote(dir.string()) + " && " +
               run_cmd(dir, cache, "-o " + shell_word(evil_name) + " --plot " + quote((dir / "p.svg").string())));
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("control character") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "PWNED"));
  CHECK_FALSE(fs::exists(evil_name));
  // Quotes, spaces and a leading '<' or '|' in names are only names.
  for (const std::string name : {"it's data.csv", "<x.csv", "|x.csv"}) {
    r = run("cd " + quote(dir.string()) + " && " +
            run_cmd(dir, cache, "-q -o " + shell_word(name) + " --plot " + shell_word(name + ".svg")));
    INFO(name << "\n" << r.output);
    CHECK(r.exit_code == 0);
    CHECK(read(dir / (name + ".svg")).find("<svg") != std::string::npos);
  }
  // The old temporary name (<plot>.tmp<PID>) planted as links to a victim for the next
  // process ids: the victim stays as it was.
  write(dir / "victim", "precious\n");
  long last = 0;
  std::ifstream("/proc/sys/kernel/ns_last_pid") >> last;
  if (last > 0)
    for (long pid = last + 1; pid < last + 400; ++pid)
      fs::create_symlink(dir / "victim", dir / ("q.svg.tmp" + std::to_string(pid)));
  r = run(run_cmd(dir, cache, "-q -o " + quote((dir / "q.csv").string()) + " --plot " + quote((dir / "q.svg").string())));
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(read(dir / "victim") == "precious\n");
  CHECK(read(dir / "q.svg").find("<svg") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("run: the destination is replaced whole or not at all; a FIFO and a huge CSV are refused", "[surface]") {
  const fs::path dir = fresh_dir("surface_outputs");
  model_in(dir);
  const fs::path cache = dir / "cache";
  write(dir / "results.csv", "the user's earlier results\n");
  // A run that fails (non-finite input at t = 0.5): exit 2, results.csv as it was, the
  // rows up to the failure in the temporary the message names.
  auto r = run(run_cmd(dir, cache, "-o " + quote((dir / "results.csv").string()) + " --set g='1/0'"));
  CHECK(r.exit_code == 1);  // a constant that is not finite is refused before anything runs
  write(dir / "push.mbs", "model push\nparameter m = 1\ninput f\nbody b : particle2d { mass m }\nforce b.u : f\n");
  r = run(kMbsc + " run " + quote((dir / "push.mbs").string()) + " --cache-dir " + quote(cache.string()) +
          " --t-end 1 --dt-out 0.01 --input 'f=1/(t-0.5)^2' -o " + quote((dir / "results.csv").string()));
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(read(dir / "results.csv") == "the user's earlier results\n");
  const auto at = r.output.find("are in ");
  REQUIRE(at != std::string::npos);
  const std::string kept = r.output.substr(at + 7, r.output.find('\n', at) - at - 7);
  const std::string partial = read(kept);
  CHECK(partial.rfind("t,", 0) == 0);
  CHECK(std::count(partial.begin(), partial.end(), '\n') > 40);
  // A named pipe nobody reads: refused at once, not a run that blocks forever.
  REQUIRE(::mkfifo((dir / "fifo").c_str(), 0600) == 0);
  r = run("timeout 60 " + run_cmd(dir, cache, "-o " + quote((dir / "fifo").string())));
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("named pipe") != std::string::npos);
  // About 10^7 rows: refused with the estimate unless --large-output.
  r = run(run_cmd(dir, cache, "--dt-out 1e-7 -o " + quote((dir / "big.csv").string())));
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("--large-output") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "big.csv"));
  fs::remove_all(dir);
}

TEST_CASE("run: every column carries its own value; accuracy far off the tolerances is reported", "[surface]") {
  const fs::path dir = fresh_dir("surface_rows");
  model_in(dir);
  const fs::path cache = dir / "cache";
  // Started at 2.5 rad the bob passes above y = -l/4, where `depth` is sqrt of a negative.
  auto r = run(run_cmd(dir, cache, "--init arm.th=2.5 --t-end 2 -o " + quote((dir / "a.csv").string())));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("warning: column 'depth' is not finite from t = ") != std::string::npos);
  std::ifstream in(dir / "a.csv");
  std::string header, line;
  std::getline(in, header);
  std::vector<std::string> names;
  {
    std::stringstream h(header);
    for (std::string c; std::getline(h, c, ',');) names.push_back(c);
  }
  const auto col = [&](const std::string& n) { return std::find(names.begin(), names.end(), n) - names.begin(); };
  long nan_rows = 0, rows = 0;
  double previous_angle = NAN;
  bool angle_moves = false;
  while (std::getline(in, line)) {
    std::vector<double> v;
    std::stringstream s(line);
    for (std::string c; std::getline(s, c, ',');) v.push_back(std::stod(c));
    const double depth = v[static_cast<std::size_t>(col("depth"))], angle = v[static_cast<std::size_t>(col("angle"))];
    const double y = v[static_cast<std::size_t>(col("b.y"))];
    // depth is NaN exactly where -y - l/4 < 0, and otherwise its own value.
    if (-y - 1.5 / 4 < -1e-9) {
      CHECK(std::isnan(depth));
      ++nan_rows;
    } else if (-y - 1.5 / 4 > 1e-9) {
      CHECK(depth == Approx(std::sqrt(-y - 1.5 / 4)));
    }
    CHECK(angle == v[static_cast<std::size_t>(col("arm.th"))]);  // never the previous row's
    if (!std::isnan(previous_angle) && angle != previous_angle) angle_moves = true;
    previous_angle = angle;
    ++rows;
  }
  CHECK(nan_rows > 0);
  CHECK(nan_rows < rows);
  CHECK(angle_moves);
  // --strict turns the warning into exit 2 (the CSV is still complete).
  r = run(run_cmd(dir, cache, "--init arm.th=2.5 --t-end 2 --strict -o " + quote((dir / "b.csv").string())));
  CHECK(r.exit_code == 2);
  CHECK(fs::exists(dir / "b.csv"));
  // An angle of 1e20 rad has no digits left below 10^4 rad: the motion cannot follow
  // the mechanism, and the summary says so (1e300 is past the values a model may hold,
  // 1e30, and refused at the option).
  r = run(run_cmd(dir, cache, "--init arm.th=1e20 -o " + quote((dir / "c.csv").string())));
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("warning: the constraint residuals") != std::string::npos);
  r = run(run_cmd(dir, cache, "--init arm.th=1e300 -o " + quote((dir / "c.csv").string())));
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("larger in magnitude than 1e+30") != std::string::npos);
  // A fixed step far too large: the energy of this conservative model is not kept.
  r = run(run_cmd(dir, cache, "--integrator rk4 --h 0.5 --t-end 20 --strict -o " + quote((dir / "d.csv").string())));
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK((r.output.find("warning: the energy changed") != std::string::npos ||
         r.output.find("the run failed") != std::string::npos));
  // The documented range of --rtol.
  r = run(run_cmd(dir, cache, "--rtol 0.5 -o " + quote((dir / "e.csv").string())));
  CHECK(r.exit_code != 0);
  CHECK_FALSE(fs::exists(dir / "e.csv"));
  fs::remove_all(dir);
}

TEST_CASE("run: the budget bounds the whole command and every option's expression", "[surface]") {
  const fs::path dir = fresh_dir("surface_budget");
  model_in(dir);
  const fs::path cache = dir / "cache";
  const std::string csv = " -o " + quote((dir / "a.csv").string());
  // The integration itself: a very fast start would take minutes.
  auto start = std::chrono::steady_clock::now();
  auto r = run("timeout 120 " + run_cmd(dir, cache, "--init arm.w=1e7 --t-end 10 --budget 4" + csv));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  INFO(r.output);
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("time budget") != std::string::npos);
  CHECK(seconds < 60);
  CHECK_FALSE(fs::exists(dir / "a.csv"));
  // Expressions: exact constants too large to fold, unknown functions, deep nesting.
  const std::string deep = std::string(10000, '(') + "1" + std::string(10000, ')');
  struct Case {
    std::string args, expect;
  } cases[] = {
      {"--set m='2^(2^40)'", "cannot be folded exactly"},
      {"--init arm.th='10^(10^12)'", "cannot be folded exactly"},
      {"--set m='factorial(100000000)'", "unknown function 'factorial'"},
      {"--set m=" + quote(deep), "nesting too deep"},
      {"--init arm.th=" + quote(deep), "nesting too deep"},
      {"--set m='1e-320'", "too small for a double"},
  };
  for (const auto& c : cases) {
    start = std::chrono::steady_clock::now();
    r = run("timeout 60 " + run_cmd(dir, cache, c.args + csv));
    INFO(c.args.substr(0, 60) << "\n" << r.output.substr(0, 2000));
    CHECK(r.exit_code == 1);
    CHECK(r.output.find(c.expect) != std::string::npos);
    CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < 30);
  }
  // --input goes through the same reader (and a model with an input).
  write(dir / "push.mbs", "model push\nparameter m = 1\ninput f\nbody b : particle2d { mass m }\nforce b.u : f\n");
  for (const std::string& input : {std::string("f='t^(2^(2^40))'"), "f=" + quote(deep), std::string("f='gamma(t)'")}) {
    r = run("timeout 60 " + kMbsc + " run " + quote((dir / "push.mbs").string()) + " --cache-dir " + quote(cache.string()) +
            " --input " + input + csv);
    INFO(r.output.substr(0, 2000));
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("--input f") != std::string::npos);
  }
  fs::remove_all(dir);
}
