// SPDX-License-Identifier: GPL-2.0-or-later
// Checks on output paths before any work (include/mbsc/run/output_guard.hpp).
#include "mbsc/run/output_guard.hpp"

#include <unistd.h>

#include <filesystem>
#include <fmt/format.h>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/driver/staged_file.hpp"
#include "mbsc/run/process.hpp"

namespace fs = std::filesystem;

namespace mbsc::run {

namespace {

/// The same file: by inode when both exist, else by their normalized absolute paths.
bool same_file(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
  return fs::weakly_canonical(fs::absolute(a), ec) == fs::weakly_canonical(fs::absolute(b), ec);
}

}  // namespace

bool check_outputs(const std::vector<std::pair<std::string, std::string>>& outputs,
                   const std::vector<std::string>& sources, std::string& error) {
  std::error_code ec;
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const auto& [flag, path] = outputs[i];
    if (path.empty() || path == "-") continue;
    if (fs::is_directory(path, ec)) {
      error = fmt::format("{}: '{}' is a folder; name a file", flag, printable(path));
      return false;
    }
    if (const std::string why = driver::not_a_plain_file(path); !why.empty()) {
      error = fmt::format("{}: '{}' {}", flag, printable(path), why);
      return false;
    }
    // gnuplot reads the CSV by name and a line break would end its string: no output
    // name holds a control character.
    for (unsigned char c : path)
      if (c < 0x20 || c == 0x7f) {
        error = fmt::format("{}: '{}' holds a control character; name the file without one", flag, printable(path));
        return false;
      }
    for (const auto& s : sources)
      if (same_file(path, s)) {
        error = fmt::format("{}: '{}' is {}; mbsc will not overwrite it", flag, printable(path),
                            s == sources.front() ? "the model file" : "a file the model includes ('" + printable(s) + "')");
        return false;
      }
    for (std::size_t j = 0; j < i; ++j)
      if (!outputs[j].second.empty() && outputs[j].second != "-" && same_file(path, outputs[j].second)) {
        error = fmt::format("{} and {} name the same file '{}'", outputs[j].first, flag, printable(path));
        return false;
      }
    const fs::path folder = fs::absolute(path, ec).parent_path();
    if (!fs::is_directory(folder, ec)) {
      error = fmt::format("{}: cannot write '{}': the folder '{}' does not exist", flag, printable(path),
                          printable(folder.string()));
      return false;
    }
    if (access(folder.c_str(), W_OK) != 0 || (fs::exists(path, ec) && access(path.c_str(), W_OK) != 0)) {
      error = fmt::format("{}: cannot write '{}': permission denied", flag, printable(path));
      return false;
    }
  }
  return true;
}

bool gnuplot_available(std::string& error) {
  const ProcessResult r = run_process({"gnuplot", "--version"}, "", 20);
  if (r.exit_code == 0) return true;
  error = "gnuplot is needed for --plot and was not found (install the Debian package gnuplot-nox)";
  return false;
}

}  // namespace mbsc::run
