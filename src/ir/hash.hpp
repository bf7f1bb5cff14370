// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Run-independent 64-bit hashing for the canonical DAG (private to src/ir). Never uses
/// std::hash, pointer values or GiNaC hashes, which may differ between runs.
#include <cstdint>
#include <string>

namespace mbsc::ir {

/// splitmix64 finaliser: a bijective avalanche mix.
inline std::uint64_t mix64(std::uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  x ^= x >> 31;
  return x;
}

/// Order-dependent combination of a running hash with one more value.
inline std::uint64_t hash_combine(std::uint64_t h, std::uint64_t v) {
  return mix64(h ^ (v + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2)));
}

/// FNV-1a over the bytes of a string (computed once per distinct text, not per node).
inline std::uint64_t hash_text(const std::string& s) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (unsigned char c : s) {
    h ^= c;
    h *= 0x100000001b3ULL;
  }
  return mix64(h);
}

}  // namespace mbsc::ir
