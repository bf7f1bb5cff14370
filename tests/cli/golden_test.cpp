// SPDX-License-Identifier: GPL-2.0-or-later
// Golden outputs: `mbsc generate` on every shipped model, in a fresh process, must
// reproduce generated/<model>/ byte for byte. (Regenerate deliberately with
// `cmake --build build --target regenerate` and review the diff.)
#include <catch2/catch.hpp>
#include <fstream>
#include <sstream>

#include "run_command.hpp"

namespace fs = std::filesystem;
using namespace mbsc_test;

namespace {
std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
}  // namespace

TEST_CASE("generated/ equals what the CLI produces now", "[golden]") {
  const fs::path root(MBSC_SOURCE_DIR);
  std::vector<fs::path> models;
  for (const auto& e : fs::directory_iterator(root / "models"))
    if (e.path().extension() == ".mbs") models.push_back(e.path());
  std::sort(models.begin(), models.end());
  REQUIRE(models.size() >= 7);
  for (const auto& model : models) {
    const std::string name = model.stem().string();
    INFO("model " << name);
    const fs::path out = fresh_dir("golden");
    auto r = run(std::string(MBSC_BINARY) + " generate " + quote(model.string()) + " -o " + quote(out.string()));
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    for (const std::string file : {name + ".hpp", name + ".cpp", std::string(".mbsc-generated")}) {
      const fs::path fresh = out / name / file;
      const fs::path golden = root / "generated" / name / file;
      REQUIRE(fs::exists(golden));
      CHECK(slurp(fresh) == slurp(golden));
    }
    fs::remove_all(out);
  }
}
