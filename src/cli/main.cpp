// SPDX-License-Identifier: GPL-2.0-or-later
// mbsc command line: flag parsing only; the work is in mbsc::driver.
#include <CLI/CLI.hpp>
#include <iostream>

#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/driver/commands.hpp"

// Sanitizer builds: LeakSanitizer reports a one-time 26-byte allocation that libcln
// makes at start-up and never frees. That library's, and nothing else, is suppressed
// here as in tests/lsan.supp, so that a sanitized mbsc also works inside a build
// (mbsc_add_model runs it) where LSAN_OPTIONS is not set.
#if defined(__SANITIZE_ADDRESS__)
#define MBSC_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define MBSC_ASAN 1
#endif
#endif
#ifdef MBSC_ASAN
extern "C" const char* __lsan_default_suppressions();
extern "C" const char* __lsan_default_suppressions() { return "leak:libcln.so\n"; }
#endif

namespace {

/// Splits "a,b c" lists given to --outputs / --what.
std::vector<std::string> split_list(const std::vector<std::string>& items) {
  std::vector<std::string> out;
  for (const auto& item : items) {
    std::string cur;
    for (char c : item + ",") {
      if (c == ',' || c == ' ') {
        if (!cur.empty()) out.push_back(cur);
        cur.clear();
      } else {
        cur += c;
      }
    }
  }
  return out;
}

bool add_freezes(const std::vector<std::string>& items, std::map<std::string, double>& frozen) {
  for (const auto& f : items) {
    std::string name;
    double value = 0;
    if (!mbsc::driver::parse_assignment(f, name, value)) {
      std::cerr << "mbsc: error: --freeze expects name=value with a finite number, got '" << mbsc::printable(f) << "'\n";
      return false;
    }
    frozen[name] = value;
  }
  return true;
}

/// --budget, --max-memory, --quiet and --progress, on every subcommand.
struct WorkFlags {
  double seconds = mbsc::driver::WorkBudget{}.seconds;
  std::size_t memory_mib = mbsc::driver::WorkBudget{}.memory_mib;
  bool quiet = false, progress = false;

  void add_to(CLI::App* cmd) {
    cmd->add_option("--budget", seconds, "time budget of the symbolic work, in seconds")
        ->check(CLI::Range(0.001, 1e7))
        ->capture_default_str();
    cmd->add_option("--max-memory", memory_mib, "memory budget of the symbolic work, in MiB")
        ->check(CLI::Range(std::size_t{16}, std::size_t{1} << 30))
        ->capture_default_str();
    cmd->add_flag("-q,--quiet", quiet, "no progress line; generate prints nothing on success (errors and warnings still)");
    cmd->add_flag("--progress", progress, "show progress even when stderr is not a terminal");
  }
  mbsc::driver::WorkArgs args() const {
    mbsc::driver::WorkArgs w;
    w.budget.seconds = seconds;
    w.budget.memory_mib = memory_mib;
    w.quiet = quiet;
    w.progress = quiet ? mbsc::driver::ProgressMode::Never
                       : progress ? mbsc::driver::ProgressMode::Always : mbsc::driver::ProgressMode::Auto;
    return w;
  }
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"mbsc: symbolic equations of motion for multibody systems, as standalone C++"};
  app.set_version_flag("--version", std::string("mbsc ") + MBSC_VERSION);
  app.require_subcommand(1);

  mbsc::driver::CheckArgs check;
  auto* c = app.add_subcommand("check", "validate a model; print its tree, variables, ranks and degrees of freedom");
  c->add_option("model", check.model, "model file (.mbs)")->required();
  std::vector<std::string> check_freeze;
  c->add_option("--freeze", check_freeze, "check with a parameter folded in, as generate --freeze would: name=value");
  WorkFlags check_work;
  check_work.add_to(c);

  mbsc::driver::PrintArgs print;
  std::vector<std::string> what, print_freeze, print_outputs;
  auto* p = app.add_subcommand("print", "print the matrices and equations of a subsystem (text or LaTeX)");
  p->add_option("model", print.model, "model file (.mbs)")->required();
  p->add_option("--node", print.node, "subsystem (dotted name); default: the whole model");
  p->add_option("--what", what,
                "comma-separated: M h eom invariants rates A B C S f fbar (default: M h eom invariants, then rates B C fbar)");
  p->add_flag("--latex", print.latex, "LaTeX for a document that loads amsmath, instead of plain text");
  p->add_flag("--standalone", print.standalone, "a complete LaTeX document (pdflatex or lualatex); implies --latex");
  p->add_flag("--expand", print.expand,
              "closed form: substitute the named intermediates (e_, r_) and the small numeric solves (X_)");
  p->add_flag("--stats", print.stats, "operation counts of the generated functions");
  p->add_option("--freeze", print_freeze, "fold a parameter into the equations: name=value (repeatable)");
  p->add_option("--outputs", print_outputs, "with --stats: only these functions");
  std::string print_state = "full";
  p->add_option("--state", print_state, "with --stats: full or minimal (as for generate)")
      ->check(CLI::IsMember({"full", "minimal"}))
      ->default_val("full");
  WorkFlags print_work;
  print_work.add_to(p);

  mbsc::driver::GenerateArgs gen;
  std::vector<std::string> outputs, freeze;
  auto* g = app.add_subcommand("generate", "write standalone C++ for a model into OUT/<model>/");
  g->add_option("model", gen.model, "model file (.mbs)")->required();
  g->add_option("-o,--out", gen.out_dir, "output folder (default: generated)")->default_val("generated");
  g->add_option("--outputs", outputs,
                "only these functions (comma-separated): rhs mass_matrix forcing inverse_dynamics position_constraints "
                "velocity_constraints constraint_jacobian position_jacobian energy outputs full_state multipliers "
                "reaction_forces");
  std::string formulation = "complement";
  g->add_option("--formulation", formulation,
                "complement: the modular method, reduced to the independent speeds; multipliers: all speeds with "
                "Lagrange multipliers and Baumgarte stabilization (gains alpha, beta at the end of p[])")
      ->check(CLI::IsMember({"complement", "multipliers"}))
      ->default_val("complement");
  std::string state = "full";
  g->add_option("--state", state,
                "full: x = (all coordinates, all speeds); minimal: x = (coordinates not given explicitly by a "
                "position constraint, independent speeds), the rest rebuilt in every function")
      ->check(CLI::IsMember({"full", "minimal"}))
      ->default_val("full");
  g->add_option("--name", gen.name, "C++ namespace and file stem (default: the model's name)");
  g->add_option("--freeze", freeze, "fold a parameter into the code: name=value (repeatable)");
  g->add_flag("--python", gen.python,
              "also write OUT/<name>/<name>.py: a ctypes + numpy module over the extern \"C\" functions (README, \"Using it\")");
  g->add_flag("--force", gen.force,
              "write into OUT/<name> even when mbsc did not write that folder (only its own files are replaced)");
  g->add_option("--depfile", gen.depfile,
                "also write a make-style depfile: the generated files depend on the model and every file it includes")
      ->type_name("FILE");
  WorkFlags gen_work;
  gen_work.add_to(g);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 1;
  }
  auto dispatch = [&]() -> int {
    if (*c) {
      check.work = check_work.args();
      if (!add_freezes(check_freeze, check.frozen)) return 1;
      return mbsc::driver::run_check(check, std::cout, std::cerr);
    }
    if (*p) {
      print.work = print_work.args();
      print.what = split_list(what);
      print.what_given = p->count("--what") > 0;
      for (const auto& o : split_list(print_outputs)) print.functions.insert(o);
      print.minimal_state = print_state == "minimal";
      if (!add_freezes(print_freeze, print.frozen)) return 1;
      return mbsc::driver::run_print(print, std::cout, std::cerr);
    }
    for (const auto& o : split_list(outputs)) gen.functions.insert(o);
    gen.minimal_state = state == "minimal";
    gen.multipliers = formulation == "multipliers";
    gen.work = gen_work.args();
    if (!add_freezes(freeze, gen.frozen)) return 1;
    return mbsc::driver::run_generate(gen, std::cout, std::cerr);
  };
  // The stages report what a user did wrong as diagnostics; what escapes them is ours.
  try {
    return dispatch();
  } catch (const std::bad_alloc&) {
    std::cerr << "mbsc: error: out of memory (lower the model's size, or raise --max-memory if the machine has more)\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "mbsc: internal error: " << mbsc::printable(e.what()) << "\n";
    return 2;
  }
}
