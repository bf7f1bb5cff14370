// SPDX-License-Identifier: GPL-2.0-or-later
// The compile cache folder (include/mbsc/run/model_cache.hpp).
#include "mbsc/run/model_cache.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fmt/format.h>
#include <functional>
#include <random>
#include <vector>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/run/sha256.hpp"

namespace fs = std::filesystem;

namespace mbsc::run {

namespace {

constexpr const char* kRecordName = "mbsc-entry";
constexpr const char* kRecordHeader = "mbsc compile cache entry 1";
constexpr const char* kWorkMarker = ".mbsc-work";
constexpr const char* kWorkPrefix = ".mbsc-work-";
constexpr std::size_t kMaxRecordBytes = 4096;

int open_folder_at(int dir, const std::string& name) {
  return ::openat(dir, name.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
}

/// This user's, and nobody else may write to it.
bool ours(const struct stat& st) { return st.st_uid == ::geteuid() && (st.st_mode & 022) == 0; }

bool hex_digits(const std::string& s, std::size_t from, std::size_t count) {
  if (s.size() < from + count) return false;
  return std::all_of(s.begin() + static_cast<long>(from), s.begin() + static_cast<long>(from + count),
                     [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); });
}

/// "model_" + 16 hex digits: the stem of an entry's generated files.
bool stem_name(const std::string& n, std::size_t from = 0) {
  return n.compare(from, 6, "model_") == 0 && hex_digits(n, from + 6, 16);
}

/// A file name mbsc writes into an entry or a work folder (the generator's files and
/// their backups, the shim, the object, the record, the work marker).
bool mbsc_file(const std::string& n) {
  const std::string base = n.rfind(".old.", 0) == 0 ? n.substr(5) : n;
  if (base == "shim.cpp" || base == "lib.so" || base == kRecordName || base == ".mbsc-generated" || base == kWorkMarker)
    return true;
  return base.size() == 26 && stem_name(base) && (base.compare(22, 4, ".hpp") == 0 || base.compare(22, 4, ".cpp") == 0);
}

/// A folder name mbsc makes inside a work folder: the stem, or the generator's temporary
/// `.STEM.mbsc-tmp-XXXXXX`.
bool mbsc_folder(const std::string& n) {
  if (n.size() == 22 && stem_name(n)) return true;
  return n.size() == 1 + 22 + 16 && n[0] == '.' && stem_name(n, 1) && n.compare(23, 10, ".mbsc-tmp-") == 0;
}

/// Unlinks, in folder `dir`, the files `file_ok` accepts and (one level down, when
/// `folder_ok` accepts them) the folders holding only such files. Links are removed,
/// never followed; anything else stays, and so does the folder that holds it.
void remove_known(int dir, const std::function<bool(const std::string&)>& file_ok,
                  const std::function<bool(const std::string&)>& folder_ok) {
  const int listing = ::dup(dir);
  if (listing < 0) return;
  DIR* d = ::fdopendir(listing);
  if (!d) {
    ::close(listing);
    return;
  }
  std::vector<std::pair<std::string, bool>> names;  // (name, is a folder)
  while (const dirent* e = ::readdir(d)) {
    const std::string n = e->d_name;
    if (n == "." || n == "..") continue;
    struct stat st {};
    if (::fstatat(dir, n.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0) continue;
    if (S_ISDIR(st.st_mode) ? folder_ok(n) : file_ok(n)) names.emplace_back(n, S_ISDIR(st.st_mode));
  }
  ::closedir(d);
  for (const auto& [n, folder] : names) {
    if (folder) {
      const int sub = open_folder_at(dir, n);
      if (sub < 0) continue;
      remove_known(sub, file_ok, [](const std::string&) { return false; });
      ::close(sub);
    }
    ::unlinkat(dir, n.c_str(), folder ? AT_REMOVEDIR : 0);
  }
}

/// Reads a small regular file of ours at dir/name; false when it is not one.
bool read_small_file(int dir, const char* name, std::string& text, struct stat& st) {
  const int fd = ::openat(dir, name, O_RDONLY | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) return false;
  bool ok = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && ours(st) &&
            static_cast<std::size_t>(st.st_size) <= kMaxRecordBytes;
  text.clear();
  char buf[kMaxRecordBytes];
  for (ssize_t n; ok && (n = ::read(fd, buf, sizeof buf)) != 0;) {
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 || text.size() + static_cast<std::size_t>(n) > kMaxRecordBytes) ok = false;
    else text.append(buf, static_cast<std::size_t>(n));
  }
  ::close(fd);
  return ok;
}

/// Size and SHA-256 of what an open file holds from its start.
bool hash_file(int fd, long long& size, std::string& digest) {
  if (::lseek(fd, 0, SEEK_SET) != 0) return false;
  Sha256 h;
  size = 0;
  char buf[65536];
  for (ssize_t n; (n = ::read(fd, buf, sizeof buf)) != 0;) {
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return false;
    h.update(buf, static_cast<std::size_t>(n));
    size += n;
  }
  digest = h.hex();
  return ::lseek(fd, 0, SEEK_SET) == 0;
}

/// Bytes of the plain files in a folder.
long long file_bytes(int dir) {
  const int listing = ::dup(dir);
  DIR* d = listing >= 0 ? ::fdopendir(listing) : nullptr;
  if (!d) {
    if (listing >= 0) ::close(listing);
    return 0;
  }
  long long bytes = 0;
  while (const dirent* e = ::readdir(d)) {
    struct stat st {};
    if (::fstatat(dir, e->d_name, &st, AT_SYMLINK_NOFOLLOW) == 0 && S_ISREG(st.st_mode)) bytes += st.st_size;
  }
  ::closedir(d);
  return bytes;
}

struct Record {
  std::string key, digest;
  long long size = -1;
};

bool parse_record(const std::string& text, Record& r) {
  std::size_t at = 0;
  int line_no = 0;
  while (at < text.size()) {
    const std::size_t end = text.find('\n', at);
    if (end == std::string::npos) return false;
    const std::string line = text.substr(at, end - at);
    at = end + 1;
    if (line_no++ == 0) {
      if (line != kRecordHeader) return false;
    } else if (line.rfind("key ", 0) == 0) {
      r.key = line.substr(4);
    } else if (line.rfind("sha256 ", 0) == 0) {
      r.digest = line.substr(7);
    } else if (line.rfind("size ", 0) == 0) {
      char* stop = nullptr;
      r.size = std::strtoll(line.c_str() + 5, &stop, 10);
      if (!stop || *stop != '\0') return false;
    }
  }
  return r.key.size() == 64 && r.digest.size() == 64 && r.size >= 0;
}

/// Creates the missing folders of `path`, each 0700 whatever the umask.
bool create_folders(const fs::path& path, std::string& error) {
  std::vector<fs::path> missing;
  std::error_code ec;
  for (fs::path p = path; !p.empty() && !fs::exists(fs::symlink_status(p, ec)); p = p.parent_path()) {
    missing.push_back(p);
    if (p == p.parent_path()) break;
  }
  for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
    if (::mkdir(it->c_str(), 0700) != 0 && errno != EEXIST) {
      error = fmt::format("cannot create the cache folder '{}': {}", printable(it->string()), std::strerror(errno));
      return false;
    }
    ::chmod(it->c_str(), 0700);  // a umask of 0777 would have left it unusable
  }
  return true;
}

long env_number(const char* name, long fallback) {
  const char* v = std::getenv(name);
  if (!v || !*v) return fallback;
  char* stop = nullptr;
  const long n = std::strtol(v, &stop, 10);
  return stop && *stop == '\0' && n > 0 ? n : fallback;
}

}  // namespace

// ---- the folder ----

std::unique_ptr<CacheFolder> CacheFolder::open(const std::string& path, std::string& error) {
  const std::string hint = " (choose another with --cache-dir)";
  if (path.empty()) {
    error = "the cache folder is not named" + hint;
    return nullptr;
  }
  if (!create_folders(path, error)) {
    error += hint;
    return nullptr;
  }
  auto c = std::unique_ptr<CacheFolder>(new CacheFolder());
  c->path_ = path;
  c->fd_ = ::open(path.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  struct stat st {};
  if (c->fd_ < 0) {
    const bool link = errno == ELOOP || errno == ENOTDIR;
    error = fmt::format("cannot open the cache folder '{}': {}{}", printable(path),
                        link ? "it is a symbolic link or not a folder (mbsc loads compiled code from it and follows no "
                               "link there; name the folder itself)"
                             : std::strerror(errno),
                        hint);
    return nullptr;
  }
  if (::fstat(c->fd_, &st) != 0 || !ours(st)) {
    error = fmt::format("the cache folder '{}' belongs to another user or is writable by others; mbsc loads compiled "
                        "code from it{}",
                        printable(path), hint);
    return nullptr;
  }
  return c;
}

CacheFolder::~CacheFolder() {
  if (fd_ >= 0) ::close(fd_);
}

int CacheFolder::open_object(const std::string& name, const std::string& key, std::string& why) const {
  why.clear();
  const int entry = open_folder_at(fd_, name);
  if (entry < 0) {
    if (errno != ENOENT) why = "it is not a folder of mbsc's";
    return -1;
  }
  struct stat st {};
  std::string text;
  Record record;
  int object = -1;
  if (::fstat(entry, &st) != 0 || !ours(st)) {
    why = "it belongs to another user or is writable by others";
  } else if (!read_small_file(entry, kRecordName, text, st) || !parse_record(text, record)) {
    why = "it has no record of its compilation";
  } else if (record.key != key) {
    why = "its record is of another model";
  } else if ((object = ::openat(entry, "lib.so", O_RDONLY | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK)) < 0 ||
             ::fstat(object, &st) != 0 || !S_ISREG(st.st_mode) || !ours(st)) {
    why = "its object is missing, not a plain file, another user's or writable by others";
  } else {
    long long size = -1;
    std::string digest;
    if (!hash_file(object, size, digest) || size != record.size || digest != record.digest)
      why = fmt::format("its object ({} bytes) does not match the record written when it was compiled ({} bytes)", size,
                        record.size);
  }
  if (why.empty()) {
    // Used now: the age the pruning goes by.
    const int rec = ::openat(entry, kRecordName, O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
    if (rec >= 0) ::futimens(rec, nullptr), ::close(rec);
  } else if (object >= 0) {
    ::close(object);
    object = -1;
  }
  ::close(entry);
  return object;
}

void CacheFolder::remove_entry(const std::string& name) const {
  // A link or a file where an entry belongs goes (the link itself, never what it names).
  struct stat at {};
  if (::fstatat(fd_, name.c_str(), &at, AT_SYMLINK_NOFOLLOW) == 0 && !S_ISDIR(at.st_mode)) {
    ::unlinkat(fd_, name.c_str(), 0);
    return;
  }
  const int entry = open_folder_at(fd_, name);
  if (entry < 0) return;
  struct stat st {};
  if (::fstat(entry, &st) == 0 && st.st_uid == ::geteuid())
    remove_known(entry, mbsc_file, [](const std::string&) { return false; });
  ::close(entry);
  ::unlinkat(fd_, name.c_str(), AT_REMOVEDIR);  // only when nothing else was in it
}

std::unique_ptr<CacheWork> CacheFolder::start_work(std::string& error) const {
  std::random_device seed;
  std::mt19937_64 draw((static_cast<std::uint64_t>(seed()) << 32) ^ seed() ^ static_cast<std::uint64_t>(::getpid()));
  auto w = std::unique_ptr<CacheWork>(new CacheWork());
  w->root_ = fd_;
  for (int attempt = 0; attempt < 100; ++attempt) {
    const std::string name = fmt::format("{}{}-{:012x}", kWorkPrefix, static_cast<long>(::getpid()), draw() & 0xffffffffffffULL);
    if (::mkdirat(fd_, name.c_str(), 0700) != 0) {
      if (errno == EEXIST) continue;
      break;
    }
    w->name_ = name;
    w->fd_ = open_folder_at(fd_, name);
    struct stat st {};
    if (w->fd_ < 0 || ::fstat(w->fd_, &st) != 0 || st.st_uid != ::geteuid()) break;
    ::fchmod(w->fd_, 0700);
    const int marker = ::openat(w->fd_, kWorkMarker, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
    if (marker < 0) break;
    const std::string text = fmt::format("mbsc compile work folder of process {}\n", static_cast<long>(::getpid()));
    const bool written = ::write(marker, text.data(), text.size()) == static_cast<ssize_t>(text.size());
    ::close(marker);
    if (!written) break;
    return w;
  }
  error = fmt::format("cannot write into the cache folder '{}': {} (choose another with --cache-dir)", printable(path_),
                      std::strerror(errno));
  return nullptr;
}

void CacheFolder::tidy(const std::string& keep) const {
  const int listing = ::dup(fd_);
  DIR* d = listing >= 0 ? ::fdopendir(listing) : nullptr;
  if (!d) {
    if (listing >= 0) ::close(listing);
    return;
  }
  struct Entry {
    std::string name;
    long long bytes;
    std::time_t used;
  };
  std::vector<Entry> entries;
  std::vector<std::string> stale_work;
  const std::time_t now = std::time(nullptr);
  while (const dirent* e = ::readdir(d)) {
    const std::string n = e->d_name;
    if (n.rfind(kWorkPrefix, 0) == 0) {
      // .mbsc-work-PID-XXXX: stale when its process is gone, or a day old.
      const long pid = std::strtol(n.c_str() + std::strlen(kWorkPrefix), nullptr, 10);
      const int w = open_folder_at(fd_, n);
      struct stat st {};
      std::string text;
      if (w >= 0 && read_small_file(w, kWorkMarker, text, st) && pid > 0 && pid != ::getpid() &&
          ((::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) || now - st.st_mtime > 86400))
        stale_work.push_back(n);
      if (w >= 0) ::close(w);
      continue;
    }
    const std::size_t dash = n.rfind('-');
    if (n == keep || dash == std::string::npos || n.size() != dash + 17 || !hex_digits(n, dash + 1, 16)) continue;
    const int entry = open_folder_at(fd_, n);
    if (entry < 0) continue;
    struct stat st {};
    std::string text;
    Record record;
    if (read_small_file(entry, kRecordName, text, st) && parse_record(text, record))
      entries.push_back({n, file_bytes(entry), st.st_mtime});
    ::close(entry);
  }
  ::closedir(d);
  for (const auto& n : stale_work) {
    const int w = open_folder_at(fd_, n);
    if (w < 0) continue;
    remove_known(w, mbsc_file, mbsc_folder);
    ::close(w);
    ::unlinkat(fd_, n.c_str(), AT_REMOVEDIR);
  }
  const long max_days = env_number("MBSC_CACHE_MAX_DAYS", 30);
  const long long max_bytes = static_cast<long long>(env_number("MBSC_CACHE_MAX_MIB", 2048)) << 20;
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
    return a.used != b.used ? a.used < b.used : a.name < b.name;
  });
  long long total = 0;
  for (const auto& e : entries) total += e.bytes;
  for (const auto& e : entries)
    if (now - e.used > max_days * 86400 || total > max_bytes) {
      remove_entry(e.name);
      total -= e.bytes;
    }
}

// ---- a work folder ----

CacheWork::~CacheWork() {
  if (fd_ < 0) return;
  remove_known(fd_, mbsc_file, mbsc_folder);
  ::close(fd_);
  ::unlinkat(root_, name_.c_str(), AT_REMOVEDIR);
}

std::string CacheWork::folder_path() const { return fmt::format("/proc/self/fd/{}", fd_); }

int CacheWork::open_subfolder(const std::string& name) const {
  const int sub = open_folder_at(fd_, name);
  struct stat st {};
  if (sub >= 0 && (::fstat(sub, &st) != 0 || !ours(st))) {
    ::close(sub);
    return -1;
  }
  return sub;
}

bool CacheWork::write_file(int subfolder, const std::string& file, const std::string& text, std::string& error) const {
  const int fd = ::openat(subfolder, file.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
  std::size_t done = 0;
  while (fd >= 0 && done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    done += static_cast<std::size_t>(n);
  }
  const bool ok = fd >= 0 && done == text.size() && ::close(fd) == 0;
  if (!ok) error = fmt::format("cannot write into the cache folder: {}", std::strerror(errno ? errno : EIO));
  return ok;
}

bool CacheWork::publish(const std::string& name, const std::string& entry, const std::string& key, std::string& error) {
  const int sub = open_subfolder(name);
  const int object = sub >= 0 ? ::openat(sub, "lib.so", O_RDONLY | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK) : -1;
  struct stat st {};
  long long size = -1;
  std::string digest;
  bool ok = object >= 0 && ::fstat(object, &st) == 0 && S_ISREG(st.st_mode) && st.st_uid == ::geteuid() &&
            ::fchmod(object, 0600) == 0 && hash_file(object, size, digest);
  if (object >= 0) ::close(object);
  ok = ok && write_file(sub, kRecordName,
                        fmt::format("{}\nkey {}\nsize {}\nsha256 {}\n", kRecordHeader, key, size, digest), error);
  if (sub >= 0) ::close(sub);
  if (!ok) {
    if (error.empty()) error = "the compiler wrote no usable object";
    return false;
  }
  if (::renameat(fd_, name.c_str(), root_, entry.c_str()) == 0) return true;
  if (errno == EEXIST || errno == ENOTEMPTY) return true;  // another run was first: its entry is checked on loading
  error = fmt::format("cannot move the compiled model into the cache folder: {}", std::strerror(errno));
  return false;
}

}  // namespace mbsc::run
