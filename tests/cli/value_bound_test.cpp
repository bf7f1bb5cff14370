// SPDX-License-Identifier: GPL-2.0-or-later
// `check` and `generate` agree on the values a model gives (docs/language.md, "Limits"):
// a value that is not a finite real number, or beyond the bound, is an error at the
// element from both commands, with exit code 1 and nothing written, whether it is
// written in the model, made by the parameters' defaults or by --freeze. (The models that
// fit a plain file are in tests/data/bad/value_*.mbs, run by bad_input_test.cpp with
// both commands.)
#include <catch2/catch.hpp>

#include <fstream>

#include "run_command.hpp"

namespace fs = std::filesystem;
using namespace mbsc_test;

namespace {

const std::string kMbsc = std::string("timeout 120 ") + MBSC_BINARY;


/// `check` and `generate` of `model` with `flags` both fail with exit code 1 and `expect`
/// in their output, no internal error, and nothing written.
void both_refuse(const fs::path& model, const std::string& flags, const std::string& expect) {
  const fs::path out = fresh_dir("values_out");
  for (const std::string command : {std::string(" check "), " generate -o " + quote(out.string()) + " "}) {
    const auto r = run(kMbsc + command + quote(model.string()) + flags);
    INFO(command << flags << "\n" << r.output);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find(expect) != std::string::npos);
    CHECK(r.output.find("internal error") == std::string::npos);
  }
  CHECK(fs::is_empty(out));
  fs::remove_all(out);
}

}  // namespace

TEST_CASE("frozen values are values: real, finite and within the bound, from check and generate", "[cli][values]") {
  const fs::path dir = fresh_dir("values");
  const fs::path m = dir / "m.mbs";
  write(m,
        "model m\n"
        "parameter a = 1, k = 1, mb = 1\n"
        "gravity (0, -9.81)\n"
        "body b : particle2d { mass mb }\n"
        "force b.u : -sqrt(a)*b.x\n"
        "force b.v : -k*k*b.y\n");
  // sqrt(-1) folds to GiNaC's I, which the code generator cannot lower.
  both_refuse(m, " --freeze a=-1", "m.mbs:5:1: error: the force on 'b.u' with --freeze a=-1: the complex number");
  // Each value within the bound, their product in the code not: 1e40.
  both_refuse(m, " --freeze k=1e20", "m.mbs:6:1: error: the force on 'b.v' with --freeze k=1e+20: -1e+40 is larger in "
                                      "magnitude than 1e+30");
  // The value itself beyond the bound (a double holds it; the forcing m g would not).
  both_refuse(m, " --freeze mb=2e307", "m.mbs: error: --freeze mb=2e+307: 2e+307 is larger in magnitude than 1e+30");
  // Not frozen, the same values are the defaults: the mass is checked there.
  write(dir / "d.mbs", "model d\nparameter mb = -4\ngravity (0, -9.81)\nbody b : particle2d { mass sqrt(mb) }\n");
  both_refuse(dir / "d.mbs", "", "d.mbs:4:28: error: mass of body 'b' at the parameter values: the complex number");
  // Within the bound all is well.
  const auto r = run(kMbsc + " check " + quote(m.string()) + " --freeze k=1e15 --freeze mb=1e30");
  INFO(r.output);
  CHECK(r.exit_code == 0);
  fs::remove_all(dir);
}

TEST_CASE("what the code generator still refuses, check refuses too, at the model", "[cli][values]") {
  // The lowering's own refusals (here: the conjugate in GiNaC's derivative of abs) are the
  // model's errors at its name, exit 1, from both commands; never an internal error.
  const fs::path dir = fresh_dir("lowering");
  write(dir / "a.mbs", "model a\ngravity (0, -9.81)\nbody b : particle2d { mass 1 }\n"
                       "constraint position {\n  c: abs(b.x) + b.y = 1\n}\n");
  both_refuse(dir / "a.mbs", "", "a.mbs:1:7: error: cannot generate function");
  fs::remove_all(dir);
}
