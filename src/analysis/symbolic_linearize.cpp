// SPDX-License-Identifier: GPL-2.0-or-later
// mbsc linearize --symbolic: the model derived again (its Taylor coefficients as GiNaC
// expressions, driver::linear_parts_spec), the reference made symbolic
// (symbolic_reference), the elimination (symbolic_linear_model), the check against the
// numeric model, and the text (include/mbsc/analysis/symbolic_linearize.hpp).
#include "mbsc/analysis/symbolic_linearize.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>

#include "mbsc/analysis/symbolic_linear_model.hpp"
#include "mbsc/diag/activity.hpp"
#include "mbsc/diag/diagnostics.hpp"
#include "mbsc/driver/linear_parts.hpp"
#include "mbsc/driver/pipeline.hpp"
#include "mbsc/driver/work_monitor.hpp"
#include "mbsc/print/canonical_text.hpp"
#include "mbsc/print/latex_layout.hpp"
#include "mbsc/print/latex_names.hpp"
#include "mbsc/sym/eom.hpp"
#include "mbsc/sym/kkt_system.hpp"
#include "mbsc/sym/tidy.hpp"
#include "mbsc/run/json_text.hpp"
#include "mbsc/run/second_order_form.hpp"

namespace mbsc::analysis {

using run::json_string;

namespace {

using GiNaC::ex;

// An entry as shown: numerator over denominator, kept apart (GiNaC would rewrite
// num * den^-1 with the sign of den's first term in its own, run-dependent term order).
struct Shown {
  ex num, den = 1;
  bool is_zero() const { return num.is_zero(); }
};

// Entries for people: a number that is not a small fraction becomes a decimal of `digits`
// significant digits (a symbol named by that text, so the canonical printer sets it as
// written); `decimals` collects their LaTeX.
class Display {
 public:
  explicit Display(int digits) : digits_(digits) {}
  Shown operator()(const ex& e) {
    const ex f = GiNaC::normal(e);
    const ex nd = f.numer_denom();
    if (GiNaC::is_a<GiNaC::numeric>(nd.op(1))) return {numbers(f.expand())};
    // The denominator scaled so that its largest coefficient is 1 (among equal ones, that
    // of the term first in printed order: GiNaC's own term order changes between runs,
    // and with it the sign normal() gives a fraction).
    ex num = nd.op(0).expand(), den = nd.op(1).expand();
    GiNaC::numeric largest(0);
    std::string first;
    for (std::size_t i = 0; i < (GiNaC::is_a<GiNaC::add>(den) ? den.nops() : 1); ++i) {
      const ex term = GiNaC::is_a<GiNaC::add>(den) ? den.op(i) : den;
      GiNaC::numeric k(1);
      ex monomial = term;
      if (GiNaC::is_a<GiNaC::mul>(term)) {
        for (std::size_t j = 0; j < term.nops(); ++j)
          if (GiNaC::is_a<GiNaC::numeric>(term.op(j))) k = GiNaC::ex_to<GiNaC::numeric>(term.op(j)), monomial = term / term.op(j);
      } else if (GiNaC::is_a<GiNaC::numeric>(term)) {
        k = GiNaC::ex_to<GiNaC::numeric>(term), monomial = 1;
      }
      const std::string text = print::canonical_text(monomial, false);
      if (GiNaC::abs(k) > GiNaC::abs(largest) || (GiNaC::abs(k) == GiNaC::abs(largest) && text < first)) largest = k, first = text;
    }
    if (!largest.is_zero()) num = (num / largest).expand(), den = (den / largest).expand();
    return {numbers(num), numbers(den)};
  }
  std::map<std::string, std::string> decimals;

 private:
  ex numbers(const ex& e) {
    if (GiNaC::is_a<GiNaC::numeric>(e)) {
      const auto& n = GiNaC::ex_to<GiNaC::numeric>(e);
      auto small = [](const GiNaC::numeric& r) { return r.is_rational() && GiNaC::abs(r.numer()) < 100000 && r.denom() <= 1000; };
      if (small(n)) return e;
      const double v = n.to_double();
      const std::string text = fmt::format("{:.{}g}", std::fabs(v), digits_);
      // A number that is a small fraction to the digits shown (1.0000000000000002) is it.
      if (const ex r = exact_number(std::stod(text)); small(GiNaC::ex_to<GiNaC::numeric>(r))) return v < 0 ? -r : r;
      if (!decimals.count(text)) {
        std::string latex = text;
        if (const auto k = text.find('e'); k != std::string::npos)
          latex = text.substr(0, k) + " \\cdot 10^{" + std::to_string(std::stoi(text.substr(k + 1))) + "}";
        decimals[text] = latex;
      }
      const ex s = symbol_named(text);
      return v < 0 ? -s : s;
    }
    struct Each : GiNaC::map_function {
      Display* d;
      explicit Each(Display* d_) : d(d_) {}
      ex operator()(const ex& x) override { return d->numbers(x); }
    } each(this);
    return e.map(each);
  }
  ex symbol_named(const std::string& text) {
    const auto it = symbols_.find(text);
    if (it != symbols_.end()) return it->second;
    return symbols_.emplace(text, GiNaC::symbol(text)).first->second;
  }
  std::map<std::string, ex> symbols_;
  int digits_;
};

}  // namespace

bool symbolic_linear_text(const run::LinearizeArgs& a, const model::Model& m, const runtime::ModelTable& T,
                          const run::ReferenceRequest& req, const NumericLinearModel& numeric, const ReferenceAt& reference_at,
                          std::string& text, std::string& error, int& exit_code) {
  exit_code = 1;
  // The full layout is the model's coordinates, then its speeds (linear_parts' columns).
  for (int i = 0; i < T.nx; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    const std::string& name = k < m.coords.size() ? m.coords[k].name : m.speeds.at(k - m.coords.size()).name;
    if (name != T.state_names[i]) {
      error = "internal: the compiled state is not the model's coordinates and speeds";
      exit_code = 2;
      return false;
    }
  }
  std::vector<int> coords;
  for (const auto& name : a.second_order) {
    const int i = runtime::ModelTable::find(T.state_names, T.nx, name.c_str());
    if (i < 0 || i >= T.nq) {
      error = fmt::format("--second-order: '{}' is not a coordinate of the model", name);
      return false;
    }
    coords.push_back(i);
  }
  Diagnostics diags;
  SymbolicReference sref;
  SymbolicLinearModel lin;
  bool ok = false;
  GiNaC::ex v, g;  // --speed and --gravity, when they are symbols
  {
    driver::WorkMonitor monitor(a.work.budget, a.work.progress);
    try {
      const std::optional<sym::Eom> eom = sym::derive(m, sym::Options{}, diags);
      if (eom) {
        // Kinematic names (named body rotations) written out: everything below is
        // differentiated by the coordinates or evaluated at the reference.
        const GiNaC::exmap names = model::kinematic_name_values(m);
        auto fin = [&](const ex& e) {
          return sym::tidy(driver::finalize(m, *eom, names.empty() ? e : e.subs(names, GiNaC::subs_options::no_pattern)));
        };
        // Speeds that follow the symbols through the velocity constraints (a wheel's spin
        // from the forward speed): the constraints solved for them.
        const SpeedSolver solve_speeds = [&](const std::vector<int>& speeds, GiNaC::exmap& at, std::string& why) {
          const sym::KktSystem sys = sym::kkt_system(m);
          const unsigned nr = static_cast<unsigned>(sys.velocity.size()), k = static_cast<unsigned>(speeds.size());
          GiNaC::matrix J(nr, k), R(nr, 1), X;
          GiNaC::exmap none;
          for (int i : speeds) none[m.speeds.at(static_cast<std::size_t>(i - T.nq)).sym] = 0;
          for (unsigned r = 0; r < nr; ++r) {
            const ex e = fold_constants(fin(sys.velocity[r]).subs(at));
            for (unsigned j = 0; j < k; ++j) J(r, j) = e.diff(m.speeds.at(static_cast<std::size_t>(speeds[j] - T.nq)).sym);
            R(r, 0) = -e.subs(none);
          }
          if (!solve_overdetermined(J, R, sref.nominal, X, why)) {
            std::vector<std::string> which;
            for (int i : speeds) which.push_back(T.state_names[i]);
            why = fmt::format("--symbolic: the reference speeds {} change with the symbols, and the velocity constraints do not "
                              "determine them ({}): give them with --init",
                              fmt::join(which, ", "), why);
            return false;
          }
          for (unsigned j = 0; j < k; ++j) at[m.speeds.at(static_cast<std::size_t>(speeds[j] - T.nq)).sym] = X(j, 0);
          return true;
        };
        if (symbolic_reference(m, T, req, a.symbolic, *numeric.ref, reference_at, solve_speeds, sref, error)) {
          for (const auto& s : sref.symbols) {
            if (s.get_name() == a.speed) v = s;
            if (s.get_name() == a.gravity) g = s;
          }
          if (!a.speed.empty() && (v.is_zero() || g.is_zero())) {
            error = fmt::format("--speed {} --gravity {} with --symbolic: name both in --symbolic too", a.speed, a.gravity);
          } else {
            const ir::FunctionSpec parts = driver::linear_parts_spec(m, fin, {});
            SymbolicLinearInput in;
            in.parts = parts.outputs;
            for (const auto& b : parts.third_bindings) in.w.push_back(b.sym);
            in.nq = T.nq_full, in.nu = T.nu_full, in.nc = T.nc, in.nin = T.nin;
            in.np = T.nposc + static_cast<int>(driver::unit_quaternion_coords(m).size());
            in.at = sref.at, in.nominal = sref.nominal, in.sel = numeric.sel, in.coords = coords;
            for (const auto& probe : sref.moved) in.elsewhere.push_back(probe.at);
            ok = symbolic_linear_model(in, lin, error);
            if (!ok && error.rfind("internal:", 0) == 0) exit_code = 2;
            if (!ok) error = fmt::format("--symbolic: model {}: {}", m.name, error);
          }
        }
      }
    } catch (const BudgetExceeded& b) {
      error = b.message + " (leave fewer names symbolic)";
    }
    monitor.stop();
  }
  if (diags.has_errors()) {
    error = diags.format();
    return false;
  }
  if (!ok) return false;

  // The symbolic model is the numeric one at the nominal values and with each symbol
  // moved (the reference recomputed there): A, B, and M, C, K of the second-order form.
  const int ns = static_cast<int>(numeric.sel.size());
  auto differs = [&](const GiNaC::matrix& S, const std::vector<double>& N, const GiNaC::exmap& at, double& scale) {
    double worst = 0.0;
    for (double x : N) scale = std::max(scale, std::fabs(x));
    for (unsigned i = 0; i < S.rows(); ++i)
      for (unsigned j = 0; j < S.cols(); ++j)
        worst = std::max(worst, std::fabs(nominal_value(S(i, j), at) - N[static_cast<std::size_t>(i * S.cols() + j)]));
    return worst;
  };
  auto check = [&](const GiNaC::matrix& A, const GiNaC::matrix& B, const std::vector<double>& An, const std::vector<double>& Bn,
                   const GiNaC::exmap& at, const std::string& where) {
    double scale = 0.0;
    const double worst = std::max(differs(A, An, at, scale), differs(B, Bn, at, scale));
    if (worst <= 1e-7 * scale || worst == 0.0) return true;
    error = fmt::format("internal: the symbolic linear model differs from the numeric one by {:.3g} (of {:.3g}) {}", worst, scale,
                        where);
    exit_code = 2;
    return false;
  };
  if (!check(lin.A, lin.B, *numeric.A, *numeric.B, sref.nominal, "at the nominal values")) return false;
  for (const auto& probe : sref.moved) {
    std::vector<double> An, Bn;
    if (!numeric.at_moved(probe.ref, An, Bn, error)) {
      error = fmt::format("--symbolic {}: the numeric model at {} = {} (the check of the symbolic one): {}", probe.name, probe.name,
                          probe.value, error);
      return false;
    }
    if (!check(lin.A, lin.B, An, Bn, probe.at, fmt::format("at {} = {}", probe.name, probe.value))) return false;
  }
  if (!coords.empty()) {
    run::SecondOrderForm f;
    std::string why;
    if (run::second_order_form(*numeric.lin, T.nq, coords, f, why)) {
      double scale = 0.0;
      const double worst = std::max({differs(lin.M, f.M, sref.nominal, scale), differs(lin.C, f.C, sref.nominal, scale),
                                     differs(lin.K, f.K, sref.nominal, scale)});
      if (!(worst <= 1e-7 * scale || worst == 0.0)) {
        error = fmt::format("internal: the symbolic second-order form differs from the numeric one by {:.3g} (of {:.3g})", worst,
                            scale);
        exit_code = 2;
        return false;
      }
    }
  }

  // ---- the text ----
  const auto full = runtime::ModelTable::names_of(T.state_names, T.nx);
  const auto inputs = runtime::ModelTable::names_of(T.input_names, T.nin);
  std::vector<std::string> names, symbols;
  for (int i : numeric.sel) names.push_back(full[static_cast<std::size_t>(i)]);
  for (const auto& s : sref.symbols) symbols.push_back(s.get_name());
  // Text and LaTeX for reading, JSON for reading back: every digit of a double.
  Display display(a.format == "json" ? 17 : 12);
  auto cells = [&](const GiNaC::matrix& M) {
    std::vector<std::vector<Shown>> out(M.rows());
    for (unsigned i = 0; i < M.rows(); ++i)
      for (unsigned j = 0; j < M.cols(); ++j) out[i].push_back(display(M(i, j)));
    return out;
  };
  const auto Ad = cells(lin.A), Bd = cells(lin.B);
  // The second-order form and its split M q'' + v C1 q' + (g K0 + v^2 K2) q = T, each
  // part free of v and g and the remainder exactly zero, else no split.
  std::vector<std::pair<std::string, GiNaC::matrix>> form;
  std::string split_note;
  if (!coords.empty()) {
    form = {{"M", lin.M}, {"C", lin.C}, {"K", lin.K}};
    if (!v.is_zero()) {
      const unsigned k = lin.M.rows();
      GiNaC::matrix C1(k, k), K0(k, k), K2(k, k);
      bool exact = true;
      for (unsigned i = 0; i < k; ++i)
        for (unsigned j = 0; j < k; ++j) {
          const ex c = GiNaC::normal(lin.C(i, j)), kk = GiNaC::normal(lin.K(i, j));
          exact = exact && !c.denom().has(v) && !c.denom().has(g) && !kk.denom().has(v) && !kk.denom().has(g) &&
                  !lin.M(i, j).has(v) && !lin.M(i, j).has(g);
          if (!exact) break;
          const ex ce = c.expand(), ke = kk.expand();
          C1(i, j) = GiNaC::normal(ce.coeff(v, 1)), K0(i, j) = GiNaC::normal(ke.coeff(g, 1)), K2(i, j) = GiNaC::normal(ke.coeff(v, 2));
          const ex rest = GiNaC::normal(ce - v * C1(i, j)) + GiNaC::normal(ke - g * K0(i, j) - v * v * K2(i, j));
          exact = exact && rest.is_zero();
          for (const ex& part : {C1(i, j), K0(i, j), K2(i, j)}) exact = exact && !part.has(v) && !part.has(g);
        }
      if (exact) form.insert(form.end(), {{"C1", C1}, {"K0", K0}, {"K2", K2}});
      split_note = exact ? fmt::format("M q'' + {} C1 q' + ({} K0 + {}^2 K2) q = T exactly", a.speed, a.gravity, a.speed)
                         : fmt::format("the form is not M q'' + {} C1 q' + ({} K0 + {}^2 K2) q = T with parts free of {} and {}",
                                       a.speed, a.gravity, a.speed, a.speed, a.gravity);
    }
  }
  std::vector<std::pair<std::string, std::vector<std::vector<Shown>>>> formd;
  for (const auto& [label, M] : form) formd.push_back({label, cells(M)});
  std::vector<Shown> refd;
  for (const auto& e : sref.state) refd.push_back(display(e));
  std::map<std::string, std::string> latex_names = m.latex_symbols;
  for (const auto& [name, latex] : display.decimals) latex_names[name] = latex;
  const print::LatexSymbolScope scope(latex_names);
  const bool latex = a.format == "latex";
  auto str = [&](const Shown& e) {
    const std::string n = print::canonical_text(e.num, latex);
    if (e.den.is_equal(ex(1))) return n;
    const std::string d = print::canonical_text(e.den, latex);
    if (latex) {
      // -\frac{g}{r}, not \frac{-g}{r}, for a numerator of one term.
      if (!GiNaC::is_a<GiNaC::add>(e.num) && !n.empty() && n[0] == '-') return "-\\frac{" + n.substr(1) + "}{" + d + "}";
      return "\\frac{" + n + "}{" + d + "}";
    }
    const bool wrap_n = GiNaC::is_a<GiNaC::add>(e.num), wrap_d = GiNaC::is_a<GiNaC::add>(e.den) || GiNaC::is_a<GiNaC::mul>(e.den);
    return (wrap_n ? "(" + n + ")" : n) + "/" + (wrap_d ? "(" + d + ")" : d);
  };
  constexpr std::size_t kLongest = 20000;  // characters of one entry: beyond, not readable
  for (const auto* block : {&Ad, &Bd})
    for (const auto& row : *block)
      for (const auto& e : row)
        if (str(e).size() > kLongest) {
          error = fmt::format("--symbolic: an entry of the linear model of {} is longer than {} characters: leave fewer names "
                              "symbolic", m.name, kLongest);
          return false;
        }
  std::string out;
  if (a.format == "json") {
    out = "{\n  \"model\": " + json_string(m.name) + ",\n  \"symbols\": [";
    for (std::size_t i = 0; i < symbols.size(); ++i) out += (i ? ", " : "") + json_string(symbols[i]);
    out += "],\n  \"reference\": {";
    for (std::size_t i = 0; i < full.size(); ++i) out += (i ? ", " : "") + json_string(full[i]) + ": " + json_string(str(refd[i]));
    out += "},\n  \"state\": [";
    for (std::size_t i = 0; i < names.size(); ++i) out += (i ? ", " : "") + json_string(names[i]);
    out += "],\n  \"inputs\": [";
    for (std::size_t i = 0; i < inputs.size(); ++i) out += (i ? ", " : "") + json_string(inputs[i]);
    out += "]";
    for (const auto& [label, block] : {std::pair{"A", &Ad}, std::pair{"B", &Bd}}) {
      out += fmt::format(",\n  \"{}\": [", label);
      for (std::size_t i = 0; i < block->size(); ++i) {
        out += i ? ",\n    [" : "\n    [";
        for (std::size_t j = 0; j < (*block)[i].size(); ++j) out += (j ? ", " : "") + json_string(str((*block)[i][j]));
        out += "]";
      }
      out += block->empty() ? "]" : "\n  ]";
    }
    if (!formd.empty()) {
      out += ",\n  \"second_order\": {\n  \"coordinates\": [";
      for (std::size_t i = 0; i < a.second_order.size(); ++i) out += (i ? ", " : "") + json_string(a.second_order[i]);
      out += "]";
      for (const auto& [label, block] : formd) {
        out += fmt::format(",\n  \"{}\": [", label);
        for (std::size_t i = 0; i < block.size(); ++i) {
          out += i ? ",\n    [" : "\n    [";
          for (std::size_t j = 0; j < block[i].size(); ++j) out += (j ? ", " : "") + json_string(str(block[i][j]));
          out += "]";
        }
        out += "\n  ]";
      }
      out += fmt::format(",\n  \"coupling\": {:.17g}", lin.coupling);
      if (!split_note.empty()) out += ",\n  \"split\": " + json_string(split_note);
      out += "}";
    }
    out += fmt::format(",\n  \"smallest_pivot\": {:.17g}", lin.smallest_pivot);
    out += "\n}\n";
  } else if (latex) {
    std::vector<print::LatexEquation> refs;
    for (std::size_t i = 0; i < full.size(); ++i)
      refs.push_back({print::latex_symbol(full[i], latex_names), str(refd[i]), ""});
    out = fmt::format("% linear model of {} about t = {}, symbols {}: d/dt dx = A dx + B du, x = ({})\n", m.name, a.t,
                      fmt::join(symbols, ", "), fmt::join(names, ", "));
    out += print::latex_equations("the reference", refs);
    if (lin.smallest_pivot < 1e-6)
      out += fmt::format("% a pivot of the elimination is {:.2g} of its matrix at the nominal values: the expressions hold near them\n",
                         lin.smallest_pivot);
    auto strings = [&](const std::vector<std::vector<Shown>>& block) {
      std::vector<std::vector<std::string>> s;
      for (const auto& row : block) {
        s.emplace_back();
        for (const auto& e : row) s.back().push_back(str(e));
      }
      return s;
    };
    out += print::latex_matrix("A", names, names, strings(Ad), latex_names);
    if (T.nin > 0) out += print::latex_matrix("B", names, inputs, strings(Bd), latex_names);
    if (!formd.empty()) out += fmt::format("% second-order form M q'' + C q' + K q = T, q = ({}){}\n", fmt::join(a.second_order, ", "),
                                           split_note.empty() ? "" : "; " + split_note);
    for (const auto& [label, block] : formd)
      out += print::latex_matrix(label, a.second_order, a.second_order, strings(block), latex_names);
  } else {
    out = fmt::format("linear model of {} about t = {} ({} state, {} components), symbols: {}\n", m.name, a.t,
                      a.state == "full" ? "full" : "minimal", ns, fmt::join(symbols, ", "));
    out += "reference:\n";
    for (std::size_t i = 0; i < full.size(); ++i) out += fmt::format("  {} = {}\n", full[i], str(refd[i]));
    auto entries = [&](const char* label, const std::vector<std::vector<Shown>>& block, const std::vector<std::string>& cols) {
      std::string s = fmt::format("{} (nonzero entries; row: the rate of that component):\n", label);
      bool any = false;
      for (std::size_t i = 0; i < block.size(); ++i)
        for (std::size_t j = 0; j < block[i].size(); ++j)
          if (!block[i][j].is_zero()) s += fmt::format("  {}[{}, {}] = {}\n", label[0], names[i], cols[j], str(block[i][j])), any = true;
      return any ? s : fmt::format("{}: 0\n", label);
    };
    out += entries("A = d(x')/dx", Ad, names);
    if (T.nin > 0) out += entries("B = d(x')/du", Bd, inputs);
    if (!formd.empty()) {
      out += fmt::format("second-order form M q'' + C q' + K q = T, q = ({}):\n", fmt::join(a.second_order, ", "));
      for (const auto& [label, block] : formd) {
        out += label + ":\n";
        for (std::size_t i = 0; i < block.size(); ++i)
          for (std::size_t j = 0; j < block[i].size(); ++j)
            out += fmt::format("  {}[{}, {}] = {}\n", label, a.second_order[i], a.second_order[j], str(block[i][j]));
      }
      out += fmt::format("coupling to the rest of the state: {:.3g} (relative, at the nominal values)\n", lin.coupling);
      if (!split_note.empty()) out += split_note + "\n";
    }
    if (lin.smallest_pivot < 1e-6)
      out += fmt::format("note: a pivot of the elimination is {:.2g} of its matrix at the nominal values: the expressions hold "
                         "near them\n", lin.smallest_pivot);
  }
  text = out;
  return true;
}

}  // namespace mbsc::analysis
