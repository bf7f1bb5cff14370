// SPDX-License-Identifier: GPL-2.0-or-later
/// parse_file: reads a model file and splices its top-level includes in place, recursively.
#include <filesystem>
#include <set>
#include <system_error>
#include <utility>

#include "mbsc/diag/activity.hpp"
#include "mbsc/diag/limits.hpp"
#include "mbsc/import/urdf_import.hpp"
#include "mbsc/parse/parse.hpp"
#include "mbsc/parse/source_file.hpp"
#include "parser_internal.hpp"

namespace mbsc::parse {

namespace {

namespace fs = std::filesystem;

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

  /// Every file read, once each, in the order first read (ast::File::sources).
  const std::vector<std::string>& sources() const { return sources_; }

  /// Parses `text` (the contents of `path`) and appends its statements to `out`,
  /// each Include statement replaced by the statements of the file it names.
  void expand(const std::string& path, const std::string& text, std::vector<ast::StatementPtr>& out) {
    ast::File file;
    if (!parse_source(text, path, diags_, file, overrides_)) ok_ = false;
    structural_.insert(file.structural.begin(), file.structural.end());
    total_tokens_ += file.token_count;
    stack_.push_back(identity(path));
    if (seen_.insert(stack_.back()).second) sources_.push_back(path);
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
      if (stack_.size() >= limits::kMaxIncludeDepth) {
        report(st->pos, "includes nested too deeply (more than " + std::to_string(limits::kMaxIncludeDepth) + ")");
        continue;
      }
      // Budgets over the whole model: a file may include another several times, and
      // chains of such files multiply (2^40 splices from 41 small files).
      if (budget_exhausted_) continue;
      if (++splices_ > limits::kMaxSplices) {
        report(st->pos, "more than " + std::to_string(limits::kMaxSplices) +
                            " includes spliced in all (do files include each other several times?)");
        budget_exhausted_ = true;
        continue;
      }
      if (total_tokens_ > limits::kMaxTotalTokens) {
        report(st->pos, "the model and its includes expand to more than " +
                            std::to_string(limits::kMaxTotalTokens >> 20) + " Mi tokens in all");
        budget_exhausted_ = true;
        continue;
      }
      checkpoint("reading", "file '" + st->name + "'", st->pos, splices_, 0);
      std::string included, why;
      if (!read_source_file(target, included, why, limits::kMaxFileBytes)) {
        report(st->pos, "cannot read file '" + target + "': " + why);
        continue;
      }
      if (!count_text(included.size(), st->pos)) continue;
      expand(target, included, out);
    }
    stack_.pop_back();
  }

  bool ok() const { return ok_; }

  /// Adds `bytes` to the text read for this model; false (reported) past the limit.
  bool count_text(std::size_t bytes, const SourcePos& pos) {
    total_bytes_ += bytes;
    if (total_bytes_ <= limits::kMaxTotalBytes) return true;
    report(pos, "the model and its includes exceed " + std::to_string(limits::kMaxTotalBytes >> 20) +
                    " MiB of text in all");
    budget_exhausted_ = true;
    return false;
  }

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
  std::set<fs::path> seen_;       // identities of the files in sources_
  std::vector<std::string> sources_;
  std::size_t splices_ = 0;      // include statements expanded so far
  std::size_t total_bytes_ = 0;  // text read so far
  std::size_t total_tokens_ = 0;  // tokens after loop expansion so far
  bool budget_exhausted_ = false;
  bool ok_ = true;
};

}  // namespace

std::optional<ast::File> parse_file(const std::string& path, Diagnostics& diags,
                                    const std::map<std::string, double>& overrides) {
  std::string text, why;
  if (!read_source_file(path, text, why, limits::kMaxFileBytes)) {
    diags.error(SourcePos{path, 0, 0}, "cannot read file '" + path + "': " + why);
    return std::nullopt;
  }
  if (import::is_urdf_path(path)) {
    // A robot description: read as the model `mbsc import` writes. Positions in that text
    // are labelled "ROBOT.urdf (imported)": the text `mbsc import ROBOT.urdf` prints.
    auto model = import::urdf_to_model(path, text, import::UrdfImportOptions{}, diags);
    if (!model) return std::nullopt;
    ast::File file;
    if (!parse_source(*model, path + " (imported)", diags, file, overrides)) return std::nullopt;
    file.path = path;
    file.sources = {path};
    file.main_source = std::move(*model);
    return file;
  }
  IncludeResolver resolver(diags, overrides);
  resolver.count_text(text.size(), SourcePos{path, 0, 0});
  ast::File file;
  file.path = path;
  resolver.expand(path, text, file.statements);
  if (!resolver.ok()) return std::nullopt;
  file.structural = resolver.structural();
  file.sources = resolver.sources();
  file.main_source = std::move(text);
  return file;
}

}  // namespace mbsc::parse
