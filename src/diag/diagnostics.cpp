// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/diag/diagnostics.hpp"

namespace mbsc {

void Diagnostics::error(const SourcePos& pos, std::string message) {
  items_.push_back({Severity::Error, pos, std::move(message)});
  ++nerrors_;
}

void Diagnostics::warning(const SourcePos& pos, std::string message) {
  items_.push_back({Severity::Warning, pos, std::move(message)});
}

void Diagnostics::note(const SourcePos& pos, std::string message) {
  items_.push_back({Severity::Note, pos, std::move(message)});
}

std::string to_string(const SourcePos& pos) {
  if (pos.line <= 0) return pos.file.empty() ? std::string("<input>") : pos.file;
  return (pos.file.empty() ? std::string("<input>") : pos.file) + ":" + std::to_string(pos.line) + ":" +
         std::to_string(pos.col);
}

std::string Diagnostics::format() const {
  std::string out;
  for (const auto& d : items_) {
    const char* kind = d.severity == Severity::Error ? "error" : d.severity == Severity::Warning ? "warning" : "note";
    out += to_string(d.pos) + ": " + kind + ": " + d.message + "\n";
  }
  return out;
}

}  // namespace mbsc
