// SPDX-License-Identifier: GPL-2.0-or-later
// `mbsc sweep` as a user calls it: the rows a grid and samples make, each row equal to
// `mbsc run` of its values alone, the same table from one thread or two, a killed sweep
// continued to the same table, a failing row kept as data, bad input refused with
// nothing written, and rows of eigenvalues (--eig) against the pendulum's closed form.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>

#include "run_command.hpp"

namespace fs = std::filesystem;
using namespace mbsc_test;

namespace {

const std::string kMbsc = MBSC_BINARY;

/// A pendulum on a rod of length l, the bob tied to the angle by position constraints.
const char* kPendulum =
    "model pend\nparameter l = 1.5, m = 2, g = 9.81\ngravity (0, -g)\n"
    "body b : particle2d { mass m }\nsubsystem arm {\n  coordinate th\n  speed w = th'\n}\n"
    "constraint position { b.x - l*sin(arm.th) = 0; b.y + l*cos(arm.th) = 0 }\n"
    "independent arm.w\ninitial arm.th = 2.5\noutput angle = arm.th\noutput energy\n";

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// A CSV as text cells (the sweep's message column is the only one that may be quoted).
struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::string at(std::size_t r, const std::string& column) const {
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == column) return rows.at(r).at(i);
    FAIL("no column " << column);
    return "";
  }
};

Table read_table(const fs::path& p) {
  Table t;
  std::ifstream in(p);
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::string cell;
    bool quoted = false;
    for (char c : line) {
      if (c == '"') quoted = !quoted;
      else if (c == ',' && !quoted) cells.push_back(cell), cell.clear();
      else cell += c;
    }
    cells.push_back(cell);
    if (t.header.empty()) t.header = cells;
    else t.rows.push_back(cells);
  }
  return t;
}

}  // namespace

TEST_CASE("mbsc sweep: rows from grids and samples, each equal to mbsc run of its values", "[cli][sweep]") {
  const fs::path dir = fresh_dir("sweep");
  write(dir / "pend.mbs", kPendulum);
  const std::string cache = " --cache-dir " + quote((dir / "cache").string());
  const std::string sweep = kMbsc + " sweep " + quote((dir / "pend.mbs").string()) + cache +
                            " --grid l=1:2:0.5 --sample 'arm.th~uniform(0.5,1.5)' -n 2 --seed 7 --t-end 1"
                            " --summary final,final:angle,max:energy_change,mean:b.y";
  auto r = run(sweep + " --threads 2 -o " + quote((dir / "two.csv").string()));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("6 rows on 2 threads") != std::string::npos);
  CHECK(!fs::exists(dir / "two.csv.partial"));
  const Table t = read_table(dir / "two.csv");
  REQUIRE(t.rows.size() == 6);
  CHECK(t.header.front() == "row");
  CHECK(t.header.back() == "message");
  const std::vector<double> grid = {1, 1, 1.5, 1.5, 2, 2};
  std::map<std::string, int> seeds;
  for (std::size_t i = 0; i < 6; ++i) {
    CHECK(t.at(i, "row") == std::to_string(i));
    CHECK(std::stod(t.at(i, "l")) == grid[i]);
    const double th = std::stod(t.at(i, "arm.th"));
    CHECK((th >= 0.5 && th < 1.5));
    CHECK(t.at(i, "status") == "ok");
    CHECK(std::stod(t.at(i, "t_reached")) == 1.0);
    ++seeds[t.at(i, "seed")];
    // The angle's final value is the summary of the output, and |E - E0| stays small.
    CHECK(t.at(i, "final:angle") == t.at(i, "final:arm.th"));
    CHECK(std::stod(t.at(i, "max:energy_change")) < 1e-6);
    CHECK(std::stod(t.at(i, "mean:b.y")) < 0.0);
  }
  CHECK(seeds.size() == 6);  // a seed per row
  // Two rows re-run alone with mbsc run: the same final state, to the last digit.
  for (std::size_t i : {1u, 4u}) {
    const fs::path csv = dir / ("row" + std::to_string(i) + ".csv");
    r = run(kMbsc + " run " + quote((dir / "pend.mbs").string()) + cache + " --t-end 1 --set l=" + t.at(i, "l") +
            " --init arm.th=" + t.at(i, "arm.th") + " -o " + quote(csv.string()));
    REQUIRE(r.exit_code == 0);
    const Table one = read_table(csv);
    for (const char* name : {"arm.th", "arm.w", "b.x", "b.y", "b.u", "b.v"})
      CHECK(one.at(one.rows.size() - 1, name) == t.at(i, std::string("final:") + name));
  }
  // The trajectories: row i's file is the CSV mbsc run writes for its values, byte for byte.
  const fs::path traj = dir / "traj";
  r = run(sweep + " --threads 2 --trajectories " + quote(traj.string()) + " -o " + quote((dir / "with_traj.csv").string()));
  REQUIRE(r.exit_code == 0);
  CHECK(slurp(dir / "with_traj.csv") == slurp(dir / "two.csv"));
  for (std::size_t i = 0; i < 6; ++i) CHECK(fs::exists(traj / ("row_" + std::to_string(i) + ".csv")));
  CHECK(std::distance(fs::directory_iterator(traj), fs::directory_iterator()) == 6);  // no temporaries left
  for (std::size_t i : {1u, 4u}) CHECK(slurp(traj / ("row_" + std::to_string(i) + ".csv")) == slurp(dir / ("row" + std::to_string(i) + ".csv")));
  // Chosen columns, t first.
  r = run(sweep + " --trajectories " + quote((dir / "angles").string()) + " --columns angle -o " +
          quote((dir / "angles.csv").string()));
  REQUIRE(r.exit_code == 0);
  const Table angles = read_table(dir / "angles" / "row_3.csv");
  CHECK(angles.header == std::vector<std::string>{"t", "angle"});
  CHECK(angles.at(angles.rows.size() - 1, "angle") == t.at(3, "final:arm.th"));

  // One thread: the same bytes.
  r = run(sweep + " --threads 1 -o " + quote((dir / "one.csv").string()));
  REQUIRE(r.exit_code == 0);
  CHECK(slurp(dir / "one.csv") == slurp(dir / "two.csv"));

  // Killed after 3 rows (the test hook stops the process as a kill would): the partial
  // table holds them; the same command again continues to the same table.
  const fs::path resumed = dir / "resumed.csv";
  r = run("MBSC_SWEEP_ABORT_AFTER_ROWS=3 " + sweep + " -o " + quote(resumed.string()));
  CHECK(r.exit_code == 3);
  CHECK(!fs::exists(resumed));
  REQUIRE(fs::exists(dir / "resumed.csv.partial"));
  r = run(sweep + " -o " + quote(resumed.string()));
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("continuing the sweep") != std::string::npos);
  CHECK(r.output.find("3 of 6 rows done") != std::string::npos);
  CHECK(r.output.find("(3 from an earlier run)") != std::string::npos);
  CHECK(slurp(resumed) == slurp(dir / "two.csv"));
  CHECK(!fs::exists(dir / "resumed.csv.partial"));
  // A partial table of other options is not continued.
  r = run("MBSC_SWEEP_ABORT_AFTER_ROWS=2 " + sweep + " -o " + quote(resumed.string()));
  CHECK(r.exit_code == 3);
  r = run(sweep + " --rtol 1e-9 -o " + quote(resumed.string()));
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("holds the rows of another sweep") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("mbsc sweep --eig: each row's eigenvalues, as the closed form and mbsc eig give them", "[cli][sweep][eig]") {
  const fs::path dir = fresh_dir("sweep_eig");
  write(dir / "pend.mbs", kPendulum);
  const std::string base = kMbsc + " sweep " + quote((dir / "pend.mbs").string()) + " --cache-dir " +
                           quote((dir / "cache").string()) + " --eig";
  // Hanging (th = 0): +-i sqrt(g/l); upright (th = pi): +-sqrt(g/l), one unstable.
  auto r = run(base + " --grid l=0.5:2:0.5 --grid arm.th=0,3.141592653589793 --threads 2 -o " +
               quote((dir / "eig.csv").string()));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const Table t = read_table(dir / "eig.csv");
  REQUIRE(t.rows.size() == 8);
  CHECK(t.header == std::vector<std::string>{"row", "seed", "l", "arm.th", "max_real", "unstable", "cyclic", "eig1.re",
                                             "eig1.im", "eig2.re", "eig2.im", "status", "message"});
  for (std::size_t i = 0; i < 8; ++i) {
    INFO("row " << i);
    REQUIRE(t.at(i, "status") == "ok");
    const double omega = std::sqrt(9.81 / std::stod(t.at(i, "l")));
    const bool upright = std::stod(t.at(i, "arm.th")) > 1;
    CHECK(std::stoi(t.at(i, "cyclic")) == 0);
    CHECK(std::stoi(t.at(i, "unstable")) == (upright ? 1 : 0));
    const double re1 = std::stod(t.at(i, "eig1.re")), im1 = std::stod(t.at(i, "eig1.im"));
    const double re2 = std::stod(t.at(i, "eig2.re")), im2 = std::stod(t.at(i, "eig2.im"));
    if (upright) {
      CHECK(re1 == Approx(omega).epsilon(1e-9));
      CHECK(re2 == Approx(-omega).epsilon(1e-9));
      CHECK(std::fabs(im1) + std::fabs(im2) < 1e-9);
      CHECK(std::stod(t.at(i, "max_real")) == re1);
    } else {
      CHECK(std::fabs(re1) + std::fabs(re2) < 1e-9 * omega);
      CHECK(std::fabs(im1) == Approx(omega).epsilon(1e-9));
      CHECK(im1 == Approx(-im2).epsilon(1e-12));
    }
  }
  // The same rows as mbsc eig sweeping l (its columns re_k, im_k in rising real part).
  r = run(kMbsc + " eig " + quote((dir / "pend.mbs").string()) + " --cache-dir " + quote((dir / "cache").string()) +
          " --sweep l=0.5:2:0.5 --init arm.th=3.141592653589793 -q -o " + quote((dir / "eig_command.csv").string()));
  REQUIRE(r.exit_code == 0);
  const Table e = read_table(dir / "eig_command.csv");
  REQUIRE(e.rows.size() == 4);
  for (std::size_t k = 0; k < 4; ++k) {
    CHECK(e.at(k, "re_2") == t.at(2 * k + 1, "eig1.re"));
    CHECK(e.at(k, "re_1") == t.at(2 * k + 1, "eig2.re"));
  }
  // A steady motion per row: from near the top, the search finds the upright equilibrium.
  r = run(base + " --grid l=1,2 --init arm.th=3 --find arm.th --steady arm.w -o " + quote((dir / "found.csv").string()));
  REQUIRE(r.exit_code == 0);
  const Table f = read_table(dir / "found.csv");
  REQUIRE(f.rows.size() == 2);
  for (std::size_t i = 0; i < 2; ++i) {
    CHECK(std::stod(f.at(i, "found:arm.th")) == Approx(M_PI).epsilon(1e-10));
    CHECK(f.at(i, "unstable") == "1");
  }
  // Options that belong to runs, or to --eig alone.
  for (const auto& [args, message] : std::vector<std::pair<std::string, std::string>>{
           {" --grid l=1,2 --summary final", "the rows of --eig are eigenvalues, not runs"},
           {" --grid l=1,2 --find arm.th", "--find names 1 unknown(s) and --steady 0 rate(s)"},
           {" --grid l=0,1", "--eig: at the first row"}}) {
    INFO(args);
    r = run(base + args + " -o " + quote((dir / "bad.csv").string()));
    CHECK(r.exit_code == 1);
    CHECK(r.output.find(message) != std::string::npos);
    CHECK(!fs::exists(dir / "bad.csv"));
  }
  r = run(kMbsc + " sweep " + quote((dir / "pend.mbs").string()) + " --grid l=1,2 --keep arm.th -o " +
          quote((dir / "bad.csv").string()));
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("belong to --eig") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("mbsc sweep: a failing row is data; bad input is refused with nothing written", "[cli][sweep][bad]") {
  const fs::path dir = fresh_dir("sweep_bad");
  write(dir / "pend.mbs", kPendulum);
  const std::string base = kMbsc + " sweep " + quote((dir / "pend.mbs").string()) + " --cache-dir " +
                           quote((dir / "cache").string()) + " --t-end 0.5 -o " + quote((dir / "t.csv").string());
  // A rod of length 0 cannot be assembled at the start; the other row runs.
  auto r = run(base + " --grid l=0,1");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("1 failed") != std::string::npos);
  const Table t = read_table(dir / "t.csv");
  REQUIRE(t.rows.size() == 2);
  CHECK(t.at(0, "status") != "ok");
  CHECK(!t.at(0, "message").empty());
  CHECK(t.at(1, "status") == "ok");
  CHECK(t.at(1, "message").empty());
  fs::remove(dir / "t.csv");

  // An initial value over a parameter that is 0 in one row (2.5 / l at l = 0), on two
  // threads: that row fails, and the sweep goes on.
  write(dir / "div.mbs", std::string(kPendulum).replace(std::string(kPendulum).find("arm.th = 2.5"), 12, "arm.th = 2.5/l"));
  r = run(kMbsc + " sweep " + quote((dir / "div.mbs").string()) + " --cache-dir " + quote((dir / "cache").string()) +
          " --t-end 0.5 --threads 2 --grid l=0,1,2 -o " + quote((dir / "div.csv").string()));
  REQUIRE(r.exit_code == 0);
  const Table d = read_table(dir / "div.csv");
  REQUIRE(d.rows.size() == 3);
  CHECK(d.at(0, "status") != "ok");
  CHECK(!d.at(0, "message").empty());
  CHECK(d.at(1, "status") == "ok");
  CHECK(d.at(2, "status") == "ok");

  const std::vector<std::pair<std::string, std::string>> bad = {
      {" --grid mass=1:2:0.5", "'mass' is neither a parameter nor a coordinate or speed of model 'pend'"},
      {" --grid l=2:1:0.5", "TO must not lie below FROM"},
      {" --grid l=1:2:0", "STEP must be a positive number"},
      {" --grid l=1:2:log1", "logN takes a whole number of points"},
      {" --sample 'l~uniform(1,2)'", "--sample needs -n"},
      {" --sample 'l~gauss(1,2)' -n 3", "unknown law 'gauss'"},
      {" --sample 'l~normal(1,-2)' -n 3", "the standard deviation must be above 0"},
      {" --grid l=1,2 --set l=3", "'l' is swept and also given with --set or --init"},
      {" --grid l=1,2 --grid l=3", "'l' is swept twice"},
      {" --grid l=1,2 --summary max:anlge", "no column named 'anlge' (did you mean 'angle'?)"},
      {" --grid l=1,2 --summary median:angle", "unknown item 'median:angle'"},
      {" --grid l=1,2 --summary max", "'max' needs a column"},
      {"", "a sweep needs --grid"},
      {" --grid l=1,2 --input 'u=@f.csv'", "not tables"},
      {" --grid l=1,2 --columns angle", "--columns: the trajectories' columns; give --trajectories DIR too"},
      {" --grid l=1,2 --trajectories tr --columns anlge", "no column named 'anlge' (did you mean 'angle'?)"},
      {" --grid l=1,2 --trajectories " + quote((dir / "pend.mbs").string()), "is not a folder"},
      {" --grid l=1:2:1e-5 --dt-out 1e-5 --trajectories tr", "pass --large-output to write them anyway"},
  };
  for (const auto& [args, message] : bad) {
    INFO(args);
    r = run(base + args);
    INFO(r.output);
    CHECK(r.exit_code == 1);
    CHECK(r.output.find("mbsc: error: ") != std::string::npos);
    CHECK(r.output.find(message) != std::string::npos);
    CHECK(!fs::exists(dir / "t.csv"));
    CHECK(!fs::exists(dir / "t.csv.partial"));
  }
  fs::remove_all(dir);
}
