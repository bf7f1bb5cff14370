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
  IncludeResolver(Diagnostics& diags, const std::map<std::string, double>& overrides)
      : diags_(diags), overrides_(overrides) {}

  /// The parameters loop bounds and indices used, over every file read.
  const std::map<std::string, double>& structural() const { return structural_; }

  /// Parses `text` (the contents of `path`) and appends its statements to `out`,
  /// each Include statement replaced by the statements of the file it names.
  void expand(const std::string& path, const std::string& text, std::vector<ast::StatementPtr>& out) {
    ast::File file;
    if (!parse_source(text, path, diags_, file, overrides_)) ok_ = false;
    structural_.insert(file.structural.begin(), file.structural.end());
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
  const std::map<std::string, double>& overrides_;
  std::map<std::string, double> structural_;  // loop parameters of every file
  std::vector<fs::path> stack_;  // files being expanded, outermost first
  bool ok_ = true;
};

}  // namespace

std::optional<ast::File> parse_file(const std::string& path, Diagnostics& diags,
                                    const std::map<std::string, double>& overrides) {
  std::string text;
  if (!read_text(path, text)) {
    diags.error(SourcePos{path, 0, 0}, "cannot open file '" + path + "'");
    return std::nullopt;
  }
  IncludeResolver resolver(diags, overrides);
  ast::File file;
  file.path = path;
  resolver.expand(path, text, file.statements);
  if (!resolver.ok()) return std::nullopt;
  file.structural = resolver.structural();
  return file;
}

}  // namespace mbsc::parse
