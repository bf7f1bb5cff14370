// SPDX-License-Identifier: GPL-2.0-or-later
#include "mbsc/diag/diagnostics.hpp"

#include <cstdio>

namespace mbsc {

void Diagnostics::add(Severity severity, const SourcePos& pos, std::string message) {
  if (items_.size() >= kMaxShown) {
    ++dropped_;
    return;
  }
  items_.push_back({severity, pos, std::move(message)});
}

void Diagnostics::error(const SourcePos& pos, std::string message) {
  add(Severity::Error, pos, std::move(message));
  ++nerrors_;
}

void Diagnostics::warning(const SourcePos& pos, std::string message) {
  // A stage that runs more than once (a derivation per independent set) warns once.
  for (const auto& d : items_)
    if (d.severity == Severity::Warning && d.message == message && d.pos.line == pos.line && d.pos.col == pos.col &&
        d.pos.file == pos.file)
      return;
  add(Severity::Warning, pos, std::move(message));
}

void Diagnostics::note(const SourcePos& pos, std::string message) { add(Severity::Note, pos, std::move(message)); }

std::string to_string(const SourcePos& pos) {
  if (pos.line <= 0) return pos.file.empty() ? std::string("<input>") : pos.file;
  return (pos.file.empty() ? std::string("<input>") : pos.file) + ":" + std::to_string(pos.line) + ":" +
         std::to_string(pos.col);
}

std::string without_error_prefix(const std::string& message) {
  const std::string prefix = "mbsc: error: ";
  return message.rfind(prefix, 0) == 0 ? message.substr(prefix.size()) : message;
}

std::string printable(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  auto escape = [&out](unsigned char c) {
    char buf[8];
    std::snprintf(buf, sizeof buf, "\\x%02X", static_cast<unsigned>(c));
    out += buf;
  };
  for (std::size_t i = 0; i < text.size();) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c < 0x80) {
      if (c < 0x20 || c == 0x7F) escape(c);
      else out += static_cast<char>(c);
      ++i;
      continue;
    }
    // A well-formed UTF-8 sequence of 2-4 bytes (no overlong forms, no surrogates).
    std::size_t len = c >= 0xF0 ? 4 : c >= 0xE0 ? 3 : c >= 0xC2 ? 2 : 0;
    if (c > 0xF4) len = 0;
    bool ok = len > 0 && i + len <= text.size();
    for (std::size_t k = 1; ok && k < len; ++k) ok = (static_cast<unsigned char>(text[i + k]) & 0xC0) == 0x80;
    if (ok && len == 3) {
      const unsigned char c1 = static_cast<unsigned char>(text[i + 1]);
      ok = !(c == 0xE0 && c1 < 0xA0) && !(c == 0xED && c1 >= 0xA0);
    }
    if (ok && len == 4) {
      const unsigned char c1 = static_cast<unsigned char>(text[i + 1]);
      ok = !(c == 0xF0 && c1 < 0x90) && !(c == 0xF4 && c1 >= 0x90);
    }
    // C1 controls U+0080..U+009F (0xC2 0x80..0x9F) act on some terminals.
    if (ok && len == 2 && c == 0xC2 && static_cast<unsigned char>(text[i + 1]) < 0xA0) ok = false;
    if (!ok) {
      escape(c);
      ++i;
      continue;
    }
    out.append(text, i, len);
    i += len;
  }
  return out;
}

std::string Diagnostics::format() const {
  std::string out;
  for (const auto& d : items_) {
    const char* kind = d.severity == Severity::Error ? "error" : d.severity == Severity::Warning ? "warning" : "note";
    out += printable(to_string(d.pos)) + ": " + kind + ": " + printable(d.message) + "\n";
  }
  if (dropped_ > 0) out += "mbsc: " + std::to_string(dropped_) + " more diagnostic(s) not shown\n";
  return out;
}

}  // namespace mbsc
