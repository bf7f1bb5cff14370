// SPDX-License-Identifier: GPL-2.0-or-later
// mbsc print --latex --standalone writes documents that LaTeX compiles: every shipped
// model, every item of --what, run through pdflatex (or lualatex) as a user would, with
// -halt-on-error, and no line of them runs past the margin by more than a few points (an
// "Overfull \hbox" in LaTeX's log). Without a LaTeX on the PATH the check is skipped,
// and says so (ctest reports it as skipped: tests/cli/CMakeLists.txt).
#include <catch2/catch.hpp>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>
#include <sstream>

#include "run_command.hpp"

namespace fs = std::filesystem;
using namespace mbsc_test;

namespace {

const std::string kMbsc = MBSC_BINARY;
const std::string kAll = "rates,A,B,C,S,f,fbar,M,h,eom,invariants";
/// How far a line may run past the margin (LaTeX's "Overfull \hbox"), in points.
constexpr double kOverfullPoints = 20.0;

/// pdflatex, else lualatex, else "".
std::string latex_program() {
  for (const char* p : {"pdflatex", "lualatex"})
    if (run(std::string("command -v ") + p).exit_code == 0) return p;
  return "";
}

std::string read(const fs::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// Writes `tex` into dir/name.tex and compiles it there; the log on failure.
void compile(const std::string& latex, const fs::path& dir, const std::string& name, const std::string& tex) {
  std::ofstream(dir / (name + ".tex")) << tex;
  const auto r = run("cd " + quote(dir.string()) + " && " + latex +
                     " -interaction=nonstopmode -halt-on-error -no-shell-escape " + quote(name + ".tex") + " </dev/null");
  INFO(name << ".tex:\n" << tex << "\n" << latex << " said:\n" << r.output);
  CHECK(r.exit_code == 0);
  CHECK(fs::exists(dir / (name + ".pdf")));
}

std::string fmt_lines(const std::vector<std::string>& lines) {
  std::string out;
  for (const auto& l : lines) out += l + "\n";
  return out;
}

}  // namespace

TEST_CASE("print --standalone compiles with LaTeX for every shipped model and every item, within the margins",
          "[latex]") {
  const std::string latex = latex_program();
  if (latex.empty()) {
    WARN("LaTeX compile check skipped: neither pdflatex nor lualatex is on the PATH "
         "(Debian: apt-get install texlive-latex-base)");
    return;
  }
  std::vector<fs::path> models;
  for (const auto& e : fs::directory_iterator(fs::path(MBSC_SOURCE_DIR) / "models"))
    if (e.path().extension() == ".mbs") models.push_back(e.path());
  models.push_back(fs::path(MBSC_SOURCE_DIR) / "tests" / "data" / "latex" / "symbols.mbs");
  std::sort(models.begin(), models.end());
  REQUIRE(models.size() >= 10);
  const fs::path dir = fresh_dir("latex");
  // Entries far longer than a line: a sum of 2000 terms, and a fraction of one (set as
  // (numerator) / (denominator) to break).
  {
    std::string sum;
    for (int i = 1; i <= 2000; ++i)
      sum += (i > 1 ? " + " : "") + std::to_string(i) + "*b.x^" + std::to_string(i % 40 + 1) + "*b.y^" + std::to_string(i / 40 + 1);
    models.push_back(dir / "long_entries.mbs");
    std::ofstream(models.back()) << "model long_entries\nbody b : particle2d { mass 1 }\nforce b.u : " << sum
                                 << "\nforce b.v : 1/(1 + " << sum << ")\n";
  }
  // The documents: every model with every item, as printed and in closed form (--expand),
  // and each subsystem with constraints of its own (not a reused instance) by itself.
  std::vector<std::pair<std::string, std::string>> documents;  // name, print options
  for (const auto& model : models) {
    const std::string name = model.stem().string(), file = quote(model.string());
    documents.push_back({name, file});
    // The Whipple bicycle's closed forms (--expand) are a 22 MB document: printed and
    // compiled by hand they are fine (pdflatex, 55 s), but in this batch, beside every
    // other document on two cores, their printing outruns the symbolic-work budget.
    if (name != "whipple_bicycle") documents.push_back({name + "_expand", file + " --expand"});
    const auto check = run(kMbsc + " check " + file);
    std::istringstream lines(check.output);
    int k = 0;
    for (std::string line; std::getline(lines, line);) {
      const auto colon = line.find(" [");
      if (line.rfind("    ", 0) != 0 || colon == std::string::npos || line.find(" 0 constraint(s)") != std::string::npos ||
          line.find("constraint(s)") == std::string::npos || line.find("reused") != std::string::npos)
        continue;
      const std::string node = line.substr(line.find_first_not_of(' '), colon - line.find_first_not_of(' '));
      documents.push_back({name + "_node" + std::to_string(++k), file + " --node " + quote(node)});
    }
  }
  REQUIRE(documents.size() > 2 * models.size());
  // Printed and compiled all at once (each LaTeX run is mostly start-up): a line per
  // document that failed. The symbolic-work budget is wall time, and the batch runs some
  // eighty prints at once: on two loaded cores the longest (rolling_disc_incline, 21 s
  // alone) outran the default 300 s and left an empty file. The budget is not what this
  // test checks (tests/cli/robustness_test.cpp does), so the prints get an hour.
  std::string prints = "cd " + quote(dir.string()) + " && { ";
  for (const auto& [name, options] : documents)
    prints += "(" + kMbsc + " print " + options + " --standalone -q --budget 3600 --what " + kAll + " > " + name + ".tex || echo FAILED " +
              name + ".tex) & ";
  auto r = run(prints + "wait; }");
  CHECK(r.output.find("FAILED") == std::string::npos);
  r = run("cd " + quote(dir.string()) + " && for f in *.tex; do (" + latex +
          " -interaction=nonstopmode -halt-on-error -no-shell-escape \"$f\" </dev/null >/dev/null 2>&1 || "
          "echo \"FAILED $f\") & done; wait");
  for (const auto& [name, options] : documents) {
    const std::string tex = read(dir / (name + ".tex")), log = read(dir / (name + ".log"));
    INFO(name << ".tex (print " << options << "):\n" << tex.substr(0, 20000) << "\n" << latex << " said:\n" << log);
    CHECK(tex.rfind("% Written by mbsc", 0) == 0);
    CHECK(tex.find("\\end{document}") != std::string::npos);
    CHECK(r.output.find("FAILED " + name + ".tex") == std::string::npos);
    CHECK(fs::exists(dir / (name + ".pdf")));
    // Nothing runs past the margin: LaTeX's "Overfull \hbox (Xpt too wide)", X at most 20pt.
    std::vector<std::string> overfull;
    std::istringstream lines(log);
    for (std::string line; std::getline(lines, line);) {
      const std::string mark = "Overfull \\hbox (";
      if (line.rfind(mark, 0) != 0) continue;
      if (std::stod(line.substr(mark.size())) > kOverfullPoints) overfull.push_back(line);
    }
    INFO("boxes wider than the text by more than " << kOverfullPoints << "pt:\n" << fmt_lines(overfull));
    CHECK(overfull.empty());
  }
  fs::remove_all(dir);
}

TEST_CASE("print --latex: names as symbols and the latex statements' symbols, in environments", "[cli]") {
  const std::string symbols = std::string(MBSC_SOURCE_DIR) + "/tests/data/latex/symbols.mbs";
  auto r = run(kMbsc + " print " + quote(symbols) + " --latex -q --what " + kAll);
  REQUIRE(r.exit_code == 0);
  // Pasted into a document: environments, no document around them.
  CHECK(r.output.find("\\begin{align*}") != std::string::npos);
  CHECK(r.output.find("\\documentclass") == std::string::npos);
  CHECK(r.output.find("\\varphi_{1}") != std::string::npos);                 // latex link[1].theta "..."
  CHECK(r.output.find("\\dot{\\varphi_{1}}") != std::string::npos);          // its rate
  CHECK(r.output.find("{\\ell^{*}}^{2}") != std::string::npos);              // braced before a power
  CHECK(r.output.find("\\tau_{\\mathrm{motor}}") != std::string::npos);      // an input
  CHECK(r.output.find("\\theta_{\\mathrm{link}_{2}}") != std::string::npos);  // link[2].theta, automatic
  CHECK(r.output.find("\\kappa") != std::string::npos);
  CHECK(r.output.find("\\Theta_{0}") != std::string::npos);
  CHECK(r.output.find("m_{\\mathrm{link}}") != std::string::npos);
  CHECK(r.output.find("mathrm{ell}") == std::string::npos);

  const std::string dp = std::string(MBSC_SOURCE_DIR) + "/models/double_pendulum.mbs";
  r = run(kMbsc + " print " + quote(dp) + " --latex -q --what rates,fbar");
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("\\dot{\\theta}_{1} &= w_{1}") != std::string::npos);
  CHECK(r.output.find("\\dot{w}_{1}") != std::string::npos);  // fbar = -M z' + h reads the rates
  CHECK(r.output.find("\\sin\\left(\\theta_{1}\\right)") != std::string::npos);
  // The model's own names are left only in the comments that label rows and columns.
  std::istringstream lines(r.output);
  for (std::string line; std::getline(lines, line);)
    if (line.find("th1") != std::string::npos || line.find("w2") != std::string::npos) CHECK(line.rfind("% ", 0) == 0);
}

TEST_CASE("print --standalone compiles for a subsystem, and with --stats", "[latex]") {
  const std::string latex = latex_program();
  if (latex.empty()) {
    WARN("LaTeX compile check skipped: neither pdflatex nor lualatex is on the PATH "
         "(Debian: apt-get install texlive-latex-base)");
    return;
  }
  const std::string five_bar = std::string(MBSC_SOURCE_DIR) + "/models/five_bar.mbs";
  auto r = run(kMbsc + " print " + quote(five_bar) + " --standalone -q --node linkage.left");
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("Subsystem \\texttt{linkage.left} of the model \\texttt{five\\_bar}") != std::string::npos);
  const fs::path dir = fresh_dir("latex_node");
  compile(latex, dir, "five_bar_left", r.output);
  const std::string dp = std::string(MBSC_SOURCE_DIR) + "/models/double_pendulum.mbs";
  r = run(kMbsc + " print " + quote(dp) + " --standalone -q --stats");
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("\\begin{verbatim}") != std::string::npos);
  compile(latex, dir, "double_pendulum_stats", r.output);
  fs::remove_all(dir);
}

TEST_CASE("print --latex warns when two names print as one symbol", "[cli]") {
  const fs::path dir = fresh_dir("latex_same");
  const fs::path model = dir / "same.mbs";
  std::ofstream(model) << "model same\nparameter m = 1, g = 9.81\ngravity (0, -g)\n"
                          "body b : particle2d { mass m }\ncoordinate th1, theta1\nspeed w1 = th1', w2 = theta1'\n"
                          "constraint position { b.x = sin(th1) + sin(theta1)\n b.y = -cos(th1) - cos(theta1) }\n";
  auto r = run(kMbsc + " print " + quote(model.string()) + " --latex -q --what M");
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(r.output.find(model.string() + ":5:17: warning: 'th1' and 'theta1' both print as \\theta_{1} in LaTeX") !=
        std::string::npos);
  // A latex statement parts them; plain text has no such question.
  std::ofstream(model, std::ios::app) << "latex theta1 \"\\vartheta_{1}\"\n";
  r = run(kMbsc + " print " + quote(model.string()) + " --latex -q --what M");
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("warning") == std::string::npos);
  CHECK(r.output.find("\\vartheta_{1}") != std::string::npos);
  std::ofstream(model) << "model same\nparameter th1 = 1, theta1 = 2\nbody b : particle2d { mass th1 + theta1 }\n";
  CHECK(run(kMbsc + " print " + quote(model.string()) + " -q --what M").output.find("warning") == std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("print --latex: the method's matrices are bold, apart from a model's own symbol M", "[cli]") {
  const fs::path dir = fresh_dir("latex_bold");
  const fs::path model = dir / "heavy.mbs";
  std::ofstream(model) << "model heavy\nparameter M = 2, h = 1\ngravity (0, -h)\nbody b : particle2d { mass M }\n";
  const auto r = run(kMbsc + " print " + quote(model.string()) + " --latex -q --what M,h,fbar,C");
  INFO(r.output);
  CHECK(r.exit_code == 0);
  // The matrix is \mathbf{M}, its entries read the parameter M; h is the parameter, \mathbf{h} the vector.
  CHECK(r.output.find("\\mathbf{M} = \\begin{pmatrix}\n    M & 0 \\\\") != std::string::npos);
  CHECK(r.output.find("\\mathbf{h} = \\begin{pmatrix}") != std::string::npos);
  CHECK(r.output.find("-M h") != std::string::npos);
  CHECK(r.output.find("\\bar{\\mathbf{f}} = ") != std::string::npos);
  CHECK(r.output.find("\\mathbf{C} = ") != std::string::npos);
}

TEST_CASE("latex statements: every command the allow-list takes compiles in the --standalone preamble", "[latex]") {
  const std::string latex = latex_program();
  if (latex.empty()) {
    WARN("LaTeX compile check skipped: neither pdflatex nor lualatex is on the PATH "
         "(Debian: apt-get install texlive-latex-base)");
    return;
  }
  // Each command of src/parse/latex_text.cpp at least once, in the form a symbol uses it.
  const std::vector<std::string> texts = {
      "\\alpha\\beta\\gamma\\delta\\epsilon\\varepsilon\\zeta\\eta\\theta\\vartheta\\iota\\kappa",
      "\\lambda\\mu\\nu\\xi\\pi\\varpi\\rho\\varrho\\sigma\\varsigma\\tau\\upsilon\\phi\\varphi\\chi\\psi\\omega",
      "\\Gamma\\Delta\\Theta\\Lambda\\Xi\\Pi\\Sigma\\Upsilon\\Phi\\Psi\\Omega",
      "\\varGamma\\varDelta\\varTheta\\varLambda\\varXi\\varPi\\varSigma\\varUpsilon\\varPhi\\varPsi\\varOmega",
      "x^{\\prime}\\ell\\hbar\\imath\\jmath\\partial\\nabla\\infty\\emptyset\\aleph",
      "a\\cdot b\\times c\\ast d\\star e\\circ f\\bullet g^{\\dagger\\ddagger}\\pm\\mp\\perp\\parallel",
      "a\\quad b\\qquad c\\,d\\;e\\:f\\!g\\>h\\ i\\{j\\}\\|\\_\\%\\$\\#\\&",
      "\\mathrm{d}\\mathbf{r}\\mathit{ab}\\mathsf{s}\\mathtt{t}\\mathcal{L}\\boldsymbol{\\omega}\\operatorname{tr}",
      "\\bar{x}\\hat\\theta\\dot{x}\\ddot{x}\\dddot{x}\\tilde{x}\\vec{r}\\breve{x}\\check{x}\\acute{x}\\grave{x}",
      "\\widehat{xy}\\widetilde{xy}\\overline{xy}\\underline{xy}\\text{load 1, max.}",
      "\\left(a\\right)\\left[b\\right]\\left|c\\right.\\left\\{d\\right\\}\\left\\|e\\right/",
      "\\left\\langle f\\right\\rangle\\left\\lvert g\\right\\rvert\\left\\lVert h\\right\\rVert",
      "\\left\\lfloor i\\right\\rfloor\\left\\lceil j\\right\\rceil\\left\\vert k\\right\\Vert",
  };
  // mbsc accepts them (mbsc check on a model that gives each to a parameter) ...
  const fs::path dir = fresh_dir("latex_allowed");
  std::string model = "model allowed\nbody b : particle2d { mass 1 }\n", body;
  for (std::size_t i = 0; i < texts.size(); ++i) {
    model += "parameter p" + std::to_string(i) + " = 1\nlatex p" + std::to_string(i) + " \"" + texts[i] + "\"\n";
    body += "$" + texts[i] + "$\\par\n$\\begin{pmatrix}{" + texts[i] + "}^{2}\\end{pmatrix}$\\par\n";
  }
  std::ofstream(dir / "allowed.mbs") << model;
  const auto r = run(kMbsc + " check " + quote((dir / "allowed.mbs").string()) + " -q");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  // ... and LaTeX compiles each, alone and with a power in a matrix cell.
  compile(latex, dir, "allowed", "\\documentclass{article}\n\\usepackage{amsmath}\n\\begin{document}\n" + body + "\\end{document}\n");
  fs::remove_all(dir);
}

TEST_CASE("latex global.NAME gives a parameter its symbol from inside a body", "[cli]") {
  const fs::path dir = fresh_dir("latex_global");
  // The body has a coordinate x of its own; global.x is the parameter (docs/language.md).
  std::ofstream(dir / "g.mbs") << "model g\nparameter M = 2, x = 3\ngravity (0, -x)\n"
                                  "body b : particle2d {\n  mass M\n  latex global.M \"\\mathcal{M}\"\n"
                                  "  latex global.x \"g_{0}\"\n  latex x \"\\xi\"\n}\n";
  auto r = run(kMbsc + " print " + quote((dir / "g.mbs").string()) + " --latex -q --what M,h");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("\\mathcal{M}") != std::string::npos);
  CHECK(r.output.find("g_{0}") != std::string::npos);
  // Not a parameter, input or t: the error names it.
  std::ofstream(dir / "bad.mbs") << "model bad\nbody b : particle2d {\n  mass 1\n  latex global.x \"\\xi\"\n}\n";
  r = run(kMbsc + " check " + quote((dir / "bad.mbs").string()) + " -q");
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("bad.mbs:4:9: error: unknown name 'global.x' in latex statement") != std::string::npos);
  fs::remove_all(dir);
}
