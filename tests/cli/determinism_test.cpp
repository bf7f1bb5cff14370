// SPDX-License-Identifier: GPL-2.0-or-later
// The same command writes the same bytes in every run (docs/backend.md "Determinism").
// GiNaC orders sums and products by hashes of load addresses, so whatever follows its
// order shows between processes, not inside one (ASLR moves the addresses from process
// to process): each command runs in kRuns separate processes at once, and every run's
// output must equal the first's byte for byte. The models exercise each feature a user
// combines: spatial springs and dampers, Coulomb friction, joint coordinates,
// quaternions, Euler angles, nodal bodies, closed loops (tests/data/determinism/, whose
// flyball governor generated two different rhs in eight runs before the fix, and shipped
// models whose `print` differed).
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "run_command.hpp"

namespace fs = std::filesystem;
using namespace mbsc_test;

namespace {

constexpr int kRuns = 10;
const std::string kSource = MBSC_SOURCE_DIR;
const std::string kMbsc = MBSC_BINARY;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// Every file under `dir` (its path relative to `dir` -> its bytes).
std::map<std::string, std::string> files_under(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) out[fs::relative(e.path(), dir).string()] = slurp(e.path());
  return out;
}

/// The first line where two texts differ, both ways, for the failure message.
std::string first_difference(const std::string& a, const std::string& b) {
  std::istringstream sa(a), sb(b);
  std::string la, lb;
  for (int line = 1;; ++line) {
    const bool ha = static_cast<bool>(std::getline(sa, la)), hb = static_cast<bool>(std::getline(sb, lb));
    if (!ha && !hb) return "no difference";
    if (!ha || !hb || la != lb)
      return "line " + std::to_string(line) + ":\n  first run: " + (ha ? la.substr(0, 400) : "(end)") +
             "\n  this run:  " + (hb ? lb.substr(0, 400) : "(end)");
  }
}

/// Runs `command(folder)` in kRuns processes at once, each in a folder of its own under
/// `dir` with its standard output, error and exit status there (out, err, status), and
/// requires every run to succeed and to leave the same files as the first.
void require_same_in_every_run(const fs::path& dir, const std::function<std::string(const fs::path&)>& command) {
  std::vector<fs::path> runs;
  std::string script;
  for (int i = 0; i < kRuns; ++i) {
    const fs::path r = dir / ("run" + std::to_string(i));
    fs::create_directories(r);
    runs.push_back(r);
    script += "(" + command(r) + " > " + quote((r / "out").string()) + " 2> " + quote((r / "err").string()) +
              "; echo $? > " + quote((r / "status").string()) + ") & ";
  }
  run(script + "wait");
  const auto first = files_under(runs.front());
  for (const auto& r : runs) {
    INFO(r.string() << ": " << slurp(r / "err").substr(0, 2000));
    REQUIRE(slurp(r / "status") == "0\n");
    const auto files = files_under(r);
    REQUIRE(files.size() == first.size());
    for (const auto& [name, bytes] : first) {
      INFO(name);
      REQUIRE(files.count(name) == 1);
      INFO(first_difference(bytes, files.at(name)));
      CHECK(files.at(name) == bytes);
    }
  }
}

std::string model_path(const std::string& model) { return quote(kSource + "/" + model); }

}  // namespace

TEST_CASE("determinism: generate writes the same files in every process", "[determinism]") {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"tests/data/determinism/flyball.mbs", ""},
      {"tests/data/determinism/flyball.mbs", "--state minimal"},
      {"tests/data/determinism/friction_sled.mbs", ""},
      {"tests/data/determinism/friction_sled.mbs", "--formulation multipliers"},
      {"tests/data/determinism/flyball.mbs", "--derivatives"},
      {"tests/data/determinism/friction_sled.mbs", "--derivatives --formulation multipliers"},
      {"tests/data/determinism/nodal_loop.mbs", ""},
      {"tests/data/determinism/nodal_loop.mbs", "--formulation multipliers"},
      {"tests/data/determinism/euler_chain.mbs", ""},
      {"tests/data/determinism/euler_chain.mbs", "--state minimal"},
      {"tests/data/determinism/euler_chain.mbs", "--formulation multipliers"},
      {"tests/data/determinism/planar_chain10.mbs", "--state minimal"},
      {"tests/data/spatial_joints/arm_joint.mbs", ""}};
  for (const auto& [model, options] : cases) {
    INFO("mbsc generate " << model << " " << options);
    const fs::path dir = fresh_dir("determinism_generate");
    require_same_in_every_run(dir, [&, &model = model, &options = options](const fs::path& r) {
      return kMbsc + " generate " + model_path(model) + " -o " + quote((r / "gen").string()) + " -q " + options;
    });
    fs::remove_all(dir);
  }
}

TEST_CASE("determinism: print and print --latex write the same text in every process", "[determinism]") {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"models/sssp.mbs", ""},
      {"models/ring_disc_joints.mbs", ""},
      {"tests/data/rigid3d/free_body_quaternion_space.mbs", ""},
      {"tests/data/planar/knife_axis_nodal.mbs", ""}};
  for (const auto& [model, options] : cases) {
    for (const std::string latex : {"", "--latex"}) {
      INFO("mbsc print " << latex << " " << model << " " << options);
      const fs::path dir = fresh_dir("determinism_print");
      require_same_in_every_run(dir, [&, &model = model, &options = options](const fs::path&) {
        return kMbsc + " print " + latex + " " + model_path(model) + " " + options;
      });
      fs::remove_all(dir);
    }
  }
}

TEST_CASE("determinism: linearize --symbolic writes the same text in every process", "[determinism]") {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"tests/data/determinism/nodal_loop.mbs", "--symbolic k,c,g"},
      {"models/four_bar.mbs", "--symbolic m1,m2,m3,g,tau0 --format latex"},
      {"models/heavy_top.mbs", "--let k=2 --set m=k/2 --symbolic k --format json"},
      {"tests/data/linear/parallelogram_redundant.mbs",
       "--init crank1.theta=-1 --init crank1.w=1.3 --keep crank1.theta,crank1.w --symbolic g,m_crank,m_coupler"}};
  for (const auto& [model, options] : cases) {
    INFO("mbsc linearize " << model << " " << options);
    const fs::path dir = fresh_dir("determinism_linearize");
    const std::string command = kMbsc + " linearize " + model_path(model) + " " + options + " -q --cache-dir " +
                                quote((dir / "cache").string());
    // Compiled once (into the cache), then read by every run.
    const auto warm = run(command);
    INFO(warm.output);
    REQUIRE(warm.exit_code == 0);
    require_same_in_every_run(dir / "runs", [&](const fs::path&) { return command; });
    fs::remove_all(dir);
  }
}

TEST_CASE("determinism: the tadpole tricycle generates the same files in every process", "[determinism_tricycle]") {
  // The largest model of the tests (127 state components, 70 constraint rows): 4.7 s of one
  // core per run, its derivation 3.3 s of that (so --outputs would save little).
  const fs::path dir = fresh_dir("determinism_tricycle");
  require_same_in_every_run(dir, [](const fs::path& r) {
    return kMbsc + " generate " + model_path("tests/data/linear/tadpole_tricycle.mbs") + " -o " +
           quote((r / "gen").string()) + " -q";
  });
  fs::remove_all(dir);
}
