// SPDX-License-Identifier: GPL-2.0-or-later
// Command-line values a user mistypes (--freeze, --outputs, --what), generate --quiet, and
// the warning for a model whose Python module would take a standard module's name.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "run_command.hpp"

namespace fs = std::filesystem;
using namespace mbsc_test;

namespace {

const std::string kMbsc = MBSC_BINARY;
const std::string kPendulum = quote(std::string(MBSC_SOURCE_DIR) + "/models/double_pendulum.mbs");

/// A one-body model named `name` (and a let, for --freeze L=...), written into `dir`.
std::string write_model(const fs::path& dir, const std::string& name) {
  const fs::path file = dir / (name + ".mbs");
  std::ofstream(file) << "model " << name
                      << "\nparameter m = 1, g = 9.81\nlet L = 2*m\ngravity (0, -g)\nbody b : particle2d { mass m }\n"
                         "output o = L*b.y\n";
  return quote(file.string());
}

}  // namespace

TEST_CASE("mistyped option values: did you mean, in the mbsc: error form", "[cli][bad]") {
  const fs::path out = fresh_dir("optvalues");
  const std::string to = " -o " + quote(out.string());
  auto r = run(kMbsc + " generate " + kPendulum + to + " --freeze gg=1");
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("error: --freeze: model 'double_pendulum' has no parameter 'gg' (did you mean 'g'?)") !=
        std::string::npos);
  // A name the model has, but not as a parameter, says what it is.
  const std::string mine = write_model(out, "lets");
  r = run(kMbsc + " check " + mine + " --freeze L=3");
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("has no parameter 'L' ('L' is a let)") != std::string::npos);

  r = run(kMbsc + " generate " + kPendulum + to + " --outputs rhs,enrgy");
  CHECK(r.exit_code == 1);
  CHECK(r.output.rfind("mbsc: error: --outputs: unknown function 'enrgy' (did you mean 'energy'?) (known: rhs,", 0) == 0);
  CHECK(r.output.find("<input>") == std::string::npos);
  r = run(kMbsc + " print " + kPendulum + " --stats --outputs mass_matrx");
  CHECK(r.exit_code == 1);
  CHECK(r.output.rfind("mbsc: error: --outputs: unknown function 'mass_matrx' (did you mean 'mass_matrix'?)", 0) == 0);

  r = run(kMbsc + " print " + kPendulum + " --what M,inavriants");
  CHECK(r.exit_code == 1);
  CHECK(r.output.rfind("mbsc: error: --what: unknown item 'inavriants' (did you mean 'invariants'?) (known: eom M h", 0) ==
        0);
  r = run(kMbsc + " print " + kPendulum + " --what zzz");
  CHECK(r.exit_code == 1);
  CHECK(r.output.rfind("mbsc: error: --what: unknown item 'zzz' (known: eom M h invariants rates A B C S f fbar)", 0) == 0);
  CHECK(!fs::exists(out / "double_pendulum"));
  fs::remove_all(out);
}

TEST_CASE("generate --quiet prints nothing on success, and still its warnings and errors", "[cli]") {
  const fs::path out = fresh_dir("quiet");
  const std::string to = " -o " + quote(out.string());
  auto r = run(kMbsc + " generate " + kPendulum + to + " --quiet");
  CHECK(r.exit_code == 0);
  CHECK(r.output.empty());
  CHECK(fs::exists(out / "double_pendulum" / "double_pendulum.cpp"));
  // Without --quiet: the summary line.
  r = run(kMbsc + " generate " + kPendulum + to);
  CHECK(r.exit_code == 0);
  CHECK(r.output.rfind("wrote ", 0) == 0);
  // An error is still printed.
  r = run(kMbsc + " generate " + kPendulum + to + " --quiet --freeze nosuch=1");
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("error: --freeze") != std::string::npos);
  fs::remove_all(out);
}

TEST_CASE("generate --python warns when the module name is a Python standard module", "[cli]") {
  const fs::path out = fresh_dir("pyname");
  const std::string to = " -o " + quote(out.string());
  for (const std::string name : {"gc", "math", "random", "signal", "array", "numpy"}) {
    INFO(name);
    const std::string file = write_model(out, name);
    auto r = run(kMbsc + " generate " + file + to + " --python --quiet");
    INFO(r.output);
    CHECK(r.exit_code == 0);  // a warning: the files are written
    CHECK(r.output.find(name + ".mbs:1:7: warning: '" + name + "' is also the name of ") != std::string::npos);
    CHECK(r.output.find("--name " + name + "_model") != std::string::npos);
    CHECK(fs::exists(out / name / (name + ".py")));
    // The way out the warning gives works, silently.
    r = run(kMbsc + " generate " + file + to + " --python --quiet --name " + name + "_model");
    CHECK(r.exit_code == 0);
    CHECK(r.output.empty());
    // Without --python no module is written: nothing to warn about.
    r = run(kMbsc + " generate " + file + to + " --quiet");
    CHECK(r.output.empty());
  }
  // --name can bring the collision too; the warning then names the file only.
  auto r = run(kMbsc + " generate " + kPendulum + to + " --python --quiet --name os");
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("double_pendulum.mbs: warning: 'os' is also the name of a module of Python's standard library") !=
        std::string::npos);
  fs::remove_all(out);
}

TEST_CASE("a number a double does not hold gets the model language's message on every flag", "[cli][bad]") {
  // 1e-320 is finite but subnormal: "too small for a double", as a literal in a model, not
  // "not finite" or "not a positive number". Each is refused before any work.
  struct Case {
    std::string args, expect;
  } cases[] = {
      {"check " + kPendulum + " --freeze m1=1e-320", "--freeze m1: number '1e-320' is too small for a double"},
      {"run " + kPendulum + " --t-end 1e-320", "number '1e-320' is too small for a double"},
      {"run " + kPendulum + " --dt-out 1e400", "number '1e400' is too large for a double"},
      {"inverse " + kPendulum + " --prescribe th1=t --t-start -1e-320", "number '1e-320' is too small for a double"},
      {"bench " + kPendulum + " --tolerances 1e-6,1e-320", "--tolerances: number '1e-320' is too small for a double"},
  };
  for (const auto& k : cases) {
    const auto r = run(kMbsc + " " + k.args);
    INFO(k.args << "\n" << r.output);
    CHECK(r.exit_code != 0);
    CHECK(r.output.find(k.expect) != std::string::npos);
    CHECK(r.output.find("not finite") == std::string::npos);
  }
}

TEST_CASE("generate --batch: the functions batched, none, and names refused", "[cli]") {
  const fs::path out = fresh_dir("batch");
  const std::string to = " -o " + quote(out.string());
  const fs::path source = out / "double_pendulum" / "double_pendulum.cpp";
  auto text = [&] {
    std::ifstream in(source);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  };
  // Default: rhs alone.
  auto r = run(kMbsc + " generate " + kPendulum + to + " --quiet");
  REQUIRE(r.exit_code == 0);
  CHECK(text().find("int rhs_batch(int n, const BatchArrays& a, int* status)") != std::string::npos);
  CHECK(text().find("energy_batch") == std::string::npos);
  // --outputs chooses the functions: no batch unless asked for.
  r = run(kMbsc + " generate " + kPendulum + to + " --quiet --outputs rhs,energy");
  REQUIRE(r.exit_code == 0);
  CHECK(text().find("BatchArrays") == std::string::npos);
  r = run(kMbsc + " generate " + kPendulum + to + " --quiet --outputs rhs,energy --batch rhs");
  REQUIRE(r.exit_code == 0);
  CHECK(text().find("int rhs_batch(") != std::string::npos);
  // Named ones, repeated names once.
  r = run(kMbsc + " generate " + kPendulum + to + " --quiet --batch energy,outputs,energy");
  REQUIRE(r.exit_code == 0);
  CHECK(text().find("rhs_batch") == std::string::npos);
  CHECK(text().find("MBSC_HOST_DEVICE int energy_at(int i, const BatchArrays& a)") != std::string::npos);
  CHECK(text().find("int outputs_batch(") != std::string::npos);
  CHECK(text().find("extern \"C\" int mbsc_double_pendulum_energy_batch(") != std::string::npos);
  // none: no batch code at all.
  r = run(kMbsc + " generate " + kPendulum + to + " --quiet --batch none");
  REQUIRE(r.exit_code == 0);
  CHECK(text().find("BatchArrays") == std::string::npos);
  // A function not emitted, a misspelt one, none with others: refused, nothing written.
  const std::string before = text();
  r = run(kMbsc + " generate " + kPendulum + to + " --outputs rhs --batch energy");
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("mbsc: error: --batch: 'energy' is not a function this generate emits (emitted: rhs;") !=
        std::string::npos);
  r = run(kMbsc + " generate " + kPendulum + to + " --batch enrgy");
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("--batch: 'enrgy' is not a function this generate emits (did you mean 'energy'?)") != std::string::npos);
  r = run(kMbsc + " generate " + kPendulum + to + " --batch none,rhs");
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("--batch: 'none' stands alone") != std::string::npos);
  CHECK(text() == before);
  fs::remove_all(out);
}
