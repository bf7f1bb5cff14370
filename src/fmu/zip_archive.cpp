// SPDX-License-Identifier: GPL-2.0-or-later
// The zip container of exported FMUs (include/mbsc/fmu/zip_archive.hpp), after the
// format's published description (PKWARE's APPNOTE): local headers with the data, then
// the central directory and its end record, little-endian throughout.
#include "mbsc/fmu/zip_archive.hpp"

#include <array>
#include <limits>

namespace mbsc::fmu {

namespace {

constexpr std::uint16_t kDosTime = 0;                 // 00:00:00
constexpr std::uint16_t kDosDate = (0 << 9) | (1 << 5) | 1;  // 1980-01-01
constexpr std::uint16_t kVersion = 20;                // 2.0: what reading these entries needs
constexpr std::uint16_t kMadeByUnix = (3 << 8) | 20;  // the external attributes are Unix modes
constexpr std::uint16_t kUtf8Names = 1 << 11;         // general purpose flag: names are UTF-8

void put16(std::string& s, std::uint16_t v) {
  s += static_cast<char>(v & 0xff);
  s += static_cast<char>(v >> 8);
}
void put32(std::string& s, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) s += static_cast<char>((v >> (8 * i)) & 0xff);
}

}  // namespace

std::uint32_t crc32(const std::string& data) {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t n = 0; n < 256; ++n) {
      std::uint32_t c = n;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xedb88320u ^ (c >> 1) : c >> 1;
      t[n] = c;
    }
    return t;
  }();
  std::uint32_t c = 0xffffffffu;
  for (unsigned char b : data) c = table[(c ^ b) & 0xff] ^ (c >> 8);
  return c ^ 0xffffffffu;
}

void ZipArchive::add(const std::string& path, std::string data, bool executable) {
  entries_.push_back({path, std::move(data), executable});
}

bool ZipArchive::bytes(std::string& out, std::string& error) const {
  constexpr std::uint64_t kMax = std::numeric_limits<std::uint32_t>::max();
  if (entries_.size() >= 0xffff) {
    error = "too many files for a zip archive without zip64";
    return false;
  }
  out.clear();
  std::string directory;
  for (const Entry& e : entries_) {
    const std::uint64_t offset = out.size();
    if (offset > kMax || e.data.size() > kMax || e.path.size() > 0xffff) {
      error = "'" + e.path + "' does not fit a zip archive without zip64 (4 GiB)";
      return false;
    }
    const std::uint32_t crc = crc32(e.data);
    const auto size = static_cast<std::uint32_t>(e.data.size());
    // Local file header.
    put32(out, 0x04034b50);
    put16(out, kVersion);
    put16(out, kUtf8Names);
    put16(out, 0);  // stored
    put16(out, kDosTime);
    put16(out, kDosDate);
    put32(out, crc);
    put32(out, size);
    put32(out, size);
    put16(out, static_cast<std::uint16_t>(e.path.size()));
    put16(out, 0);  // no extra field
    out += e.path;
    out += e.data;
    // Its central directory record.
    put32(directory, 0x02014b50);
    put16(directory, kMadeByUnix);
    put16(directory, kVersion);
    put16(directory, kUtf8Names);
    put16(directory, 0);
    put16(directory, kDosTime);
    put16(directory, kDosDate);
    put32(directory, crc);
    put32(directory, size);
    put32(directory, size);
    put16(directory, static_cast<std::uint16_t>(e.path.size()));
    put16(directory, 0);  // extra
    put16(directory, 0);  // comment
    put16(directory, 0);  // disk
    put16(directory, 0);  // internal attributes
    const std::uint32_t mode = 0100000u | (e.executable ? 0755u : 0644u);  // a regular file
    put32(directory, mode << 16);
    put32(directory, static_cast<std::uint32_t>(offset));
    directory += e.path;
  }
  if (out.size() + directory.size() > kMax) {
    error = "the archive exceeds 4 GiB, the limit of zip without zip64";
    return false;
  }
  const auto directory_offset = static_cast<std::uint32_t>(out.size());
  out += directory;
  put32(out, 0x06054b50);
  put16(out, 0);
  put16(out, 0);
  put16(out, static_cast<std::uint16_t>(entries_.size()));
  put16(out, static_cast<std::uint16_t>(entries_.size()));
  put32(out, static_cast<std::uint32_t>(directory.size()));
  put32(out, directory_offset);
  put16(out, 0);  // no comment
  return true;
}

}  // namespace mbsc::fmu
