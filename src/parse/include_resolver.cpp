// SPDX-License-Identifier: GPL-2.0-or-later
/// parse_file: reads a model file and splices its top-level includes in place, recursively.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>
#include <utility>

#include "mbsc/parse/parse.hpp"
#include "parser_internal.hpp"

namespace mbsc::parse {

namespace {

namespace fs = std::filesystem;

/// Include chains longer than this are rejected (a guard; cycles are caught earlier).
constexpr std::size_t max_include_depth = 64;

bool read_text(const std::string& path, std::string& text) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) return false;
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream buf;
  buf << in.rdbuf();
  if (in.bad()) return false;
  text = buf.str();
  return true;
}

/// The identity of a file for cycle detection.
fs::path identity(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::weakly_canonical(path, ec);
  if (ec) p = fs::absolute(path, ec).lexically_normal();
  return p;
}

class IncludeResolver {
 public:
  explicit IncludeResolver(Diagnostics& diags) : diags_(diags) {}

  /// Parses `text` (the contents of `path`) and appends its statements to `out`,
  /// each Include statement replaced by the statements of the file it names.
  void expand(const std::string& path, const std::string& text, std::vector<ast::StatementPtr>& out) {
    ast::File file;
    if (!parse_source(text, path, diags_, file)) ok_ = false;
    stack_.push_back(identity(path));
    for (const auto& st : file.statements) {
      if (st->kind != ast::Statement::Kind::Include) {
        out.push_back(st);
        continue;
      }
      const std::string target = (fs::path(path).parent_path() / st->name).string();
      if (is_open(identity(target))) {
        report(st->pos, "cyclic include of '" + st->name + "'");
        continue;
      }
      if (stack_.size() >= max_include_depth) {
        report(st->pos, "includes nested too deeply (more than " + std::to_string(max_include_depth) + ")");
        continue;
      }
      std::string included;
      if (!read_text(target, included)) {
        report(st->pos, "cannot open file '" + target + "'");
        continue;
      }
      expand(target, included, out);
    }
    stack_.pop_back();
  }

  bool ok() const { return ok_; }

 private:
  bool is_open(const fs::path& p) const {
    for (const auto& q : stack_)
      if (q == p) return true;
    return false;
  }

  void report(const SourcePos& pos, std::string message) {
    diags_.error(pos, std::move(message));
    ok_ = false;
  }

  Diagnostics& diags_;
  std::vector<fs::path> stack_;  // files being expanded, outermost first
  bool ok_ = true;
};

}  // namespace

std::optional<ast::File> parse_file(const std::string& path, Diagnostics& diags) {
  std::string text;
  if (!read_text(path, text)) {
    diags.error(SourcePos{path, 0, 0}, "cannot open file '" + path + "'");
    return std::nullopt;
  }
  IncludeResolver resolver(diags);
  ast::File file;
  file.path = path;
  resolver.expand(path, text, file.statements);
  if (!resolver.ok()) return std::nullopt;
  return file;
}

}  // namespace mbsc::parse
