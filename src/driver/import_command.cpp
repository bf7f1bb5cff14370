// SPDX-License-Identifier: GPL-2.0-or-later
// mbsc import: reads a URDF, writes the model text. The text is read back through the
// model front end before anything is written, so an import that succeeds gives a model
// mbsc accepts; the output is written all or nothing and an existing file is replaced
// only with --force (it may hold the user's edits).
#include <filesystem>

#include <fmt/format.h>

#include "mbsc/diag/limits.hpp"
#include "mbsc/driver/import_command.hpp"
#include "mbsc/driver/staged_file.hpp"
#include "mbsc/model/build.hpp"
#include "mbsc/parse/parse.hpp"
#include "mbsc/parse/source_file.hpp"

namespace mbsc::driver {

int run_import(const ImportArgs& a, std::ostream& out, std::ostream& err) {
  Diagnostics diags;
  std::string text, why;
  if (!parse::read_source_file(a.urdf, text, why, limits::kMaxFileBytes)) {
    diags.error(SourcePos{a.urdf, 0, 0}, "cannot read file '" + a.urdf + "': " + why);
    err << diags.format();
    return 1;
  }
  const auto model = import::urdf_to_model(a.urdf, text, a.options, diags);
  if (!model) {
    err << diags.format();
    return 1;
  }
  // The written model must read back: a failure here is mbsc's, and says so.
  const std::string label = a.output.empty() || a.output == "-" ? a.urdf + " (imported)" : a.output;
  Diagnostics back;
  auto file = parse::parse_text(*model, label, back);
  std::optional<model::Model> m;
  if (file) m = model::build(*file, back);
  if (!m || back.has_errors()) {
    err << back.format();
    err << fmt::format("mbsc: error: the model imported from '{}' does not read back (a bug in mbsc import; please "
                       "report it with the URDF); nothing written\n",
                       a.urdf);
    return 1;
  }
  err << diags.format();  // warnings, if any
  if (a.output.empty() || a.output == "-") {
    out << *model;
    return 0;
  }
  std::error_code ec;
  if (!a.force && std::filesystem::exists(std::filesystem::symlink_status(a.output, ec))) {
    err << fmt::format("mbsc: error: '{}' exists; it may hold your edits, so import does not replace it (give --force "
                       "to replace it, or another -o)\n",
                       printable(a.output));
    return 1;
  }
  StagedFile staged;
  std::string error;
  if (!staged.stage(a.output, *model, "-o", error) || !staged.commit(error)) {
    err << "mbsc: error: " << error << "\n";
    return 1;
  }
  std::size_t bodies = 0;
  for (const auto& n : m->nodes) bodies += n.kind == model::LeafKind::Rigid3d;
  err << fmt::format("wrote {}: model {}, {} bodies, {} coordinates\n", printable(a.output), m->name, bodies, m->coords.size());
  return 0;
}

}  // namespace mbsc::driver
