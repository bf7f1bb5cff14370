// SPDX-License-Identifier: GPL-2.0-or-later
// "did you mean": the edit distance against a hand count, the typo limit, the
// deterministic choice among equally close names, and the suggestions the parser and
// the model builder attach to their "unknown ..." messages.
#include <catch2/catch.hpp>

#include <algorithm>
#include <random>

#include "mbsc/diag/name_suggestions.hpp"
#include "mbsc/model/build.hpp"
#include "mbsc/parse/parse.hpp"

using mbsc::closest_name;
using mbsc::did_you_mean;
using mbsc::edit_distance;

namespace {

/// Every error message of building `text` (parse errors included), in report order.
std::vector<std::string> errors_of(const std::string& text) {
  mbsc::Diagnostics d;
  auto file = mbsc::parse::parse_text(text, "t.mbs", d);
  if (file) mbsc::model::build(*file, d);
  std::vector<std::string> out;
  for (const auto& x : d.all())
    if (x.severity == mbsc::Severity::Error) out.push_back(std::to_string(x.pos.line) + ":" + std::to_string(x.pos.col) + ": " + x.message);
  return out;
}

}  // namespace

TEST_CASE("edit distance counts insertions, deletions, substitutions and neighbour swaps", "[diag][suggest]") {
  CHECK(edit_distance("", "") == 0);
  CHECK(edit_distance("", "abc") == 3);
  CHECK(edit_distance("mass", "mass") == 0);
  CHECK(edit_distance("mas", "mass") == 1);          // insertion
  CHECK(edit_distance("intertia", "inertia") == 1);  // deletion
  CHECK(edit_distance("m4", "m3") == 1);             // substitution
  CHECK(edit_distance("tehta", "theta") == 1);       // swap of neighbours
  CHECK(edit_distance("kitten", "sitting") == 3);    // the textbook pair
  CHECK(edit_distance("abcdef", "badcfe") == 3);     // three swaps
  CHECK(edit_distance("ca", "abc") == 3);            // the restricted form: no edit of a swapped pair
  // Symmetric.
  CHECK(edit_distance("rigid2", "rigid2d") == edit_distance("rigid2d", "rigid2"));
}

TEST_CASE("suggestions: only close names, the first listed among equals, never the name itself", "[diag][suggest]") {
  CHECK(mbsc::typo_distance_limit(1) == 0);
  CHECK(mbsc::typo_distance_limit(2) == 1);
  CHECK(mbsc::typo_distance_limit(4) == 1);
  CHECK(mbsc::typo_distance_limit(8) == 2);
  CHECK(mbsc::typo_distance_limit(12) == 3);
  CHECK(closest_name("m_3", {"m1", "m3", "l3"}) == std::optional<std::string>("m3"));
  CHECK_FALSE(closest_name("z", {"x", "y"}));         // one letter: every letter is one edit away
  CHECK_FALSE(closest_name("stiff", {"mass", "l1"}));  // nothing close
  CHECK_FALSE(closest_name("m3", {"m3"}));
  // m4 is one edit from both m3 and m5: the first listed wins, whatever else is around.
  CHECK(closest_name("m4", {"m3", "m5"}) == std::optional<std::string>("m3"));
  CHECK(closest_name("m4", {"m5", "m3"}) == std::optional<std::string>("m5"));
  // The closer one wins over the earlier one.
  CHECK(closest_name("inertai", {"inertial_x", "inertia"}) == std::optional<std::string>("inertia"));
  CHECK(did_you_mean("lenght", {"length"}) == " (did you mean 'length'?)");
  CHECK(did_you_mean("q", {"length"}).empty());
  CHECK(mbsc::list_names({"a", "b", "c"}) == "a, b and c");
}

TEST_CASE("unknown names suggest a close name in scope, and nothing more goes wrong", "[diag][suggest][model]") {
  const auto errs = errors_of("model m\nparameter m3 = 1, l = 2\nbody b : particle2d { mass m_3 }\n");
  REQUIRE(errs.size() == 1);  // no "body 'b' has no mass" after it
  CHECK(errs[0] == "3:28: unknown name 'm_3' (did you mean 'm3'?)");
  // A body's own variables are in scope inside it: a typo of one is suggested relative.
  const auto inner = errors_of("model m\nbody b : particle2d { mass 1\n output s = tehta }\nbody c : rigid2d { mass 1  inertia 1 }\n");
  REQUIRE(inner.size() == 1);
  CHECK(inner[0] == "3:13: unknown name 'tehta'");  // b has no theta: c's is only reachable as c.theta
  const auto rigid = errors_of("model m\nbody c : rigid2d { mass 1  inertia 1\n output s = tehta }\n");
  REQUIRE(rigid.size() == 1);
  CHECK(rigid[0] == "3:13: unknown name 'tehta' (did you mean 'theta'?)");
  const auto dotted = errors_of("model m\nbody c : rigid2d { mass 1  inertia 1 }\noutput s = c.tehta\n");
  REQUIRE(dotted.size() == 1);
  CHECK(dotted[0] == "3:12: unknown name 'c.tehta' (did you mean 'c.theta'?)");
  const auto func = errors_of("model m\noutput s = sni(t)\n");
  REQUIRE(func.size() == 1);
  CHECK(func[0] == "2:12: unknown function 'sni' (did you mean 'sin'?)");
  const auto variable = errors_of("model m\nbody b : particle2d { mass 1 }\nforce b.uu : 1\n");
  REQUIRE(variable.size() == 1);
  CHECK(variable[0] == "3:7: unknown variable 'b.uu' (did you mean 'b.u'?)");
}

TEST_CASE("an inertia whose value fails is not also missing", "[diag][suggest][model]") {
  const auto errs = errors_of("model m\nparameter J1 = 1\nbody b : rigid2d { mass 1  inertia j1 }\n");
  REQUIRE(errs.size() == 1);
  CHECK(errs[0] == "3:36: unknown name 'j1' (did you mean 'J1'?)");
}

TEST_CASE("a point that failed is not also unknown to the joint that names it", "[diag][suggest][model]") {
  const auto errs = errors_of(
      "model m\nparameter l = 1\nbody b : rigid2d { mass 1  inertia 1  point P (0, -ll) }\n"
      "joint j : revolute ground.origin b.P\n");
  REQUIRE(errs.size() == 1);
  CHECK(errs[0] == "3:52: unknown name 'll' (did you mean 'l'?)");
  // A ground point too.
  const auto ground = errors_of(
      "model m\nground { point A (1, qq) }\nbody b : rigid2d { mass 1  inertia 1  point P (0, 0) }\n"
      "joint j : revolute ground.A b.P\n");
  REQUIRE(ground.size() == 1);
  CHECK(ground[0] == "2:22: unknown name 'qq'");
}

TEST_CASE("an unknown kind lists the kinds and components", "[diag][suggest][model]") {
  const auto errs = errors_of("model m\ncomponent Arm(l) { body b : particle2d { mass l } }\nbody b : rigid2 { mass 1 }\n");
  REQUIRE(errs.size() == 1);
  CHECK(errs[0] == "3:10: subsystem 'b' has unknown kind or component 'rigid2' (did you mean 'rigid2d'?); the leaf kinds "
                   "are particle2d, particle3d, rigid2d, rigid2d_nodal, rigid3d and custom, the components Arm");
  const auto none = errors_of("model m\nbody b : pendulum { mass 1 }\n");
  REQUIRE(none.size() == 1);
  CHECK(none[0].find("unknown kind or component 'pendulum'; the leaf kinds are particle2d,") != std::string::npos);
  CHECK(none[0].find("(no component is defined)") != std::string::npos);
}

TEST_CASE("a misspelt keyword is an unknown statement inside a one-line body too", "[diag][suggest][parse]") {
  const auto own_line = errors_of("model m\nbody b : rigid2d {\n  mass 1\n  intertia 1\n}\n");
  REQUIRE(own_line.size() == 1);
  CHECK(own_line[0] == "4:3: unknown statement 'intertia' (did you mean 'inertia'?)");
  const auto one_line = errors_of("model m\nbody b : rigid2d { mass 1  intertia 1 }\n");
  REQUIRE(one_line.size() == 1);
  CHECK(one_line[0] == "2:28: unknown statement 'intertia' (did you mean 'inertia'?)");
  const auto first = errors_of("model m\nbody b : rigid2d { mas 1  inertia 1 }\n");
  REQUIRE(first.size() == 1);
  CHECK(first[0] == "2:20: unknown statement 'mas' (did you mean 'mass'?)");
  // A name that is no keyword's typo keeps the plain message.
  const auto plain = errors_of("model m\nbody b : rigid2d { mass 1  J 1 }\n");
  REQUIRE(plain.size() == 1);
  CHECK(plain[0] == "2:28: expected end of statement after mass expression, found 'J'");
}

TEST_CASE("suggestions stay cheap for very long names", "[diag][suggest]") {
  // Two names of 200 000 characters that differ at the end: the band keeps it linear.
  const std::string a = std::string(200000, 'a') + "x", b = std::string(200000, 'a') + "y";
  CHECK(closest_name(a, {b}) == std::optional<std::string>(b));
  CHECK_FALSE(closest_name(a, {std::string(200000, 'a') + "pqrs"}));  // four edits
  CHECK(edit_distance("aaaa", "aaaaaaaa") == 4);
}

namespace {
/// The whole optimal-string-alignment table, written plainly: the reference for the
/// banded, early-stopping distance.
std::size_t full_table_distance(const std::string& a, const std::string& b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i)
    for (std::size_t j = 1; j <= b.size(); ++j) {
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}
}  // namespace

TEST_CASE("the banded distance agrees with the whole table, and so does the suggestion", "[diag][suggest]") {
  std::mt19937 rng(7);
  auto word = [&rng] {
    std::string w(rng() % 9, 'a');
    for (auto& c : w) c = static_cast<char>('a' + rng() % 3);  // three letters: many near misses
    return w;
  };
  for (int k = 0; k < 3000; ++k) {
    const std::string a = word(), b = word();
    INFO(a << " / " << b);
    REQUIRE(edit_distance(a, b) == full_table_distance(a, b));
    const bool close = a != b && full_table_distance(a, b) <= mbsc::typo_distance_limit(a.size());
    REQUIRE(closest_name(a, {b}).has_value() == close);
  }
}

TEST_CASE("names: a name without its subsystem, and an indexed name as written", "[names]") {
  const std::vector<std::string> state{"cart.x", "cart.u", "load.theta", "load.u", "x"};
  CHECK(mbsc::did_you_mean("theta", state) == " (did you mean 'load.theta'?)");
  CHECK(mbsc::did_you_mean("u", state) == " (did you mean 'cart.u' or 'load.u'?)");
  CHECK(mbsc::did_you_mean("heta", state).empty());  // a suffix of a name, not of a component
  CHECK(mbsc::did_you_mean("xx", state) == " (did you mean 'x'?)");  // a typo first
  CHECK(mbsc::declared_name("blk[1].x") == "blk_1.x");
  CHECK(mbsc::declared_name("a[2][13].w") == "a_2_13.w");
  CHECK(mbsc::declared_name("m") == "m");
  CHECK(mbsc::declared_name("a[i].x") == "a[i].x");  // not an index: left for the error to show
  CHECK(mbsc::declared_name("[1]") == "[1]");
}
