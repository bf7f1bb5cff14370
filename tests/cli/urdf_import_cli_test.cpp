// SPDX-License-Identifier: GPL-2.0-or-later
// `mbsc import` and .urdf files given to the other commands (docs/urdf.md): positioned
// errors for bad URDF with nothing written, the output file's rules (stdout, -o, no
// silent overwrite), byte-identical imports, the planar joint's carriages, a run of a
// URDF straight from the command line, and the real robots beside the repository
// (../shared/robots: skipped with a message where that folder is absent).
#include <catch2/catch.hpp>
#include <fstream>
#include <regex>
#include <sstream>

#include "run_command.hpp"

namespace fs = std::filesystem;
using namespace mbsc_test;

namespace {

const std::string kMbsc = MBSC_BINARY;
const std::string kData = std::string(MBSC_SOURCE_DIR) + "/tests/data/urdf/";

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// A two-link arm with `joint2` spliced in as its second joint, and `extra` before </robot>.
std::string arm(const std::string& joint2, const std::string& extra = "") {
  return "<robot name=\"arm\">\n"
         "  <link name=\"base\"/>\n"
         "  <joint name=\"j1\" type=\"revolute\">\n"
         "    <parent link=\"base\"/> <child link=\"l1\"/>\n"
         "    <axis xyz=\"0 0 1\"/>\n"
         "  </joint>\n"
         "  <link name=\"l1\">\n"
         "    <inertial> <mass value=\"1\"/> <inertia ixx=\"0.1\" ixy=\"0\" ixz=\"0\" iyy=\"0.1\" iyz=\"0\" izz=\"0.1\"/> </inertial>\n"
         "  </link>\n" +
         joint2 +
         "  <link name=\"l2\">\n"
         "    <inertial> <mass value=\"1\"/> <inertia ixx=\"0.1\" ixy=\"0\" ixz=\"0\" iyy=\"0.1\" iyz=\"0\" izz=\"0.1\"/> </inertial>\n"
         "  </link>\n" +
         extra + "</robot>\n";
}

std::string joint2(const std::string& type, const std::string& body = "<axis xyz=\"0 1 0\"/>") {
  return "  <joint name=\"j2\" type=\"" + type + "\">\n    <parent link=\"l1\"/> <child link=\"l2\"/>\n    " + body +
         "\n  </joint>\n";
}

struct Bad {
  const char* what;
  std::string text;
  const char* position;  // "line:col"
  const char* message;
};

}  // namespace

TEST_CASE("mbsc import: bad URDF is a positioned error, exit 1, nothing written", "[urdf]") {
  const fs::path dir = fresh_dir("urdf_bad");
  const std::vector<Bad> cases = {
      {"XML error", "<robot name=\"r\">\n  <link name=\"a\">\n</robot>\n", "2:3", "not well-formed XML (mismatched element"},
      {"root element", "<model name=\"r\"/>\n", "1:1", "a URDF's root element is <robot>"},
      {"unknown joint type", arm(joint2("hinge")), "10:20", "unknown joint type 'hinge'"},
      {"non-unit axis", arm(joint2("revolute", "<axis xyz=\"0 0 2\"/>")), "12:11", "is not a unit vector (its length is 2)"},
      {"zero axis", arm(joint2("prismatic", "<axis xyz=\"0 0 0\"/>")), "12:11", "is not a unit vector"},
      {"bad numbers", arm(joint2("revolute", "<origin xyz=\"1 2\"/>")), "12:13", "xyz=\"1 2\" should be 3 finite numbers"},
      {"not a number", arm(joint2("revolute", "<origin rpy=\"0 nan 0\"/>")), "12:13", "should be 3 finite numbers"},
      {"unknown link", arm("  <joint name=\"j2\" type=\"fixed\">\n    <parent link=\"l11\"/> <child link=\"l2\"/>\n  </joint>\n"),
       "11:13", "unknown link 'l11' (did you mean 'l1'?)"},
      {"second parent (a loop)",
       arm(joint2("revolute"), "  <joint name=\"j3\" type=\"revolute\">\n    <parent link=\"base\"/> <child link=\"l2\"/>\n  </joint>\n"),
       "18:34", "link 'l2' is already the child of joint 'j2'"},
      {"two roots", arm(joint2("revolute"), "  <link name=\"stray\"/>\n"), "17:3", "are both roots"},
      {"missing inertial on a moving link",
       "<robot name=\"r\">\n  <link name=\"a\"/>\n  <joint name=\"j\" type=\"revolute\">\n    <parent link=\"a\"/> <child "
       "link=\"b\"/>\n  </joint>\n  <link name=\"b\"/>\n</robot>\n",
       "6:3", "link 'b' moves (joint 'j') but has no <inertial>"},
      {"negative mass",
       "<robot name=\"r\">\n  <link name=\"a\"/>\n  <joint name=\"j\" type=\"revolute\">\n    <parent link=\"a\"/> <child "
       "link=\"b\"/>\n  </joint>\n  <link name=\"b\">\n    <inertial> <mass value=\"-1\"/> <inertia ixx=\"1\" ixy=\"0\" "
       "ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/> </inertial>\n  </link>\n</robot>\n",
       "7:22", "the mass must not be negative"},
      {"indefinite inertia",
       "<robot name=\"r\">\n  <link name=\"a\"/>\n  <joint name=\"j\" type=\"revolute\">\n    <parent link=\"a\"/> <child "
       "link=\"b\"/>\n  </joint>\n  <link name=\"b\">\n    <inertial> <mass value=\"1\"/> <inertia ixx=\"1\" ixy=\"2\" "
       "ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/> </inertial>\n  </link>\n</robot>\n",
       "7:5", "the inertia tensor is not positive definite"},
      {"mimic of an unknown joint", arm(joint2("revolute", "<mimic joint=\"j11\"/>")), "12:12",
       "<mimic> follows unknown joint 'j11' (did you mean 'j1'?)"},
      {"mimic of a fixed joint", arm(joint2("fixed", "<mimic joint=\"j1\"/>")), "12:5",
       "<mimic> ties the coordinates of two distinct revolute"},
      {"floating joint under a moving link", arm(joint2("floating")), "10:20", "a floating joint must hang from the fixed root"},
      {"a number beyond the language's range", arm(joint2("revolute", "<origin xyz=\"1e31 0 0\"/>")), "12:13",
       "1e+31 is outside the range of mbsc's numbers"},
      {"a floating base without mass",
       "<robot name=\"r\">\n  <link name=\"w\"/>\n  <joint name=\"f\" type=\"floating\">\n    <parent link=\"w\"/> <child "
       "link=\"b\"/>\n  </joint>\n  <link name=\"b\">\n    <inertial> <mass value=\"0\"/> <inertia ixx=\"0\" ixy=\"0\" "
       "ixz=\"0\" iyy=\"0\" iyz=\"0\" izz=\"0\"/> </inertial>\n  </link>\n</robot>\n",
       "6:3", "is a free body (the floating base, or a floating joint's child) with mass 0"},
  };
  for (const auto& c : cases) {
    SECTION(c.what) {
      const fs::path urdf = dir / "robot.urdf", out = dir / "robot.mbs";
      write(urdf, c.text);
      const auto r = run(kMbsc + " import " + quote(urdf.string()) + " -o " + quote(out.string()));
      INFO(r.output);
      CHECK(r.exit_code == 1);
      CHECK(r.output.find(urdf.string() + ":" + c.position + ": error: ") != std::string::npos);
      CHECK(r.output.find(c.message) != std::string::npos);
      CHECK_FALSE(fs::exists(out));
      // Every other command refuses the file the same way, at the same place.
      const auto check = run(kMbsc + " check " + quote(urdf.string()));
      CHECK(check.exit_code == 1);
      CHECK(check.output.find(urdf.string() + ":" + c.position + ": error: ") != std::string::npos);
    }
  }
  fs::remove_all(dir);
}

TEST_CASE("mbsc import: the output file, byte-identical imports, options", "[urdf]") {
  const fs::path dir = fresh_dir("urdf_out");
  const std::string urdf = quote(kData + "every_joint.urdf");
  const auto to_stdout = run(kMbsc + " import " + urdf);
  REQUIRE(to_stdout.exit_code == 0);
  CHECK(to_stdout.output.find("model every_joint\n") != std::string::npos);
  // What the file holds that the model does not use is listed in the header.
  CHECK(to_stdout.output.find("1 <visual>") != std::string::npos);
  CHECK(to_stdout.output.find("joint <limit>") != std::string::npos);
  CHECK(to_stdout.output.find("friction 0.1 not modelled") != std::string::npos);
  // Damping acts on its joint, the input beside it; the mimic joint is a position row.
  CHECK(to_stdout.output.find("torque tau_shoulder - 0.2*q_shoulder_dot") != std::string::npos);
  CHECK(to_stdout.output.find("force tau_slide - 1.5*q_slide_dot") != std::string::npos);
  CHECK(to_stdout.output.find("mimic_thumb: q_thumb = -0.5*q_finger + 0.1") != std::string::npos);
  // Quarter turns are exact: the elbow's origin rpy (pi/2, 0, pi) as written in the file.
  CHECK(to_stdout.output.find("rpy (pi/2, 0, pi)") != std::string::npos);

  const fs::path out = dir / "robot.mbs";
  auto r = run(kMbsc + " import " + urdf + " -o " + quote(out.string()));
  REQUIRE(r.exit_code == 0);
  const std::string first = slurp(out);
  CHECK(r.output.find("wrote") != std::string::npos);
  // The written model is an ordinary model file.
  CHECK(run(kMbsc + " check " + quote(out.string())).exit_code == 0);
  // An existing file is not replaced without --force (it may hold the user's edits).
  write(out, "# edited\n");
  r = run(kMbsc + " import " + urdf + " -o " + quote(out.string()));
  CHECK(r.exit_code == 1);
  CHECK(r.output.find("give --force") != std::string::npos);
  CHECK(slurp(out) == "# edited\n");
  r = run(kMbsc + " import " + urdf + " -o " + quote(out.string()) + " --force");
  CHECK(r.exit_code == 0);
  CHECK(slurp(out) == first);  // byte-identical from run to run
  CHECK(first + "" == to_stdout.output.substr(0, first.size()));

  // URDF names become identifiers; what reaches a comment is escaped (an attribute may
  // hold a newline, &#10;, which must not start a statement), and a coordinate's rate
  // name is free too (a link named q_j_dot).
  const fs::path odd = dir / "odd.urdf";
  write(odd, "<robot name=\"odd\">\n  <link name=\"base\"/>\n  <joint name=\"j\" type=\"revolute\">\n"
             "    <parent link=\"base\"/> <child link=\"q_j_dot\"/>\n  </joint>\n"
             "  <link name=\"q_j_dot\">\n    <inertial> <mass value=\"1\"/> <inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" "
             "iyz=\"0\" izz=\"1\"/> </inertial>\n  </link>\n"
             "  <joint name=\"k\" type=\"continuous\">\n    <parent link=\"q_j_dot\"/> <child link=\"b&#10;parameter evil = 1 #\"/>\n"
             "  </joint>\n  <link name=\"b&#10;parameter evil = 1 #\">\n    <inertial> <mass value=\"1\"/> <inertia ixx=\"1\" "
             "ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/> </inertial>\n  </link>\n</robot>\n");
  const auto odd_model = run(kMbsc + " import " + quote(odd.string()));
  INFO(odd_model.output);
  REQUIRE(odd_model.exit_code == 0);
  CHECK(odd_model.output.find("\nparameter evil") == std::string::npos);
  CHECK(odd_model.output.find("coordinate q_j_2 ") != std::string::npos);
  CHECK(run(kMbsc + " check " + quote(odd.string())).exit_code == 0);

  // --floating-base frees the root; --no-inputs drops the torques but keeps the damping.
  const auto free_base = run(kMbsc + " import " + urdf + " --floating-base --no-inputs");
  REQUIRE(free_base.exit_code == 0);
  CHECK(free_base.output.find("independent base.u, base.v, base.w, base.wx, base.wy, base.wz, q_shoulder_dot") !=
        std::string::npos);
  CHECK(free_base.output.find("input ") == std::string::npos);
  CHECK(free_base.output.find("torque -0.2*q_shoulder_dot") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("URDF planar joint: two slides and a turn on massless carriages", "[urdf]") {
  const auto r = run(kMbsc + " check " + quote(kData + "planar_base.urdf"));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("model planar_base: 4 degree(s) of freedom") != std::string::npos);
  CHECK(r.output.find("independent speeds: q_glide_a_dot, q_glide_b_dot, q_glide_turn_dot, q_swing_dot") != std::string::npos);
}

TEST_CASE("mbsc run reads a URDF: a free-flying robot keeps its energy", "[run]") {
  const fs::path dir = fresh_dir("urdf_run");
  const auto r = run(kMbsc + " run " + quote(kData + "floating_base.urdf") + " --t-end 1 --rtol 1e-10 -o " +
                     quote((dir / "fb.csv").string()) + " --init q_left_hip_dot=3 --init trunk.wz=2 --init trunk.u=0.5");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  std::smatch m;
  REQUIRE(std::regex_search(r.output, m, std::regex("largest \\|E - E0\\| = ([0-9.e+-]+) \\(E0 = ([0-9.e+-]+)\\)")));
  CHECK(std::stod(m[1]) < 1e-7 * std::abs(std::stod(m[2])));
  fs::remove_all(dir);
}

TEST_CASE("the real robots: import, check, degrees of freedom from the file", "[urdf_robots]") {
  const fs::path robots = fs::path(MBSC_SOURCE_DIR).parent_path() / "shared" / "robots";
  if (!fs::exists(robots / "ur5_robot.urdf")) {
    WARN("skipped: no robot URDFs at " << robots.string() << " (they live beside the repository, not in it)");
    return;
  }
  const fs::path dir = fresh_dir("urdf_robots");
  for (const auto& [name, floating] : std::vector<std::pair<std::string, bool>>{
           {"ur5_robot", false}, {"panda", false}, {"solo12", true}, {"talos_full_v2", true}}) {
    // The expected count from the file itself: moving joints that do not mimic, plus six.
    const std::string text = slurp(robots / (name + ".urdf"));
    int moving = 0, mimic = 0;
    const std::regex joint("<joint[^>]*type=\"(revolute|continuous|prismatic)\""), mimic_tag("<mimic ");
    moving = static_cast<int>(std::distance(std::sregex_iterator(text.begin(), text.end(), joint), std::sregex_iterator()));
    mimic = static_cast<int>(std::distance(std::sregex_iterator(text.begin(), text.end(), mimic_tag), std::sregex_iterator()));
    const int dof = moving - mimic + (floating ? 6 : 0);
    const fs::path out = dir / (name + ".mbs");
    auto r = run(kMbsc + " import " + quote((robots / (name + ".urdf")).string()) + " -o " + quote(out.string()) +
                 (floating ? " --floating-base" : ""));
    INFO(name << ": " << r.output);
    REQUIRE(r.exit_code == 0);
    r = run(kMbsc + " check " + quote(out.string()));
    REQUIRE(r.exit_code == 0);
    CHECK(r.output.find(": " + std::to_string(dof) + " degree(s) of freedom") != std::string::npos);
  }
  fs::remove_all(dir);
}
