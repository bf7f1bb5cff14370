// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// SHA-256 (FIPS 180-4), for the compile cache: an entry's key and the content of its
/// shared object are recorded by this hash and checked before the object is loaded.
#include <cstddef>
#include <cstdint>
#include <string>

namespace mbsc::run {

class Sha256 {
 public:
  Sha256();
  void update(const void* data, std::size_t size);
  void update(const std::string& text) { update(text.data(), text.size()); }
  /// The digest as 64 lowercase hex digits; the object is spent afterwards.
  std::string hex();

 private:
  void block(const unsigned char* p);
  std::uint32_t h_[8];
  unsigned char buffer_[64];
  std::size_t used_ = 0;
  std::uint64_t bytes_ = 0;
};

/// The hex digest of `text`.
std::string sha256_hex(const std::string& text);

}  // namespace mbsc::run
