// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Source positions and the diagnostics every stage reports into.
#include <cstddef>
#include <string>
#include <vector>

namespace mbsc {

/// A position in a model file: 1-based line and column.
struct SourcePos {
  std::string file;
  int line = 0;
  int col = 0;
};

enum class Severity { Error, Warning, Note };

struct Diagnostic {
  Severity severity = Severity::Error;
  SourcePos pos;
  std::string message;
};

/// Collected errors and warnings; stages report here instead of throwing. Only the first
/// kMaxShown are kept (a file of garbage has one error per line); the rest are counted.
class Diagnostics {
 public:
  static constexpr std::size_t kMaxShown = 100;
  void error(const SourcePos& pos, std::string message);
  void warning(const SourcePos& pos, std::string message);
  void note(const SourcePos& pos, std::string message);
  bool has_errors() const { return nerrors_ > 0; }
  int error_count() const { return nerrors_; }
  const std::vector<Diagnostic>& all() const { return items_; }
  /// "file:line:col: error: message" lines, in report order, control characters and
  /// invalid UTF-8 escaped (printable()).
  std::string format() const;

 private:
  void add(Severity severity, const SourcePos& pos, std::string message);
  std::vector<Diagnostic> items_;
  int nerrors_ = 0;
  std::size_t dropped_ = 0;  // diagnostics past kMaxShown
};

/// `text` safe to print on a terminal: valid UTF-8 is kept, except control characters
/// (C0, DEL, C1), which become \xNN like any byte that is not valid UTF-8.
std::string printable(const std::string& text);

/// "file:line:col" (or "file" when line is 0).
std::string to_string(const SourcePos& pos);

/// A message without the "mbsc: error: " that begins a whole error line, for a caller
/// that puts it into a sentence or a table cell of its own.
std::string without_error_prefix(const std::string& message);

}  // namespace mbsc
