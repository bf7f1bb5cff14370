// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// Source positions and the diagnostics every stage reports into.
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

/// Collected errors and warnings; stages report here instead of throwing.
class Diagnostics {
 public:
  void error(const SourcePos& pos, std::string message);
  void warning(const SourcePos& pos, std::string message);
  void note(const SourcePos& pos, std::string message);
  bool has_errors() const { return nerrors_ > 0; }
  int error_count() const { return nerrors_; }
  const std::vector<Diagnostic>& all() const { return items_; }
  /// "file:line:col: error: message" lines, in report order.
  std::string format() const;

 private:
  std::vector<Diagnostic> items_;
  int nerrors_ = 0;
};

/// "file:line:col" (or "file" when line is 0).
std::string to_string(const SourcePos& pos);

}  // namespace mbsc
