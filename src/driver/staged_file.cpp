// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/driver/staged_file.hpp"

#include <fcntl.h>
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

std::string not_a_plain_file(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return "";  // not there (or a dangling link): a new file
  if (S_ISREG(st.st_mode)) return "";
  if (S_ISDIR(st.st_mode)) return "is a folder; name a file";
  const char* kind = S_ISFIFO(st.st_mode) ? "a named pipe" : S_ISSOCK(st.st_mode) ? "a socket" : "a device";
  return fmt::format("is {}, not a plain file; mbsc writes a file beside it and renames it into place (write to "
                     "standard output with '-' instead)",
                     kind);
}

StagedFile::~StagedFile() {
  close_fd();
  if (temp_.empty()) return;
  std::error_code ec;
  fs::remove(temp_, ec);
  for (const auto& d : created_) fs::remove(d, ec);  // deepest first; only while empty
}

void StagedFile::close_fd() {
  if (fd_ < 0) return;
  if (::close(fd_) != 0 && !failed_) failed_ = true, write_errno_ = errno;
  fd_ = -1;
}

bool StagedFile::open(const std::string& path, const std::string& what, std::string& error) {
  what_ = what;
  std::error_code ec;
  if (path.empty() || !fs::path(path).has_filename() || fs::is_directory(path, ec)) {
    error = fmt::format("mbsc: error: {} '{}' names a folder, not a file", what, printable(path));
    return false;
  }
  if (const std::string why = not_a_plain_file(path); !why.empty()) {
    error = fmt::format("mbsc: error: {} '{}' {}", what, printable(path), why);
    return false;
  }
  // A link to a file: the file it names is replaced, the link stays.
  fs::path dest(path);
  if (fs::is_symlink(fs::symlink_status(dest, ec)) && fs::exists(dest, ec)) dest = fs::canonical(dest, ec);
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
  fd_ = ::mkostemp(pattern.data(), O_CLOEXEC);
  if (fd_ < 0) {
    error = fmt::format("mbsc: error: cannot write {} '{}': {}", what, printable(path), std::strerror(errno));
    return false;
  }
  temp_ = pattern;
  path_ = dest.string();
  // mkstemp makes the file private (0600); the destination gets the mode a new file of
  // the user's gets, or the one the file it replaces had.
  struct stat old {};
  const mode_t mask = ::umask(0);
  ::umask(mask);
  ::fchmod(fd_, ::stat(path_.c_str(), &old) == 0 ? (old.st_mode & 07777) : (0666 & ~mask));
  return true;
}

bool StagedFile::write(const std::string& text) {
  if (fd_ < 0 || failed_) return false;
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd_, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      failed_ = true;
      write_errno_ = n < 0 ? errno : ENOSPC;
      return false;
    }
    done += static_cast<std::size_t>(n);
  }
  return true;
}

bool StagedFile::stage(const std::string& path, const std::string& text, const std::string& what, std::string& error) {
  if (!open(path, what, error)) return false;
  if (write(text)) return true;
  error = fmt::format("mbsc: error: cannot write {} '{}': {}", what, printable(path), std::strerror(write_errno_));
  return false;  // the destructor removes the temporary file
}

bool StagedFile::commit(std::string& error) {
  close_fd();
  if (failed_) {
    error = fmt::format("mbsc: error: cannot write {} '{}': {}; it was left as it was", what_, printable(path_),
                        std::strerror(write_errno_));
    return false;
  }
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

std::string StagedFile::keep() {
  close_fd();
  std::string kept = temp_;
  temp_.clear();
  created_.clear();
  return kept;
}

}  // namespace mbsc::driver
