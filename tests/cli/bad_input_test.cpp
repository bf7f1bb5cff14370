// SPDX-License-Identifier: GPL-2.0-or-later
// Every model in tests/data/bad must fail with `file:line:col: error: ...` naming the
// element (the `# expect: LINE:COL: TEXT` line of the file), exit code 1, and leave
// the output folder empty. `# expect-errors: N` also checks that exactly N errors are
// reported (no second, misleading error after the first). `check` must refuse each the
// same way: what generate refuses, check refuses, at the same place.
#include <catch2/catch.hpp>
#include <fstream>

#include "run_command.hpp"

namespace fs = std::filesystem;
using namespace mbsc_test;

namespace {

struct Expectation {
  std::string file;      // file the error points into, relative to the model's folder ("" = the model itself)
  std::string position;  // "LINE:COL"
  std::string text;
  int errors = -1;       // the number of errors, or -1 when not checked
};

Expectation read_expectation(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  Expectation ex;
  while (std::getline(in, line)) {
    const std::string file_tag = "# expect-file: ", tag = "# expect: ", count_tag = "# expect-errors: ";
    if (line.rfind(file_tag, 0) == 0) ex.file = line.substr(file_tag.size());
    if (line.rfind(count_tag, 0) == 0) ex.errors = std::stoi(line.substr(count_tag.size()));
    if (line.rfind(tag, 0) != 0) continue;
    std::string rest = line.substr(tag.size());
    auto colon = rest.find(':', rest.find(':') + 1);
    ex.position = rest.substr(0, colon);
    ex.text = rest.substr(colon + 2);
  }
  return ex;
}

}  // namespace

TEST_CASE("bad input: clear error with position, exit 1, nothing written", "[cli][bad]") {
  const fs::path dir = fs::path(MBSC_SOURCE_DIR) / "tests" / "data" / "bad";
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".mbs") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  REQUIRE(files.size() >= 25);
  for (const auto& f : files) {
    Expectation ex = read_expectation(f);
    INFO("model " << f.filename().string());
    REQUIRE(!ex.position.empty());
    const fs::path out = fresh_dir("bad");
    const std::string where = ex.file.empty() ? f.string() : (f.parent_path() / ex.file).string();
    for (const std::string command : {" generate -o " + quote(out.string()) + " ", std::string(" check ")}) {
      CommandResult r = run(std::string(MBSC_BINARY) + command + quote(f.string()));
      INFO(command << "output:\n" << r.output);
      CHECK(r.exit_code == 1);
      CHECK(r.output.find(where + ":" + ex.position + ": error: ") != std::string::npos);
      CHECK(r.output.find(ex.text) != std::string::npos);
      if (ex.errors >= 0) {
        int errors = 0;
        for (auto at = r.output.find(": error: "); at != std::string::npos; at = r.output.find(": error: ", at + 1)) ++errors;
        CHECK(errors == ex.errors);
      }
      CHECK(fs::is_empty(out));
    }
    fs::remove_all(out);
  }
}

TEST_CASE("bad command-line values are errors too", "[cli][bad]") {
  const std::string model = std::string(MBSC_SOURCE_DIR) + "/models/double_pendulum.mbs";
  const fs::path out = fresh_dir("badflag");
  auto r = run(std::string(MBSC_BINARY) + " generate " + quote(model) + " -o " + quote(out.string()) + " --freeze nosuch=1");
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("no parameter 'nosuch'") != std::string::npos);
  r = run(std::string(MBSC_BINARY) + " generate " + quote(model) + " -o " + quote(out.string()) + " --freeze g");
  CHECK(r.exit_code == 1);
  r = run(std::string(MBSC_BINARY) + " generate " + quote(model) + " -o " + quote(out.string()) + " --outputs nosuch");
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("unknown function 'nosuch'") != std::string::npos);
  r = run(std::string(MBSC_BINARY) + " generate /no/such/model.mbs -o " + quote(out.string()));
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("error") != std::string::npos);
  CHECK(fs::is_empty(out));
  fs::remove_all(out);
}
