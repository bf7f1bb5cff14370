// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/driver/output_folder.hpp"

#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "mbsc/diag/diagnostics.hpp"

namespace mbsc::driver {

namespace fs = std::filesystem;

namespace {

constexpr const char* kMarkerHeader = "# This folder was written by mbsc generate.";

std::string marker_text(const std::vector<OutputFile>& files) {
  std::string text = std::string(kMarkerHeader) +
                     "\n# mbsc replaces or removes the files listed below, and only those, when it\n"
                     "# generates into this folder again. Anything else here is left alone.\n";
  for (const auto& f : files) text += f.name + "\n";
  return text;
}

/// A name the marker may list: a plain file name, nothing that leaves the folder.
bool plain_name(const std::string& n) {
  return !n.empty() && n != "." && n != ".." && n != kMarkerName && n.find('/') == std::string::npos &&
         n.find('\0') == std::string::npos;
}

/// Reads the marker of an existing folder: true (and the files it lists) when the
/// folder is mbsc's.
bool read_marker(const fs::path& dir, std::set<std::string>& listed) {
  std::error_code ec;
  const fs::path marker = dir / kMarkerName;
  const auto st = fs::symlink_status(marker, ec);
  if (ec || !fs::is_regular_file(st) || fs::file_size(marker, ec) > 65536 || ec) return false;
  std::ifstream in(marker, std::ios::binary);
  std::string line;
  if (!std::getline(in, line) || line != kMarkerHeader) return false;
  while (std::getline(in, line))
    if (!line.empty() && line[0] != '#' && plain_name(line)) listed.insert(line);
  return true;
}

bool write_file(const fs::path& p, const std::string& text) {
  std::ofstream f(p, std::ios::binary | std::ios::trunc);
  f << text;
  f.close();
  return static_cast<bool>(f);
}

/// The name a replaced file is kept under, in the temporary folder, until the new
/// files are all in place.
std::string backup_name(const std::string& name) { return ".old." + name; }

/// Removes the files a write may have put into a temporary folder (its own and the
/// backups), then the folder itself; nothing else (it only goes when it is empty).
void discard(const fs::path& tmp, const std::vector<OutputFile>& files) {
  std::error_code ec;
  for (const auto& f : files) {
    fs::remove(tmp / f.name, ec);
    fs::remove(tmp / backup_name(f.name), ec);
  }
  fs::remove(tmp, ec);
}

/// Temporary folders of earlier runs for this name that were interrupted (Ctrl-C during
/// the write): `.NAME.mbsc-tmp-XXXXXX` folders holding only files mbsc writes.
void discard_stale(const fs::path& out_dir, const std::string& name, const std::vector<OutputFile>& files) {
  std::error_code ec;
  const std::string prefix = "." + name + ".mbsc-tmp-";
  std::vector<fs::path> stale;
  for (fs::directory_iterator it(out_dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string entry = it->path().filename().string();
    if (entry.size() == prefix.size() + 6 && entry.compare(0, prefix.size(), prefix) == 0 &&
        fs::is_directory(it->symlink_status()))
      stale.push_back(it->path());
  }
  for (const auto& dir : stale) discard(dir, files);
}

std::string shown(const fs::path& p) { return printable(p.string()); }

/// The checks before anything is written: may mbsc write `files` into OUT/NAME? Sets
/// `fresh` when the folder does not exist, else `previous` (what its marker lists).
bool inspect(const std::string& out_dir_text, const std::string& name, const std::vector<OutputFile>& files_in,
             bool force, bool& fresh, std::set<std::string>& previous, std::string& error) {
  const fs::path out_dir = out_dir_text.empty() ? fs::path(".") : fs::path(out_dir_text);
  const fs::path target = out_dir / name;
  std::vector<OutputFile> files = files_in;
  files.push_back({kMarkerName, marker_text(files_in)});
  for (const auto& f : files_in)
    if (!plain_name(f.name)) {
      error = fmt::format("mbsc: internal error: output file name '{}' is not a plain name", printable(f.name));
      return false;
    }

  // What is there now decides what may be replaced.
  std::error_code ec;
  const auto st = fs::symlink_status(target, ec);
  if (ec && ec != std::errc::no_such_file_or_directory) {
    error = fmt::format("mbsc: error: cannot inspect '{}': {}", shown(target), ec.message());
    return false;
  }
  if (!fs::exists(st)) {
    fresh = true;
  } else if (fs::is_symlink(st) && !force) {
    error = fmt::format("mbsc: error: '{}' is a symbolic link; mbsc does not write through it (generate elsewhere with "
                        "-o or --name, or pass --force)",
                        shown(target));
    return false;
  } else if (!fs::is_directory(target, ec)) {
    error = fmt::format("mbsc: error: '{}' exists and is not a folder; mbsc will not replace it (generate elsewhere "
                        "with -o or --name)",
                        shown(target));
    return false;
  } else if (!read_marker(target, previous) && !force) {
    error = fmt::format("mbsc: error: '{}' exists and was not written by mbsc (it has no {} marker); refusing to "
                        "touch it. Generate elsewhere with -o or --name, or pass --force to write {}.hpp and {}.cpp "
                        "into it (nothing else there is removed)",
                        shown(target), kMarkerName, name, name);
    return false;
  }
  if (!fresh)
    for (const auto& f : files) {
      const auto fst = fs::symlink_status(target / f.name, ec);
      if (fs::is_directory(fst)) {
        error = fmt::format("mbsc: error: '{}' is a folder; mbsc will not replace it", shown(target / f.name));
        return false;
      }
    }

  return true;
}

}  // namespace

bool check_output_folder(const std::string& out_dir_text, const std::string& name, const std::vector<OutputFile>& files_in,
                         bool force, std::string& error) {
  bool fresh = false;
  std::set<std::string> previous;
  return inspect(out_dir_text, name, files_in, force, fresh, previous, error);
}

bool write_output_folder(const std::string& out_dir_text, const std::string& name, const std::vector<OutputFile>& files_in,
                         bool force, std::string& error) {
  const fs::path out_dir = out_dir_text.empty() ? fs::path(".") : fs::path(out_dir_text);
  const fs::path target = out_dir / name;
  std::vector<OutputFile> files = files_in;
  files.push_back({kMarkerName, marker_text(files_in)});
  bool fresh = false;
  std::set<std::string> previous;  // files the marker says mbsc wrote before
  if (!inspect(out_dir_text, name, files_in, force, fresh, previous, error)) return false;
  std::error_code ec;

  // Write everything into a fresh temporary folder next to the target.
  fs::create_directories(out_dir, ec);
  if (ec || !fs::is_directory(out_dir, ec)) {
    error = fmt::format("mbsc: error: cannot create folder '{}': {}", shown(out_dir),
                        ec ? ec.message() : std::string("a file of that name exists"));
    return false;
  }
  discard_stale(out_dir, name, files);
  std::string pattern = (out_dir / ("." + name + ".mbsc-tmp-XXXXXX")).string();
  if (!::mkdtemp(pattern.data())) {
    error = fmt::format("mbsc: error: cannot create a temporary folder in '{}': {}", shown(out_dir), std::strerror(errno));
    return false;
  }
  const fs::path tmp(pattern);
  // mkdtemp makes the folder private (0700); the final folder gets the usual mode.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  ::chmod(tmp.c_str(), 0777 & ~mask);
  for (const auto& f : files)
    if (!write_file(tmp / f.name, f.text)) {
      discard(tmp, files);
      error = fmt::format("mbsc: error: cannot write into '{}' (disk full or no permission?)", shown(out_dir));
      return false;
    }

  // Move into place: the whole folder at once when new; else file by file (each rename
  // replaces one file atomically), the marker last.
  if (fresh) {
    fs::rename(tmp, target, ec);
    if (ec) {
      discard(tmp, files);
      error = fmt::format("mbsc: error: cannot create '{}': {}", shown(target), ec.message());
      return false;
    }
    return true;
  }
  // The files being replaced move into the temporary folder first, so that a failure
  // half-way can put every one of them back (all or nothing).
  std::vector<std::string> backed_up, moved_in;
  auto roll_back = [&] {
    std::error_code ignore;
    for (const auto& f : moved_in) fs::remove(target / f, ignore);
    for (const auto& f : backed_up) fs::rename(tmp / backup_name(f), target / f, ignore);
    discard(tmp, files);
  };
  for (const auto& f : files) {
    if (!fs::exists(fs::symlink_status(target / f.name, ec))) continue;
    fs::rename(target / f.name, tmp / backup_name(f.name), ec);
    if (ec) {
      const std::string why = ec.message();
      roll_back();
      error = fmt::format("mbsc: error: cannot replace '{}': {}", shown(target / f.name), why);
      return false;
    }
    backed_up.push_back(f.name);
  }
  for (const auto& f : files) {
    fs::rename(tmp / f.name, target / f.name, ec);
    if (ec) {
      const std::string why = ec.message();
      roll_back();
      error = fmt::format("mbsc: error: cannot write '{}': {}", shown(target / f.name), why);
      return false;
    }
    moved_in.push_back(f.name);
  }
  discard(tmp, files);  // the backups, then the folder
  // Files mbsc wrote last time and not now (another --name, fewer outputs): remove them,
  // and nothing else.
  std::set<std::string> now;
  for (const auto& f : files) now.insert(f.name);
  for (const auto& old : previous) {
    if (now.count(old)) continue;
    const auto ost = fs::symlink_status(target / old, ec);
    if (fs::is_regular_file(ost)) fs::remove(target / old, ec);
  }
  return true;
}

}  // namespace mbsc::driver
