// SPDX-License-Identifier: GPL-2.0-or-later
// Unit tests of StagedFile: a file replaced all or nothing, no temporary left behind.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>

#include "mbsc/driver/staged_file.hpp"

namespace fs = std::filesystem;
using mbsc::driver::StagedFile;

namespace {

fs::path fresh_dir() {
  std::random_device rd;
  const fs::path p = fs::temp_directory_path() / ("mbsc_staged_test_" + std::to_string(rd()) + std::to_string(rd()));
  fs::create_directories(p);
  return p;
}

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::size_t entries(const fs::path& dir) {
  return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

}  // namespace

TEST_CASE("staged file: the destination changes only on commit", "[driver][staged]") {
  const fs::path dir = fresh_dir();
  const fs::path dest = dir / "out.d";
  std::ofstream(dest) << "old";
  std::string error;
  {
    StagedFile f;
    REQUIRE(f.stage(dest.string(), "new text", "--depfile", error));
    CHECK(read(dest) == "old");  // staged beside it, not yet in place
    CHECK(entries(dir) == 2);
    REQUIRE(f.commit(error));
  }
  CHECK(read(dest) == "new text");
  CHECK(entries(dir) == 1);  // no temporary file left
  {
    StagedFile f;
    REQUIRE(f.stage(dest.string(), "abandoned", "--depfile", error));
  }  // never committed: the temporary file goes, the destination stays
  CHECK(read(dest) == "new text");
  CHECK(entries(dir) == 1);
  fs::remove_all(dir);
}

TEST_CASE("staged file: missing folders are created, a folder is refused", "[driver][staged]") {
  const fs::path dir = fresh_dir();
  std::string error;
  {
    StagedFile f;
    REQUIRE(f.stage((dir / "a" / "b" / "x.d").string(), "t", "--depfile", error));
    REQUIRE(f.commit(error));
  }
  CHECK(read(dir / "a" / "b" / "x.d") == "t");
  StagedFile f;
  CHECK_FALSE(f.stage((dir / "a").string(), "t", "--depfile", error));
  CHECK(error.find("--depfile") != std::string::npos);
  CHECK(error.find("names a folder") != std::string::npos);
  // A path under a file cannot become a folder.
  CHECK_FALSE(f.stage((dir / "a" / "b" / "x.d" / "y.d").string(), "t", "--depfile", error));
  CHECK(error.find("cannot create folder") != std::string::npos);
  fs::remove_all(dir);
}
