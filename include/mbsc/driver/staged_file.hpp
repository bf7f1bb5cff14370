// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// One output file written all or nothing: the `--depfile`, the CSVs, tables and plots of
/// run, inverse, bench, linearize and eig.
///
/// open() creates a fresh temporary file beside the destination (mkstemp: a new name,
/// O_EXCL, never a file or link that was there); write() appends to it; commit() renames
/// it over the destination in one step. So a destination is either its old self or
/// complete, whatever happens meanwhile (a kill, a full disk). A destination that is a
/// link to a plain file is replaced through the link (the file it names), and one that
/// exists but is not a plain file (a FIFO, a device, a folder) is refused. keep() ends a
/// write that failed half-way: the temporary stays, with what was written, for the
/// message to name. Otherwise a temporary that is never committed is removed by the
/// destructor, with the folders open() created for it.
#include <string>
#include <vector>

namespace mbsc::driver {

class StagedFile {
 public:
  StagedFile() = default;
  StagedFile(const StagedFile&) = delete;
  StagedFile& operator=(const StagedFile&) = delete;
  ~StagedFile();

  /// Creates the destination's folder if needed and opens a temporary file there. False,
  /// with `error` set (a whole sentence), when it cannot, or when `path` is a folder or
  /// not a plain file; `what` names the file in messages (e.g. "--depfile", "-o").
  bool open(const std::string& path, const std::string& what, std::string& error);
  /// Appends `text`; false once any write failed (disk full), which commit() reports.
  bool write(const std::string& text);
  /// open() and write(): the whole text at once.
  bool stage(const std::string& path, const std::string& text, const std::string& what, std::string& error);

  /// Moves the written file into place. False, with `error` set, when a write or the
  /// rename failed (the destination is then unchanged and the temporary removed).
  bool commit(std::string& error);
  /// Closes the temporary and leaves it in place; returns its path ("" when none).
  std::string keep();

  /// The temporary's path while open.
  const std::string& temporary() const { return temp_; }

 private:
  void close_fd();
  std::string path_, temp_, what_;
  int fd_ = -1;
  bool failed_ = false;
  int write_errno_ = 0;
  std::vector<std::string> created_;  // folders open() created, deepest first
};

/// Why `path` cannot be replaced by a file mbsc writes ("" when it can): it exists but
/// is not a plain file (a FIFO, a device, a socket, a folder), also through a link.
std::string not_a_plain_file(const std::string& path);

}  // namespace mbsc::driver
