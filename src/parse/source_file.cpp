// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/parse/source_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace mbsc::parse {

namespace {

/// Closes the descriptor on every way out.
struct FileDescriptor {
  int fd = -1;
  ~FileDescriptor() {
    if (fd >= 0) ::close(fd);
  }
};

std::string size_text(std::size_t bytes) {
  if (bytes % (std::size_t{1} << 20) == 0) return std::to_string(bytes >> 20) + " MiB";
  return std::to_string(bytes) + " bytes";
}

}  // namespace

bool read_source_file(const std::string& path, std::string& text, std::string& why, std::size_t max_bytes) {
  if (path.find('\0') != std::string::npos) {
    why = "the name contains a NUL byte";
    return false;
  }
  // O_NONBLOCK: opening a pipe that has no writer must not wait; the type is checked
  // on the open descriptor, so nothing can be swapped in between.
  FileDescriptor f;
  f.fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
  if (f.fd < 0) {
    why = errno == ENOENT ? std::string("no such file") : std::strerror(errno);
    return false;
  }
  struct stat st {};
  if (::fstat(f.fd, &st) != 0) {
    why = std::strerror(errno);
    return false;
  }
  if (S_ISDIR(st.st_mode)) {
    why = "is a folder, not a model file";
    return false;
  }
  if (!S_ISREG(st.st_mode)) {
    why = "is not a regular file (a device, pipe or socket)";
    return false;
  }
  if (static_cast<std::size_t>(st.st_size) > max_bytes) {
    why = "is larger than the limit of " + size_text(max_bytes) + " for one model file";
    return false;
  }
  text.clear();
  char buf[1 << 16];
  for (;;) {
    const ssize_t n = ::read(f.fd, buf, sizeof buf);
    if (n == 0) break;
    if (n < 0) {
      if (errno == EINTR) continue;
      why = std::string("read error: ") + std::strerror(errno);
      text.clear();
      return false;
    }
    // Some files (under /proc) report no size and grow while read: keep counting.
    if (text.size() + static_cast<std::size_t>(n) > max_bytes) {
      why = "is larger than the limit of " + size_text(max_bytes) + " for one model file";
      text.clear();
      return false;
    }
    text.append(buf, static_cast<std::size_t>(n));
  }
  return true;
}

}  // namespace mbsc::parse
