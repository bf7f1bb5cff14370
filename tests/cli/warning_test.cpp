// SPDX-License-Identifier: GPL-2.0-or-later
// Every model in tests/data/warn compiles (exit 0, the code is written) with the warning
// its `# warn: LINE:COL: TEXT` line names, printed once, at that position; and a
// model that needs no warning (the shipped ones) prints none.
#include <catch2/catch.hpp>
#include <fstream>

#include "run_command.hpp"

namespace fs = std::filesystem;
using namespace mbsc_test;

namespace {

struct Expected {
  std::string position, text;
};

Expected read_warning(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  Expected w;
  const std::string tag = "# warn: ";
  while (std::getline(in, line)) {
    if (line.rfind(tag, 0) != 0) continue;
    const std::string rest = line.substr(tag.size());
    const auto colon = rest.find(':', rest.find(':') + 1);
    w.position = rest.substr(0, colon);
    w.text = rest.substr(colon + 2);
  }
  return w;
}

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace

TEST_CASE("warnings: at the element, once, and the model still compiles", "[cli][warn]") {
  const fs::path dir = fs::path(MBSC_SOURCE_DIR) / "tests" / "data" / "warn";
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".mbs") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  REQUIRE(files.size() >= 2);
  for (const auto& f : files) {
    const Expected w = read_warning(f);
    INFO("model " << f.filename().string());
    REQUIRE(!w.position.empty());
    const fs::path out = fresh_dir("warn");
    CommandResult r = run(std::string(MBSC_BINARY) + " generate " + quote(f.string()) + " -o " + quote(out.string()));
    INFO("output:\n" << r.output);
    CHECK(r.exit_code == 0);
    const std::string head = f.string() + ":" + w.position + ": warning: ";
    CHECK(count(r.output, head + w.text) == 1);
    CHECK(count(r.output, ": warning: ") == 1);
    CHECK_FALSE(fs::is_empty(out));
    fs::remove_all(out);
  }
}

TEST_CASE("warnings: the shipped models are not singular at their reference configuration", "[cli][warn]") {
  for (const auto& e : fs::directory_iterator(fs::path(MBSC_SOURCE_DIR) / "models")) {
    if (e.path().extension() != ".mbs") continue;
    INFO("model " << e.path().filename().string());
    CommandResult r = run(std::string(MBSC_BINARY) + " check " + quote(e.path().string()));
    INFO("output:\n" << r.output);
    CHECK(r.exit_code == 0);
    CHECK(r.output.find("singular at the reference configuration") == std::string::npos);
  }
}
