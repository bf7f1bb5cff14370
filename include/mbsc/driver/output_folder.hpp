// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Writing generated files so that nothing a user wrote is ever lost.
///
/// `generate` writes OUT/NAME/. The files go first into a fresh temporary folder next to
/// it, and move into place only when all of them are written. OUT/NAME is mbsc's when
/// it holds the marker file kMarkerName, which lists the files mbsc wrote there: only
/// those are replaced or removed, whatever else the folder holds stays. A folder without
/// the marker is refused, unless `force`: then mbsc writes its files into it (replacing
/// files of the same names) and removes nothing. Nothing is ever removed recursively.
#include <string>
#include <vector>

namespace mbsc::driver {

/// The marker's file name inside OUT/NAME.
inline constexpr const char* kMarkerName = ".mbsc-generated";

struct OutputFile {
  std::string name;  // a plain file name (no folder part)
  std::string text;
};

/// Writes `files` (plus the marker) into out_dir/name. Returns false with `error` set
/// (a whole sentence) when it refused or failed; then nothing was changed in out_dir
/// but, possibly, out_dir itself created.
bool write_output_folder(const std::string& out_dir, const std::string& name, const std::vector<OutputFile>& files,
                         bool force, std::string& error);

/// The checks write_output_folder makes before it writes anything, alone: false with
/// `error` set when it would refuse. Changes nothing (generate runs it before it stages
/// a --depfile, so that a refused run creates no folder).
bool check_output_folder(const std::string& out_dir, const std::string& name, const std::vector<OutputFile>& files,
                         bool force, std::string& error);

}  // namespace mbsc::driver
