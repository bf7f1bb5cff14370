// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// A shipped planar model rebuilt with Simbody's own API, plus the map from mbsc's state
// names (crank.theta, crank.w, slider.x, motor_left.i, ...) to Simbody's state.
//
// Every mechanism is a tree of Pin (rotation about z) and Slider (translation along x)
// mobilizers in the plane z = 0, its loops cut at one joint each and closed by planar
// constraints (pin_constraint below: two PointInPlane rows, exactly the two equations of
// a planar revolute joint). A body's mbsc angle `theta` is its Pin angle plus its
// parent's angle (the mobilizer frames are aligned with the body frames), so the body
// frames are mbsc's body frames: x axis along the bar, points at mbsc's body coordinates.
#include <Simbody.h>

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace simbench {

struct Mechanism {
  SimTK::MultibodySystem system;
  SimTK::SimbodyMatterSubsystem matter{system};
  SimTK::GeneralForceSubsystem forces{system};

  // A rotating body: mbsc angle = q + parent's angle (parent < 0: a child of ground or of
  // a non-rotating body), rate = u + parent's rate.
  struct Angle {
    std::string theta, w;
    SimTK::MobilizedBody body;
    int parent;
  };
  // A translating body: mbsc position = q + offset, speed = u.
  struct Slide {
    std::string x, u;
    SimTK::MobilizedBody body;
    double offset;
  };
  // A state entry that is neither (the five-bar's motor currents, Simbody z variables).
  struct Extra {
    std::string name;
    std::function<double(const SimTK::State&)> get;
    std::function<void(SimTK::State&, double)> set;
  };
  std::vector<Angle> angles;  // parents before children
  std::vector<Slide> slides;
  std::vector<Extra> extras;
  // Other mbsc names of the same quantity (the five-bar's linkage.left.theta is its
  // upper bar's angle): alias -> the name used above.
  std::map<std::string, std::string> aliases;

  // The model's independent coordinates and speeds (mbsc names), in report order.
  std::vector<std::string> independent;
  // Assembly only (assemble.hpp): one disabled ConstantSpeed per independent speed.
  std::vector<std::pair<std::string, SimTK::Constraint::ConstantSpeed>> speed_locks;

  int add_angle(const std::string& stem, SimTK::MobilizedBody body, int parent = -1) {
    angles.push_back({stem + ".theta", stem + ".w", body, parent});
    return static_cast<int>(angles.size()) - 1;
  }
  void add_slide(const std::string& stem, SimTK::MobilizedBody body, double offset) {
    slides.push_back({stem + ".x", stem + ".u", body, offset});
  }

  const std::string& resolve(const std::string& name) const {
    const auto it = aliases.find(name);
    return it == aliases.end() ? name : it->second;
  }
  // Whether `name` is a coordinate / a speed / an extra this mechanism knows.
  bool knows(const std::string& name) const;
  double get(const SimTK::State& s, const std::string& name) const;
  // Sets coordinates, keeping the other bodies' absolute angles (children's q follow).
  void set_positions(SimTK::State& s, const std::map<std::string, double>& values) const;
  // Sets speeds, keeping the other bodies' absolute rates; extras are set here too.
  void set_speeds(SimTK::State& s, const std::map<std::string, double>& values) const;
  // The mobilizer carrying a coordinate or speed (throws for extras / unknown names).
  SimTK::MobilizedBody mobilizer_of(const std::string& name, bool& ground_child) const;
};

// Builds one of the shipped models by its mbsc name; throws std::runtime_error for others.
std::unique_ptr<Mechanism> make_mechanism(const std::string& model);
std::vector<std::string> mechanism_names();

// --- helpers shared by the model files ---------------------------------------------

// Mass properties of a planar body: mass m at (cx, cy) in the body frame, inertia Jc
// about the mass centre for rotations about z (the x, y entries are irrelevant to a
// planar motion and set to Jc so the 3-D inertia is valid).
SimTK::Body::Rigid planar_body(double m, double Jc, double cx = 0.0, double cy = 0.0);

// A planar revolute joint between point pa of body a and point pb of body b (body
// coordinates): two PointInPlane rows, the planes of a through pa normal to its x and y.
void pin_constraint(SimTK::SimbodyMatterSubsystem& matter, SimTK::MobilizedBody& a, SimTK::Vec2 pa,
                    SimTK::MobilizedBody& b, SimTK::Vec2 pb);

// Frame at (x, y) in the plane with the body's orientation (no rotation).
inline SimTK::Transform at(double x, double y) { return SimTK::Transform(SimTK::Vec3(x, y, 0)); }

}  // namespace simbench
