// SPDX-License-Identifier: GPL-2.0-or-later
// `mbsc generate --python`: the module is written beside the C++ files (all or nothing,
// in the marker), byte-identical from run to run, and run by Debian's python3 + numpy
// over a shared library built with the README's one line, it reproduces what the C++
// functions compute at a random state (tests/data/abi/reference_driver.cpp, calling the
// C++ names through the header), with the defaults, shape checks and exceptions of
// tests/data/abi/check_python_module.py. Also: a model with inputs stops on a null u
// in a debug build.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "run_command.hpp"

using mbsc_test::quote;
using mbsc_test::run;

namespace fs = std::filesystem;

namespace {

const std::string kSource = MBSC_SOURCE_DIR;
const std::string kMbsc = MBSC_BINARY;
/// Debian's python3 (the one with python3-numpy); MBSC_TEST_PYTHON overrides it (the
/// python_module_skip entry of tests/cli/CMakeLists.txt points it at one without numpy).
std::string python() {
  const char* p = std::getenv("MBSC_TEST_PYTHON");
  return p && *p ? p : "/usr/bin/python3";
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

struct Case {
  std::string model;  // path under the source folder
  std::string name;
};

}  // namespace

TEST_CASE("generate --python: the module matches the C++ functions", "[python]") {
  const std::string interpreter = python();
  const auto numpy = run(interpreter + " -c 'import numpy'");
  if (numpy.exit_code != 0) {
    WARN("Python module check skipped: " << interpreter << " cannot import numpy (Debian: apt-get install python3-numpy, "
         "as scripts/install_deps.sh does): " << numpy.output);
    return;
  }

  const fs::path dir = mbsc_test::fresh_dir("python");
  // Constrained with parameters (no input); constrained with inputs; a custom leaf with
  // an input and no energy.
  for (const Case& c : {Case{"models/double_pendulum.mbs", "double_pendulum"}, Case{"models/slider_crank.mbs", "slider_crank"},
                        Case{"tests/data/abi/dc_motor.mbs", "dc_motor"}}) {
    INFO("model " << c.model);
    const std::string model = kSource + "/" + c.model;
    // Not --quiet: the line it prints on success names the files.
    const auto gen = run(quote(kMbsc) + " generate " + quote(model) + " -o " + quote(dir.string()) + " --python");
    INFO(gen.output);
    REQUIRE(gen.exit_code == 0);
    const fs::path out = dir / c.name;
    REQUIRE(gen.output.find(c.name + ".py") != std::string::npos);
    for (const char* ext : {".hpp", ".cpp", ".py"}) REQUIRE(fs::is_regular_file(out / (c.name + ext)));
    REQUIRE(slurp(out / ".mbsc-generated").find(c.name + ".py") != std::string::npos);
    const std::string module = slurp(out / (c.name + ".py"));
    REQUIRE(module.find("As a special exception") != std::string::npos);

    // Byte-identical from run to run (another folder, another process).
    const fs::path again = dir / "again";
    const auto gen2 = run(quote(kMbsc) + " generate " + quote(model) + " -o " + quote(again.string()) + " --python --quiet");
    REQUIRE(gen2.exit_code == 0);
    REQUIRE(slurp(again / c.name / (c.name + ".py")) == module);

    // The README's compile line, then the C++ reference linked with that library (one
    // compile of the model: what is compared is the binding, not the arithmetic).
    const auto so = run("cd " + quote(out.string()) + " && c++ -O2 -shared -fPIC " + c.name + ".cpp -o lib" + c.name + ".so");
    INFO(so.output);
    REQUIRE(so.exit_code == 0);
    const std::string driver = (out / "reference").string();
    const auto cc = run("c++ -std=c++17 -O1 -Wall -Wextra -Werror -I" + quote(out.string()) + " -DMBSC_MODEL=" + c.name +
                        " '-DMBSC_MODEL_HEADER=\"" + c.name + ".hpp\"' " + quote(kSource + "/tests/data/abi/reference_driver.cpp") +
                        " -L" + quote(out.string()) + " -l" + c.name + " -Wl,-rpath," + quote(out.string()) + " -o " +
                        quote(driver));
    INFO(cc.output);
    REQUIRE(cc.exit_code == 0);
    const auto ref = run(quote(driver) + " 17 > " + quote((out / "reference.txt").string()));
    REQUIRE(ref.exit_code == 0);

    // The module, its library found next to it by default.
    const auto py = run(interpreter + " " + quote(kSource + "/tests/data/abi/check_python_module.py") + " " + quote(out.string()) +
                        " " + c.name + " " + quote((out / "reference.txt").string()));
    INFO(py.output);
    REQUIRE(py.exit_code == 0);
    REQUIRE(py.output.find("checked ") != std::string::npos);
  }
  fs::remove_all(dir);
}

TEST_CASE("generate --python writes nothing when generation fails", "[python]") {
  const fs::path dir = mbsc_test::fresh_dir("python_fail");
  const auto gen = run(quote(kMbsc) + " generate " + quote(kSource + "/tests/data/bad/duplicate_parameter.mbs") + " -o " +
                       quote(dir.string()) + " --python --quiet");
  REQUIRE(gen.exit_code == 1);
  REQUIRE(fs::is_empty(dir));
  fs::remove_all(dir);
}

TEST_CASE("a model with inputs stops on a null u in a debug build", "[python]") {
  const fs::path dir = mbsc_test::fresh_dir("null_u");
  const auto gen = run(quote(kMbsc) + " generate " + quote(kSource + "/tests/data/abi/dc_motor.mbs") + " -o " +
                       quote(dir.string()) + " --quiet");
  REQUIRE(gen.exit_code == 0);
  std::ofstream(dir / "main.cpp") << "#include \"dc_motor/dc_motor.hpp\"\n"
                                     "int main() {\n"
                                     "  const double x[2] = {1.0, 0.5};\n"
                                     "  double xdot[2];\n"
                                     "  return mbsc_gen::dc_motor::rhs(0.0, x, nullptr, mbsc_gen::dc_motor::kParamDefaults, xdot);\n"
                                     "}\n";
  const auto cc = run("cd " + quote(dir.string()) +
                      " && c++ -std=c++17 -Wall -Wextra -Werror main.cpp dc_motor/dc_motor.cpp -o debug_run");
  INFO(cc.output);
  REQUIRE(cc.exit_code == 0);
  const auto r = run(quote((dir / "debug_run").string()));
  INFO(r.output);
  REQUIRE(r.exit_code != 0);  // abort(): killed by SIGABRT
  REQUIRE(r.output.find("u != nullptr") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("generate --derivatives --python: the derivatives as matrices, equal to differences", "[python]") {
  const std::string interpreter = python();
  if (run(interpreter + " -c 'import numpy'").exit_code != 0) {
    WARN("Python derivative check skipped: " << interpreter << " cannot import numpy");
    return;
  }
  const fs::path dir = mbsc_test::fresh_dir("python_derivatives");
  // A loop with inputs (the slider-crank's drive).
  const auto gen = run(quote(kMbsc) + " generate " + quote(kSource + "/models/slider_crank.mbs") + " -o " +
                       quote(dir.string()) + " --python --derivatives --quiet");
  INFO(gen.output);
  REQUIRE(gen.exit_code == 0);
  const fs::path out = dir / "slider_crank";
  const auto so = run("cd " + quote(out.string()) + " && c++ -O2 -shared -fPIC slider_crank.cpp -o libslider_crank.so");
  INFO(so.output);
  REQUIRE(so.exit_code == 0);
  const auto py = run(interpreter + " " + quote(kSource + "/tests/data/abi/check_python_derivatives.py") + " " +
                      quote(out.string()) + " slider_crank");
  INFO(py.output);
  REQUIRE(py.exit_code == 0);
  REQUIRE(py.output.find("checked ") != std::string::npos);
  fs::remove_all(dir);
}
