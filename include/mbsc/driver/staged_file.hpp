// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// One file written all or nothing, alongside the output folder (generate --depfile).
///
/// stage() writes the text into a fresh temporary file next to the destination, so that
/// every way the write can fail (no such folder, no permission, disk full) shows before
/// anything is replaced; commit() then renames it over the destination in one step. A
/// staged file that is never committed is removed by the destructor, with the folders
/// stage() created for it.
#include <string>
#include <vector>

namespace mbsc::driver {

class StagedFile {
 public:
  StagedFile() = default;
  StagedFile(const StagedFile&) = delete;
  StagedFile& operator=(const StagedFile&) = delete;
  ~StagedFile();

  /// Creates the destination's folder if needed and writes `text` to a temporary file
  /// there. False, with `error` set (a whole sentence), when it cannot, or when `path`
  /// is a folder; `what` names the file in messages (e.g. "--depfile").
  bool stage(const std::string& path, const std::string& text, const std::string& what, std::string& error);

  /// Moves the staged file into place. False, with `error` set, when the rename fails
  /// (the destination is then unchanged).
  bool commit(std::string& error);

 private:
  std::string path_, temp_, what_;
  std::vector<std::string> created_;  // folders stage() created, deepest first
};

}  // namespace mbsc::driver
