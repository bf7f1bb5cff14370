// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// A zip archive (the container of an FMU) written in memory: every entry stored
/// uncompressed with its CRC-32, in the order added, with a fixed time stamp
/// (1980-01-01 00:00) so that the same entries give the same bytes. Plain zip (no zip64):
/// up to 65 535 entries and 4 GiB in all, which an error reports.
#include <cstdint>
#include <string>
#include <vector>

namespace mbsc::fmu {

/// CRC-32 (ISO-HDLC, the polynomial of zip and gzip) of `data`.
std::uint32_t crc32(const std::string& data);

class ZipArchive {
 public:
  /// `path` uses '/' and names a file (folders are implied); `executable` marks it 0755.
  void add(const std::string& path, std::string data, bool executable = false);
  /// The archive's bytes; false with `error` when it would exceed plain zip's limits.
  bool bytes(std::string& out, std::string& error) const;

 private:
  struct Entry {
    std::string path, data;
    bool executable;
  };
  std::vector<Entry> entries_;
};

}  // namespace mbsc::fmu
