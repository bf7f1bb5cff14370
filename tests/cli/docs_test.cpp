// SPDX-License-Identifier: GPL-2.0-or-later
// The repository's docs stand alone: every relative link in README.md, docs/*.md and the
// shipped models resolves to a file inside the repository, and nothing cites a path
// outside it (design notes that a reader of the repository cannot open).
#include <catch2/catch.hpp>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "run_command.hpp"

namespace fs = std::filesystem;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::vector<fs::path> documents(const fs::path& root) {
  std::vector<fs::path> files{root / "README.md"};
  for (const char* dir : {"docs", "models"})
    for (const auto& e : fs::directory_iterator(root / dir))
      if (e.path().extension() == ".md" || e.path().extension() == ".mbs") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

/// True when `target` (relative to `from`'s folder) stays inside `root`.
bool inside(const fs::path& root, const fs::path& from, const std::string& target) {
  const fs::path resolved = fs::weakly_canonical(from.parent_path() / target);
  const std::string r = fs::weakly_canonical(root).string() + "/";
  return resolved.string().rfind(r, 0) == 0;
}

}  // namespace

TEST_CASE("docs: relative links resolve inside the repository", "[docs]") {
  const fs::path root(MBSC_SOURCE_DIR);
  const std::regex link(R"(\]\(([^)#\s]+)(#[^)]*)?\))");  // [text](target#anchor)
  int checked = 0;
  for (const auto& file : documents(root)) {
    const std::string text = slurp(file);
    for (auto it = std::sregex_iterator(text.begin(), text.end(), link); it != std::sregex_iterator(); ++it) {
      const std::string target = (*it)[1];
      if (target.find("://") != std::string::npos || target.rfind("mailto:", 0) == 0) continue;
      INFO(file.string() << " links to " << target);
      CHECK(inside(root, file, target));
      CHECK(fs::exists(file.parent_path() / target));
      ++checked;
    }
  }
  CHECK(checked > 10);
}

TEST_CASE("docs: no citation of files outside the repository", "[docs]") {
  const fs::path root(MBSC_SOURCE_DIR);
  // A path that climbs out of the repository (`../x/...` from the root or from docs/
  // climbing twice) or names the design notes the docs grew from.
  const std::regex outside(R"((^|[\s`(])(\.\./)+(shared|seeds|design)\b|methodology\.md|architecture\.md)");
  for (const auto& file : documents(root)) {
    const std::string text = slurp(file);
    std::smatch m;
    INFO(file.string());
    CHECK_FALSE(std::regex_search(text, m, outside));
  }
}

TEST_CASE("docs: the sample header of docs/backend.md is what mbsc generates", "[docs]") {
  const fs::path root = MBSC_SOURCE_DIR;
  const std::string doc = slurp(root / "docs" / "backend.md");
  const std::string open = "```cpp\n", intro = "Header `<name>.hpp`";
  const auto at = doc.find(intro);
  REQUIRE(at != std::string::npos);
  const auto begin = doc.find(open, at);
  REQUIRE(begin != std::string::npos);
  const auto end = doc.find("```", begin + open.size());
  const std::string sample = doc.substr(begin + open.size(), end - begin - open.size());
  // The model the text describes, generated as it says.
  const fs::path dir = mbsc_test::fresh_dir("docs_header");
  std::ofstream(dir / "pendulum.mbs") << "model pendulum\nparameter g = 9.81, l = 1\n"
                                         "subsystem p : custom {\n  coordinate q\n  speed w = q'\n  force w : -g/l*sin(q)\n}\n";
  const auto r = mbsc_test::run("cd " + mbsc_test::quote(dir.string()) + " && " + std::string(MBSC_BINARY) +
                                " generate pendulum.mbs -o out --freeze l=1 --outputs rhs --quiet");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const std::string header = slurp(dir / "out" / "pendulum" / "pendulum.hpp");
  // Every declaration, doc comment and constant of the sample, as a whole line.
  std::istringstream lines(sample);
  int checked = 0;
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("///", 0) != 0 && line.rfind("int ", 0) != 0 && line.rfind("inline constexpr", 0) != 0 &&
        line.rfind("MBSC_HOST_DEVICE int ", 0) != 0 && line.rfind("#ifndef MBSC_HOST_DEVICE", 0) != 0 &&
        line.rfind("//   ", 0) != 0 && line.rfind("// kInputNames", 0) != 0)
      continue;
    INFO(line);
    CHECK(header.find("\n" + line + "\n") != std::string::npos);
    ++checked;
  }
  CHECK(checked >= 15);
  fs::remove_all(dir);
}

namespace {

/// An expected line: its pieces between `…` appear, in order, within one output line.
bool line_matches(const std::string& line, const std::string& expected) {
  const std::string ellipsis = "\xE2\x80\xA6";  // …
  std::size_t at = 0, from = 0;
  while (true) {
    const std::size_t cut = expected.find(ellipsis, from);
    const std::string piece = expected.substr(from, cut == std::string::npos ? std::string::npos : cut - from);
    if (!piece.empty()) {
      const std::size_t found = line.find(piece, at);
      if (found == std::string::npos) return false;
      at = found + piece.size();
    }
    if (cut == std::string::npos) return true;
    from = cut + ellipsis.size();
  }
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

}  // namespace

// docs/tutorial.md runs as written: every `console` block's commands ("$ " lines) in a
// folder that holds the repository's models/, include/ and apps/, each exit 0 and
// printing the lines the tutorial shows after it, in order (`…` inside a line stands for
// any text, a line that is only `…` for any lines); every `mbs` block quotes the model
// file named just before it, line for line.
TEST_CASE("docs/tutorial.md: every command runs and prints what the tutorial shows", "[tutorial]") {
  const fs::path root(MBSC_SOURCE_DIR);
  const std::vector<std::string> doc = lines_of(slurp(root / "docs" / "tutorial.md"));
  const fs::path dir = mbsc_test::fresh_dir("tutorial");
  for (const char* sub : {"models", "include", "apps"}) fs::create_directory_symlink(root / sub, dir / sub);
  const std::string bin = fs::path(MBSC_BINARY).parent_path().string();
  int commands = 0, quotes = 0;
  std::string last_model;  // the last `models/NAME.mbs` the text names
  const std::regex model_ref("`(models/[a-z_0-9]+\\.mbs)`");
  for (std::size_t i = 0; i < doc.size(); ++i) {
    for (auto it = std::sregex_iterator(doc[i].begin(), doc[i].end(), model_ref); it != std::sregex_iterator(); ++it)
      last_model = (*it)[1];
    if (doc[i] == "```mbs") {
      REQUIRE_FALSE(last_model.empty());
      const std::vector<std::string> file = lines_of(slurp(root / last_model));
      for (++i; i < doc.size() && doc[i] != "```"; ++i) {
        INFO("tutorial line " << i + 1 << " quotes " << last_model << ": " << doc[i]);
        CHECK(std::find(file.begin(), file.end(), doc[i]) != file.end());
        ++quotes;
      }
      continue;
    }
    if (doc[i] != "```console") continue;
    // The block: commands, each followed by its expected lines.
    std::vector<std::pair<std::string, std::vector<std::string>>> steps;
    for (++i; i < doc.size() && doc[i] != "```"; ++i) {
      if (doc[i].rfind("$ ", 0) == 0) steps.push_back({doc[i].substr(2), {}});
      else if (!steps.empty() && doc[i] != "\xE2\x80\xA6") steps.back().second.push_back(doc[i]);
    }
    for (const auto& [command, expected] : steps) {
      // The command as a script (its own quotes intact), run with mbsc on PATH.
      mbsc_test::write(dir / "step.sh", command + "\n");
      const auto r = mbsc_test::run("cd " + mbsc_test::quote(dir.string()) + " && PATH=" + mbsc_test::quote(bin) +
                                    ":\"$PATH\" MBSC_CACHE_DIR=" + mbsc_test::quote((dir / "cache").string()) +
                                    " sh step.sh");
      INFO("$ " << command << "\n" << r.output);
      ++commands;
      if (r.output.find("gnuplot is needed") != std::string::npos) {
        WARN("gnuplot not installed: the tutorial's plot command is not checked");
        continue;
      }
      CHECK(r.exit_code == 0);
      const std::vector<std::string> out = lines_of(r.output);
      std::size_t next = 0;
      for (const auto& e : expected) {
        INFO("expected, in order: " << e);
        std::size_t k = next;
        while (k < out.size() && !line_matches(out[k], e)) ++k;
        CHECK(k < out.size());
        if (k < out.size()) next = k + 1;
      }
    }
  }
  CHECK(commands >= 12);
  CHECK(quotes >= 10);
  fs::remove_all(dir);
}
