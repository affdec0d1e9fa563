// Linear servo (paper eqs 4-5, extension module) and screw drive (helicoidal
// module) in the World, on test module types given through
// WorldConfig::module_types: reaching and holding a reference, force
// saturation, the drive along a body axis and its force/speed limits, the
// supply current and energy (rotary servos too), what firmware reads.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "model/module_def.h"
#include "model/units.h"
#include "physics/world.h"
#include "world_of.h"

namespace chainsim {
namespace {
constexpr double kG = 9.81;

BodyDef box(const std::string& name, double mass, const Eigen::Vector3d& centre,
            const Eigen::Vector3d& size) {
  BodyDef b;
  b.name = name;
  b.shape = Shape::Box;
  b.box_m = size;
  b.mass_kg = mass;
  b.pose.position = centre;
  return b;
}

// two boxes of equal mass and a slider between them along `axis` (module
// frame), stroke 0..15 mm, a linear servo on it and its current on ADC 0.
// (Equal masses: with the base pinned and a slide 10 times heavier, ODE's
// QuickStep at 30 iterations leaves the slide 0.05 mm off and jittering by
// 0.035 mm; it is exact at 200 iterations. The extension module's two boxes
// are alike.)
ModuleDef slide_def(const Eigen::Vector3d& axis, double slide_mass, double fmax, double l0,
                    double v_free) {
  ModuleDef d;
  d.type = "slide_test";
  d.bodies.push_back(box("base", slide_mass, {-0.01, 0, 0}, {0.02, 0.02, 0.02}));
  d.bodies.push_back(box("slide", slide_mass, {-0.03, 0, 0}, {0.02, 0.018, 0.018}));
  JointDef j;
  j.name = "extend";
  j.type = JointType::Slider;
  j.parent = 0;
  j.child = 1;
  j.axis = axis;
  j.lo = 0.0;
  j.hi = 0.015;
  d.joints.push_back(j);
  ActuatorDef a;
  a.name = "linear";
  a.type = ActuatorType::LinearServo;
  a.joint = 0;
  a.fmax_n = fmax;
  a.l0_m = l0;
  a.v_free_m_s = v_free;
  d.actuators.push_back(a);
  SensorDef c;
  c.name = "linear_current";
  c.type = SensorType::MotorCurrent;
  c.actuator = 0;
  c.channel = 0;
  d.sensors.push_back(c);
  d.front.body = 0;
  d.back.body = 1;
  d.back.frame.position = Eigen::Vector3d(-0.04, 0, 0);
  return d;
}

// one box pushed along `direction` (body frame = module frame here)
ModuleDef screw_def(const Eigen::Vector3d& direction, double mass, double fmax, double v_free) {
  ModuleDef d;
  d.type = "screw_test";
  d.bodies.push_back(box("pig", mass, {-0.02, 0, 0}, {0.04, 0.02, 0.02}));
  ActuatorDef a;
  a.name = "screw";
  a.type = ActuatorType::ScrewDrive;
  a.body = 0;
  a.direction = direction;
  a.fmax_n = fmax;
  a.v_free_m_s = v_free;
  d.actuators.push_back(a);
  d.front.body = 0;
  d.back.body = 0;
  d.back.frame.position = Eigen::Vector3d(-0.04, 0, 0);
  return d;
}

WorldConfig config_for(const ModuleDef& def, double gravity, double z = 0.5) {
  WorldConfig c;
  c.module_types = {def};
  c.gravity_m_s2 = gravity;
  c.head_position = Eigen::Vector3d(0, 0, z);
  return c;
}

void run(World& w, double seconds, double* energy_j = nullptr) {
  const double h = static_cast<double>(w.dt_us()) * 1e-6;
  const int n = static_cast<int>(std::lround(seconds / h));
  for (int k = 0; k < n; ++k) {
    w.step();
    // what the lockstep server integrates into summary.json's energy_j
    if (energy_j) *energy_j += w.module_supply_current_a(0) * WorldConfig{}.servo.supply_v * h;
  }
}

TEST(LinearServo, ReachesItsReferenceAndHolds) {
  // 1 N, 2 mm band, 20 mm/s no-load speed (a micro linear servo)
  World w = world_of(config_for(slide_def(-Eigen::Vector3d::UnitX(), 0.005, 1.0, 0.002, 0.02), 0.0),
          {"slide_test"});
  w.pin_body(0, 0);
  ASSERT_EQ(w.servo_count(0), 1);
  EXPECT_EQ(w.servo_kind(0, 0), ServoKind::Linear);
  w.set_servo_setpoint(0, 0, 0.010);
  double vmax = 0, pos_prev = 0, law_err = 0, early_effort = 0;
  for (int k = 0; k < 4000; ++k) {  // 2 s: 0.4 s at full speed, then the band (l0/v_free = 0.1 s)
    w.step();
    const double pos = w.servo_position(0, 0);
    const double v = (pos - pos_prev) / 5e-4;  // ODE: pos' = pos + h v'
    vmax = std::max(vmax, v);
    pos_prev = pos;
    // while saturated (more than l0 = 2 mm away): F = fmax (1 - v/v_free)
    if (0.010 - pos > 0.0021) law_err = std::max(law_err, std::fabs(w.servo_effort(0, 0) - (1 - v / 0.02)));
    if (k == 0) early_effort = w.servo_effort(0, 0);
  }
  double lo = 1e9, hi = -1e9;
  for (int k = 0; k < 2000; ++k) {  // the next second
    w.step();
    lo = std::min(lo, w.servo_position(0, 0));
    hi = std::max(hi, w.servo_position(0, 0));
  }
  std::printf("linear servo: first-step force %.3f N, top speed %.2f mm/s, final %.4f mm, spread "
              "%.2g mm, force law error %.2g N\n", early_effort, vmax * 1e3, hi * 1e3, (hi - lo) * 1e3,
              law_err);
  // the first step already reaches most of the no-load speed (m v_free / fmax
  // = 0.1 ms < h): the step's force is what the implicit law gives, not fmax
  EXPECT_GT(early_effort, 0.1);
  EXPECT_LT(law_err, 1e-6);
  EXPECT_LE(vmax, 0.02 * 1.001);              // never faster than the no-load speed
  EXPECT_GT(vmax, 0.02 * 0.95);               // and it gets there on a long move
  EXPECT_NEAR(hi, 0.010, 1e-6);
  EXPECT_LT(hi - lo, 1e-7);                   // holds: no oscillation, no drift
  EXPECT_NEAR(w.servo_effort(0, 0), 0.0, 1e-6);
  // a set-point beyond the stroke is clamped to it
  w.set_servo_setpoint(0, 0, 0.1);
  EXPECT_NEAR(w.servo_setpoint(0, 0), 0.015, 1e-12);
}

// the paper's law exactly (no speed term): an undamped spring in continuous
// time; the implicit proportional term keeps it stable and it settles
TEST(LinearServo, PurePaperLawIsStable) {
  World w = world_of(config_for(slide_def(-Eigen::Vector3d::UnitX(), 0.005, 1.0, 0.002, 0.0), 0.0),
          {"slide_test"});
  w.pin_body(0, 0);
  w.set_servo_setpoint(0, 0, 0.008);
  double peak = 0;
  for (int k = 0; k < 2000; ++k) {
    w.step();
    const double p = w.servo_position(0, 0);
    ASSERT_TRUE(std::isfinite(p));
    peak = std::max(peak, p);
  }
  std::printf("pure law: peak %.3f mm, after 1 s %.4f mm\n", peak * 1e3, w.servo_position(0, 0) * 1e3);
  EXPECT_LE(peak, 0.015 + 1e-4);   // at most up to the stop
  EXPECT_NEAR(w.servo_position(0, 0), 0.008, 2e-5);
}

// slider vertical: the servo lifts a light slide to its reference less the
// proportional droop l0 m g / fmax, and cannot lift a heavy one (the force
// saturates at fmax and the slide stays on its lower stop)
TEST(LinearServo, HoldsALoadWithDroopAndSaturatesOnAnOverload) {
  for (double mass : {0.05, 0.2}) {
    World w = world_of(config_for(slide_def(Eigen::Vector3d::UnitZ(), mass, 1.0, 0.002, 0.02), kG),
            {"slide_test"});
    w.pin_body(0, 0);
    w.set_servo_setpoint(0, 0, 0.010);
    double energy = 0;
    run(w, 2.0, &energy);
    const double pos = w.servo_position(0, 0), f = w.servo_effort(0, 0);
    std::printf("slide %.0f g: position %.4f mm, force %.4f N, supply %.4f A, energy %.4f J\n",
                mass * 1e3, pos * 1e3, f, w.module_supply_current_a(0), energy);
    const double weight = mass * kG;
    if (weight < 1.0) {
      EXPECT_NEAR(pos, 0.010 - 0.002 * weight / 1.0, 2e-5);
      EXPECT_NEAR(f, weight, 1e-3);
    } else {
      EXPECT_NEAR(pos, 0.0, 2e-4);   // on the stop
      EXPECT_NEAR(f, 1.0, 1e-3);     // saturated (less the stop's tiny ERP push-back speed)
      // stalled: the supply current is the stall current Vs/R (the default)
      EXPECT_NEAR(w.module_supply_current_a(0), 5.0 / 12.0, 1e-3);
      ModuleSample s;
      w.sample(0, &s);
      EXPECT_NEAR(s.adc[0], 5.0 / 12.0 / 0.5 * 1023, 1.0);
    }
    EXPECT_NEAR(w.module_supply_current_a(0), std::fabs(f) / 1.0 * 5.0 / 12.0, 1e-9);
    EXPECT_GT(energy, 0.0);
  }
}

TEST(ScrewDrive, PushesABodyAlongItsAxisUpToTheNoLoadSpeed) {
  // heading rotates the chain: the drive axis turns with the body
  WorldConfig c = config_for(screw_def(Eigen::Vector3d::UnitX(), 0.02, 0.5, 0.03), 0.0);
  c.heading_rad = 0.6;
  World w = world_of(c, {"screw_test"});
  EXPECT_EQ(w.servo_kind(0, 0), ServoKind::Screw);
  w.set_servo_setpoint(0, 0, 1.0);
  w.step();
  // the implicit law: F = fmax (1 - v'/v_free) with v' the end-of-step speed
  const double v1 = w.body_state(0, 0).linear_velocity.norm();
  EXPECT_NEAR(w.servo_effort(0, 0), 0.5 * (1 - v1 / 0.03), 1e-9);
  EXPECT_NEAR(v1, 5e-4 * w.servo_effort(0, 0) / 0.02, 1e-9);   // and it is what moved the body
  run(w, 0.2);
  const Eigen::Vector3d axis(std::cos(0.6), std::sin(0.6), 0);
  const Eigen::Vector3d v = w.body_state(0, 0).linear_velocity;
  std::printf("screw drive, full drive: speed %.5f m/s, off-axis %.2g m/s, force %.2g N\n",
              v.dot(axis), (v - v.dot(axis) * axis).norm(), w.servo_effort(0, 0));
  EXPECT_NEAR(v.dot(axis), 0.03, 1e-5);              // stops accelerating at v_free
  EXPECT_LT((v - v.dot(axis) * axis).norm(), 1e-9);  // along its axis only
  EXPECT_NEAR(w.servo_rate(0, 0), 0.03, 1e-5);  // speed along the axis
  EXPECT_NEAR(w.servo_effort(0, 0), 0.0, 1e-3);
  // half reverse: half the no-load speed backwards
  w.set_servo_setpoint(0, 0, -0.5);
  run(w, 0.2);
  EXPECT_NEAR(w.body_state(0, 0).linear_velocity.dot(axis), -0.015, 1e-5);
  ModuleSample s;
  w.sample(0, &s);
  EXPECT_EQ(s.servo_position_wire[0], -45000);  // no sensor: echoes the command (-0.5 of full scale)
  // commands are clamped to -1..1
  w.set_servo_setpoint(0, 0, 7.0);
  EXPECT_DOUBLE_EQ(w.servo_setpoint(0, 0), 1.0);
}

// climbing straight up: speed v_free (1 - m g / fmax) while the drive can lift
// the body; beyond its force limit it cannot, and the force stays at fmax
TEST(ScrewDrive, ClimbsAtTheSpeedItsForceAllowsAndSaturatesBeyond) {
  for (double fmax : {0.5, 0.1}) {
    const double m = 0.02;
    World w = world_of(config_for(screw_def(Eigen::Vector3d::UnitZ(), m, fmax, 0.03), kG, 5.0), {"screw_test"});
    w.set_servo_setpoint(0, 0, 1.0);
    double energy = 0;
    run(w, 0.3, &energy);
    const double vz = w.body_state(0, 0).linear_velocity.z();
    std::printf("screw drive climbing with fmax %.2f N: vz %.5f m/s, force %.4f N, supply %.4f A\n",
                fmax, vz, w.servo_effort(0, 0), w.module_supply_current_a(0));
    if (fmax > m * kG) {
      EXPECT_NEAR(vz, 0.03 * (1 - m * kG / fmax), 1e-5);
      EXPECT_NEAR(w.servo_effort(0, 0), m * kG, 1e-4);
    } else {
      EXPECT_LT(vz, -0.5);                       // it falls: the drive is too weak
      EXPECT_DOUBLE_EQ(w.servo_effort(0, 0), fmax);
      const double a_expect = -kG + fmax / m;
      run(w, 0.1);
      EXPECT_NEAR((w.body_state(0, 0).linear_velocity.z() - vz) / 0.1, a_expect, 1e-3);
    }
    EXPECT_NEAR(w.module_supply_current_a(0), std::fabs(w.servo_effort(0, 0)) / fmax * 5.0 / 12.0,
                1e-9);
    EXPECT_GT(energy, 0.0);
  }
}

TEST(ScrewDrive, WithoutSpeedTermItIsAConstantForce) {
  World w = world_of(config_for(screw_def(Eigen::Vector3d::UnitX(), 0.02, 0.2, 0.0), 0.0), {"screw_test"});
  w.set_servo_setpoint(0, 0, 0.5);
  run(w, 0.1);
  // F = 0.1 N on 20 g for 0.1 s: 0.5 m/s
  EXPECT_NEAR(w.body_state(0, 0).linear_velocity.x(), 0.5, 1e-9);
  EXPECT_DOUBLE_EQ(w.servo_effort(0, 0), 0.1);
}

TEST(ScrewDrive, DisabledOrUnpoweredPushesNothingAndDrawsNothing) {
  for (bool unpowered : {false, true}) {
    World w = world_of(config_for(screw_def(Eigen::Vector3d::UnitX(), 0.02, 0.5, 0.03), 0.0), {"screw_test"});
    w.set_servo_setpoint(0, 0, 1.0);
    if (unpowered)
      w.set_module_powered(0, false);
    else
      w.set_servo_enabled(0, 0, false);
    double energy = 0;
    run(w, 0.2, &energy);
    EXPECT_EQ(w.body_state(0, 0).linear_velocity.norm(), 0.0);
    EXPECT_EQ(energy, 0.0);
    EXPECT_EQ(w.servo_effort(0, 0), 0.0);
  }
}

// energy (the server's integral of supply current x supply voltage) of a rotary
// servo: > 0 while it moves, 0 when the module is unpowered
TEST(Power, MovingServoUsesEnergyAndUnpoweredNone) {
  WorldConfig c;
  c.gravity_m_s2 = 0;
  c.head_position = Eigen::Vector3d(0, 0, 0.3);
  for (bool powered : {true, false}) {
    World w = world_of(c, {"rotation"});
    w.pin_body(0, 0);
    w.set_module_powered(0, powered);
    double energy = 0;
    for (int k = 0; k < 4; ++k) {  // four 90 degree moves
      w.set_servo_setpoint(0, 0, (k % 2 ? -45 : 45) * kRadPerDeg);
      run(w, 0.25, &energy);
    }
    std::printf("rotation module, %s: %.4f J for four 90 degree moves\n",
                powered ? "powered" : "unpowered", energy);
    if (powered) {
      // each move: about 0.4 A for a few ms, then a running current: mJ
      EXPECT_GT(energy, 1e-3);
      EXPECT_LT(energy, 0.2);
    } else {
      EXPECT_EQ(energy, 0.0);
    }
  }
}

TEST(LinearServo, MovingUsesEnergyAndUnpoweredNone) {
  for (bool powered : {true, false}) {
    World w = world_of(config_for(slide_def(-Eigen::Vector3d::UnitX(), 0.005, 1.0, 0.002, 0.02), 0.0),
          {"slide_test"});
    w.pin_body(0, 0);
    w.set_module_powered(0, powered);
    w.set_servo_setpoint(0, 0, 0.012);
    double energy = 0;
    run(w, 2.0, &energy);
    std::printf("linear servo 12 mm move, %s: %.5f J, final %.3f mm\n",
                powered ? "powered" : "unpowered", energy, w.servo_position(0, 0) * 1e3);
    if (powered) {
      // accelerating 5 g to 20 mm/s takes < 1 ms at 1 N: it runs at no-load
      // speed with almost no force; the energy is that of the short start
      // and stop, tiny but not zero
      EXPECT_GT(energy, 0.0);
      EXPECT_NEAR(w.servo_position(0, 0), 0.012, 1e-6);
    } else {
      EXPECT_EQ(energy, 0.0);
      EXPECT_NEAR(w.servo_position(0, 0), 0.0, 1e-12);
    }
  }
}

// set-points from the wire and what firmware reads back, each kind in its
// wire unit: a rotary servo in millidegrees, a linear servo in micrometres,
// a screw drive's command echoed
TEST(ForceActuators, SetPointsAndSamplesUseEachKindsWireUnit) {
  ModuleSample s;
  {
    WorldConfig c;
    c.gravity_m_s2 = 0;
    c.head_position = Eigen::Vector3d(0, 0, 0.3);
    World w = world_of(c, {"rotation"});
    w.pin_body(0, 0);
    EXPECT_EQ(w.servo_kind(0, 1), ServoKind::Rotary);
    w.set_servo_setpoint_wire(0, 0, 30000);  // 30 degrees
    EXPECT_NEAR(w.servo_setpoint(0, 0), 30 * kRadPerDeg, 1e-15);
    run(w, 0.5);
    w.sample(0, &s);
    EXPECT_EQ(s.servo_position_wire[0], RotaryServo::to_wire(w.servo_position(0, 0)));
    EXPECT_NEAR(s.servo_position_wire[0], 30000, 200);
  }
  {
    World w = world_of(config_for(slide_def(-Eigen::Vector3d::UnitX(), 0.005, 1.0, 0.002, 0.02), 0.0),
            {"slide_test"});
    w.pin_body(0, 0);
    EXPECT_EQ(w.servo_kind(0, 0), ServoKind::Linear);
    w.set_servo_setpoint_wire(0, 0, 7100);  // 7.1 mm
    EXPECT_NEAR(w.servo_setpoint(0, 0), 0.0071, 1e-15);
    run(w, 1.0);
    w.sample(0, &s);
    EXPECT_EQ(s.servo_position_wire[0], LinearServo::to_wire(w.servo_position(0, 0)));
    EXPECT_NEAR(s.servo_position_wire[0], 7100, 1);
  }
  {
    World w = world_of(config_for(screw_def(Eigen::Vector3d::UnitX(), 0.02, 0.5, 0.03), 0.0), {"screw_test"});
    EXPECT_EQ(w.servo_kind(0, 0), ServoKind::Screw);
    w.set_servo_setpoint_wire(0, 0, -22500);  // a quarter reverse (full: 90 degrees of servo pulse)
    EXPECT_NEAR(w.servo_setpoint(0, 0), -0.25, 1e-15);
    run(w, 0.1);
    w.sample(0, &s);
    EXPECT_EQ(s.servo_position_wire[0], -22500);
    EXPECT_LT(w.servo_rate(0, 0), 0.0);  // and it drives backwards
  }
}

TEST(ForceActuators, ValidationRejectsBadParameters) {
  ModuleDef d = slide_def(Eigen::Vector3d::UnitX(), 0.005, 1.0, 0.002, 0.02);
  EXPECT_NO_THROW(validate_module_def(d));
  d.actuators[0].l0_m = 0;
  EXPECT_THROW(validate_module_def(d), std::invalid_argument);
  d = slide_def(Eigen::Vector3d::UnitX(), 0.005, 0.0, 0.002, 0.02);
  EXPECT_THROW(validate_module_def(d), std::invalid_argument);
  d = slide_def(Eigen::Vector3d::UnitX(), 0.005, 1.0, 0.002, -1.0);
  EXPECT_THROW(validate_module_def(d), std::invalid_argument);
  d = slide_def(Eigen::Vector3d::UnitX(), 0.005, 1.0, 0.002, 0.02);
  d.joints[0].type = JointType::Hinge;
  EXPECT_THROW(validate_module_def(d), std::invalid_argument);
  ModuleDef s = screw_def(Eigen::Vector3d::Zero(), 0.02, 0.5, 0.03);
  EXPECT_THROW(validate_module_def(s), std::invalid_argument);
  s = screw_def(Eigen::Vector3d::UnitX(), 0.02, 0.5, 0.03);
  s.actuators[0].body = 3;
  EXPECT_THROW(validate_module_def(s), std::invalid_argument);
  EXPECT_EQ(driven_servo_actuators(screw_def(Eigen::Vector3d::UnitX(), 0.02, 0.5, 0.03)).size(), 1u);
}

}  // namespace
}  // namespace chainsim
