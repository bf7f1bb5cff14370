// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// The folder where `mbsc run` (and inverse, bench, linearize, eig) keeps compiled models.
/// mbsc loads code from it into its own process, so nothing in it is trusted by its path:
///
/// * The folder is opened once, without following a link at its last component, and
///   checked on the descriptor: a folder of this user's that nobody else may write to.
///   It is created 0700 whatever the umask. Everything below it is reached from that
///   descriptor (openat, O_NOFOLLOW), never by a path that could be swapped meanwhile.
/// * An entry `NAME-KEY/` holds the generated sources, `lib.so` and `mbsc-entry`, a
///   record written by the run that compiled it: the SHA-256 of the full cache key and
///   the size and SHA-256 of `lib.so`. Before loading, the entry, record and object must
///   be this user's, writable by nobody else, and the object must match its record; the
///   object is then loaded through its verified descriptor (/proc/self/fd), so the file
///   checked is the file loaded. An entry that does not match is removed and rebuilt.
/// * An entry is built in a private work folder `.mbsc-work-PID-XXXXXX` (marked by a
///   file `.mbsc-work`) and renamed into place when complete. Work folders of runs that
///   ended are removed on a later build; removal only ever unlinks the names mbsc itself
///   writes there, so nothing a user put into the folder (e.g. with --cache-dir) is
///   deleted.
/// * Entries not used for MBSC_CACHE_MAX_DAYS (default 30) days are pruned, and then the
///   least recently used ones while the entries take more than MBSC_CACHE_MAX_MIB
///   (default 2048) MiB; pruning runs whenever a new entry is built.
#include <memory>
#include <string>

namespace mbsc::run {

class CacheWork;

class CacheFolder {
 public:
  /// Opens (creating, 0700) the folder at `path`; null with `error` (a whole sentence).
  static std::unique_ptr<CacheFolder> open(const std::string& path, std::string& error);
  ~CacheFolder();
  CacheFolder(const CacheFolder&) = delete;
  CacheFolder& operator=(const CacheFolder&) = delete;

  const std::string& path() const { return path_; }

  /// The verified object of entry `name` for the key digest `key`: an open read-only
  /// descriptor, or -1 with `why` empty (no such entry) or saying why it cannot be used.
  int open_object(const std::string& name, const std::string& key, std::string& why) const;

  /// Removes entry `name`: the files mbsc writes into an entry, then the folder if empty.
  void remove_entry(const std::string& name) const;

  /// A new private work folder; null with `error`.
  std::unique_ptr<CacheWork> start_work(std::string& error) const;

  /// Removes the work folders of runs that ended, and prunes entries by age and size
  /// (never `keep`).
  void tidy(const std::string& keep) const;

 private:
  CacheFolder() = default;
  int fd_ = -1;
  std::string path_;
};

/// A work folder: the generator writes into `folder_path()`, the compiler runs in a
/// subfolder (`subfolder_fd`), and `publish` turns that subfolder into an entry.
class CacheWork {
 public:
  ~CacheWork();  // removes what is left of the work folder
  CacheWork(const CacheWork&) = delete;
  CacheWork& operator=(const CacheWork&) = delete;

  /// A path to the work folder that cannot be redirected (/proc/self/fd/N).
  std::string folder_path() const;
  /// The work folder's subfolder `name`, opened; -1 when it is not a folder of ours.
  int open_subfolder(const std::string& name) const;
  /// Writes `text` to a new file `file` in the subfolder (0600). False with `error`.
  bool write_file(int subfolder, const std::string& file, const std::string& text, std::string& error) const;
  /// Records subfolder `name`'s lib.so (made private, size and hash) with the key digest
  /// and renames the subfolder to entry `entry`. When another run put that entry in place
  /// first, that one stays (true). False with `error`.
  bool publish(const std::string& name, const std::string& entry, const std::string& key, std::string& error);

 private:
  friend class CacheFolder;
  CacheWork() = default;
  int root_ = -1;  // the cache folder (not owned)
  int fd_ = -1;
  std::string name_;
};

}  // namespace mbsc::run
