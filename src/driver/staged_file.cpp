// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/driver/staged_file.hpp"

#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "mbsc/diag/diagnostics.hpp"

namespace mbsc::driver {

namespace fs = std::filesystem;

StagedFile::~StagedFile() {
  if (temp_.empty()) return;
  std::error_code ec;
  fs::remove(temp_, ec);
  for (const auto& d : created_) fs::remove(d, ec);  // deepest first; only while empty
}

bool StagedFile::stage(const std::string& path, const std::string& text, const std::string& what, std::string& error) {
  what_ = what;
  const fs::path dest(path);
  std::error_code ec;
  if (path.empty() || !dest.has_filename() || fs::is_directory(dest, ec)) {
    error = fmt::format("mbsc: error: {} '{}' names a folder, not a file", what, printable(path));
    return false;
  }
  const fs::path dir = dest.parent_path();
  if (!dir.empty()) {
    // The folders this creates go again when the file is never committed.
    for (fs::path d = dir; !d.empty() && !fs::exists(fs::symlink_status(d, ec)); d = d.parent_path()) {
      created_.push_back(d.string());
      if (d == d.parent_path()) break;
    }
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir, ec)) {
      error = fmt::format("mbsc: error: cannot create folder '{}' for {}: {}", printable(dir.string()), what,
                          ec ? ec.message() : std::string("a file of that name exists"));
      return false;
    }
  }
  std::string pattern = (dir / ("." + dest.filename().string() + ".mbsc-tmp-XXXXXX")).string();
  const int fd = ::mkstemp(pattern.data());
  if (fd < 0) {
    error = fmt::format("mbsc: error: cannot write {} '{}': {}", what, printable(path), std::strerror(errno));
    return false;
  }
  temp_ = pattern;
  // mkstemp makes the file private (0600); the destination gets the usual mode.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  ::fchmod(fd, 0666 & ~mask);
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    done += static_cast<std::size_t>(n);
  }
  const bool closed = ::close(fd) == 0;
  if (done < text.size() || !closed) {
    error = fmt::format("mbsc: error: cannot write {} '{}' (disk full or no permission?)", what, printable(path));
    return false;  // the destructor removes the temporary file
  }
  path_ = path;
  return true;
}

bool StagedFile::commit(std::string& error) {
  std::error_code ec;
  fs::rename(temp_, path_, ec);
  if (ec) {
    error = fmt::format("mbsc: error: cannot write {} '{}': {}", what_, printable(path_), ec.message());
    return false;
  }
  temp_.clear();
  created_.clear();
  return true;
}

}  // namespace mbsc::driver
