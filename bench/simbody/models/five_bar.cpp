// SPDX-License-Identifier: GPL-2.0-or-later
// models/five_bar.mbs in Simbody: two arms (upper bar on a ground pivot, lower bar pinned
// at its tip), the payload a point mass at the left lower bar's tip, the loop closed
// where the right lower bar's tip meets it (two rows). Each base pivot is driven through
// a gear (motor rate = eta * arm rate) by a DC motor:
//   motor:   Im w' = k i - bm w            (w = eta * dtheta)
//   circuit: Lm i' = v - Rm i - kappa w    (v = 0 here)
// The rotor's inertia appears at the arm as Im eta^2 (added to the upper bar), its
// torque as eta (k i - bm eta dtheta); the two currents are Simbody z variables with
// i' from the circuit equation. Viscous damping -bU dtheta at each base pivot, gravity.
#include "../mechanism.hpp"

namespace simbench {

using namespace SimTK;

namespace {

struct MotorData {
  double k = 0.05, kappa = 0.05, Im = 1e-5, bm = 1e-6, Lm = 1e-3, Rm = 1.0, eta = 20, bU = 0.01;
};

// The two motors and the pivot damping, as one force element owning the currents.
class Motors : public Force::Custom::Implementation {
 public:
  Motors(const GeneralForceSubsystem& forces, MobilizedBody left, MobilizedBody right, MotorData d)
      : forces_(forces), arm_{left, right}, d_(d) {}
  void realizeTopology(State& s) const override { z_ = forces_.allocateZ(s, Vector(2, 0.0)); }
  double current(const State& s, int k) const { return forces_.getZ(s)[z_ + k]; }
  void set_current(State& s, int k, double i) const { forces_.updZ(s)[z_ + k] = i; }
  void calcForce(const State& s, Vector_<SpatialVec>&, Vector_<Vec3>&, Vector& mobility) const override {
    for (int k = 0; k < 2; ++k) {
      const double dtheta = arm_[k].getOneU(s, MobilizerUIndex(0));
      const double torque = d_.eta * (d_.k * current(s, k) - d_.bm * d_.eta * dtheta) - d_.bU * dtheta;
      arm_[k].applyOneMobilityForce(s, MobilizerUIndex(0), torque, mobility);
    }
  }
  Real calcPotentialEnergy(const State&) const override { return 0; }
  void realizeAcceleration(const State& s) const override {
    for (int k = 0; k < 2; ++k) {
      const double w = d_.eta * arm_[k].getOneU(s, MobilizerUIndex(0));
      forces_.updZDot(s)[z_ + k] = (-d_.Rm * current(s, k) - d_.kappa * w) / d_.Lm;
    }
  }

 private:
  const GeneralForceSubsystem& forces_;
  MobilizedBody arm_[2];
  MotorData d_;
  mutable ZIndex z_;
};

}  // namespace

// parameter s = 0.1, aUL = aUR = 0.25, aBL = aBR = 0.35, mUL = mUR = 0.2, mBL = mBR = 0.25,
//           bU = 0.01, mL = 0.1, k = kappa = 0.05, Im = 1e-5, bm = 1e-6, Lm = 1e-3,
//           Rm = 1.0, eta = 20, g = 9.81; v_left = v_right = 0
void build_five_bar(Mechanism& m) {
  const double s = 0.1, aU = 0.25, aB = 0.35, mU = 0.2, mB = 0.25, mL = 0.1, g = 9.81;
  const MotorData d;
  Force::UniformGravity(m.forces, m.matter, Vec3(0, -g, 0));
  const double Jrotor = d.Im * d.eta * d.eta;
  // Upper bars: frame at the base pivot, mass centre at mid-length.
  MobilizedBody::Pin upL(m.matter.Ground(), at(-s, 0), planar_body(mU, mU * aU * aU / 12 + Jrotor, aU / 2), at(0, 0));
  MobilizedBody::Pin upR(m.matter.Ground(), at(s, 0), planar_body(mU, mU * aU * aU / 12 + Jrotor, aU / 2), at(0, 0));
  // Left lower bar with the payload at its tip (a particle at a pin moves with the tip).
  const double mLow = mB + mL, cx = (mB * aB / 2 + mL * aB) / mLow;
  const double Jc = mB * aB * aB / 12 + mB * (aB / 2 - cx) * (aB / 2 - cx) + mL * (aB - cx) * (aB - cx);
  MobilizedBody::Pin loL(upL, at(aU, 0), planar_body(mLow, Jc, cx), at(0, 0));
  MobilizedBody::Pin loR(upR, at(aU, 0), planar_body(mB, mB * aB * aB / 12, aB / 2), at(0, 0));
  pin_constraint(m.matter, loL, Vec2(aB, 0), loR, Vec2(aB, 0));
  auto* motors = new Motors(m.forces, upL, upR, d);
  Force::Custom(m.forces, motors);  // the subsystem owns the implementation
  const int il = m.add_angle("linkage.left.upper", upL);
  m.add_angle("linkage.left.lower", loL, il);
  const int ir = m.add_angle("linkage.right.upper", upR);
  m.add_angle("linkage.right.lower", loR, ir);
  for (const char* side : {"left", "right"}) {
    const std::string arm = std::string("linkage.") + side;
    m.aliases[arm + ".theta"] = arm + ".upper.theta";
    m.aliases[arm + ".dtheta"] = arm + ".upper.w";
    m.aliases[arm + ".phi"] = arm + ".lower.theta";
    m.aliases[arm + ".dphi"] = arm + ".lower.w";
  }
  for (int k = 0; k < 2; ++k)
    m.extras.push_back({k == 0 ? "motor_left.i" : "motor_right.i", [motors, k](const State& st) { return motors->current(st, k); },
                        [motors, k](State& st, double v) { motors->set_current(st, k, v); }});
  m.independent = {"linkage.left.theta",  "linkage.right.theta", "linkage.left.dtheta",
                   "linkage.right.dtheta", "motor_left.i",        "motor_right.i"};
}

}  // namespace simbench
