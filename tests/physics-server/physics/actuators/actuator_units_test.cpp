// Each actuator kind's configuration (Params, from its ActuatorDef and the
// world's servo parameters), its one wire <-> physical conversion, and the
// force actuators' shared law and current: without ODE where they need none,
// through a World where they do.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>

#include "model/module_def.h"
#include "model/units.h"
#include "physics/actuators/actuator.h"
#include "physics/actuators/force_motor.h"
#include "physics/world.h"
#include "world_of.h"

namespace chainsim {
namespace {

constexpr int32_t kWireMax = std::numeric_limits<int32_t>::max();

// wire -> physical -> wire gives the wire value back, over the whole int32
// range the protocol can carry
TEST(WireUnits, EveryKindRoundTripsWireValues) {
  for (ServoKind kind : {ServoKind::Rotary, ServoKind::Linear, ServoKind::Screw, ServoKind::DcMotor}) {
    for (int32_t w : {0, 1, -1, 999, -1000, 12345, -45000, 90000, 1000000, -7654321, kWireMax - 1,
                      -kWireMax}) {
      EXPECT_EQ(to_wire(kind, setpoint_from_wire(kind, w)), w)
          << "kind " << static_cast<int>(kind) << ", wire " << w;
    }
  }
}

TEST(WireUnits, EachKindHasItsOwnUnit) {
  EXPECT_NEAR(RotaryServo::setpoint_from_wire(90000), kPi / 2, 1e-15);  // millidegrees
  EXPECT_NEAR(LinearServo::setpoint_from_wire(12345), 0.012345, 1e-17);  // micrometres
  EXPECT_NEAR(ScrewDrive::setpoint_from_wire(-22500), -0.25, 1e-17);     // a servo pulse: +-90 degrees = full
  EXPECT_EQ(RotaryServo::to_wire(-kPi / 4), -45000);
  EXPECT_EQ(LinearServo::to_wire(0.0071), 7100);
  EXPECT_EQ(ScrewDrive::to_wire(1.0), 90000);
  EXPECT_NEAR(DcMotor::setpoint_from_wire(-22500), -0.25, 1e-17);        // as the screw drive
  EXPECT_EQ(DcMotor::to_wire(-0.5), -45000);
  // the dispatch by kind is the same conversion
  EXPECT_EQ(setpoint_from_wire(ServoKind::Rotary, 1234), RotaryServo::setpoint_from_wire(1234));
  EXPECT_EQ(to_wire(ServoKind::Linear, 0.5), LinearServo::to_wire(0.5));
}

// the rotary conversion keeps the arithmetic traces were recorded with:
// millidegrees * 1e-3 * pi / 180, and back rad * 180 / pi * 1e3
TEST(WireUnits, RotaryConversionIsBitForBitTheRecordedOne) {
  for (int32_t w : {1, 7, 333, 29999, 45001, -89999}) {
    const double rad = w * 1e-3 * kPi / 180.0;
    EXPECT_EQ(RotaryServo::setpoint_from_wire(w), rad);
    EXPECT_EQ(RotaryServo::to_wire(rad), static_cast<int32_t>(std::lround(rad * 180.0 / kPi * 1e3)));
  }
}

TEST(WireUnits, ValuesRoundToNearestAndClampToTheInt32Range) {
  EXPECT_EQ(LinearServo::to_wire(0.0000014), 1);
  EXPECT_EQ(LinearServo::to_wire(0.0000016), 2);
  EXPECT_EQ(LinearServo::to_wire(-0.0000025), -3);  // halves away from zero
  EXPECT_EQ(LinearServo::to_wire(1e9), kWireMax);
  EXPECT_EQ(RotaryServo::to_wire(-1e12), -kWireMax);
  EXPECT_EQ(ScrewDrive::to_wire(std::nan("")), 0);
  EXPECT_EQ(ScrewDrive::to_wire(std::numeric_limits<double>::infinity()), 0);
}

// set-points from the wire are clamped to each actuator's range
TEST(WireUnits, WireSetPointsAreClampedToTheActuatorsRange) {
  WorldConfig c;
  c.head_position = Eigen::Vector3d(0, 0, 0.5);
  World w = world_of(c, {"rotation", "extension", "helicoidal"});
  ASSERT_EQ(w.servo_kind(1, 0), ServoKind::Linear);
  ASSERT_EQ(w.servo_kind(2, 0), ServoKind::DcMotor);  // the helicoidal module's head motor
  w.set_servo_setpoint_wire(0, 0, 120000);  // beyond the +90 degree stop
  EXPECT_NEAR(w.servo_setpoint(0, 0), kPi / 2, 1e-12);
  w.set_servo_setpoint_wire(0, 1, -kWireMax);
  EXPECT_NEAR(w.servo_setpoint(0, 1), -kPi / 2, 1e-12);
  const ModuleDef ext = builtin_module_def("extension");
  const JointDef& slider = ext.joints[ext.actuators[driven_servo_actuators(ext)[0]].joint];
  w.set_servo_setpoint_wire(1, 0, kWireMax);
  EXPECT_EQ(w.servo_setpoint(1, 0), slider.hi);
  w.set_servo_setpoint_wire(1, 0, -kWireMax);
  EXPECT_EQ(w.servo_setpoint(1, 0), slider.lo);
  w.set_servo_setpoint_wire(2, 0, 450000);  // five times full scale
  EXPECT_EQ(w.servo_setpoint(2, 0), 1.0);
  w.set_servo_setpoint_wire(2, 0, -90001);
  EXPECT_EQ(w.servo_setpoint(2, 0), -1.0);
}

ActuatorDef force_def(ActuatorType type) {
  ActuatorDef a;
  a.type = type;
  a.fmax_n = 2.0;
  a.l0_m = 0.004;
  a.v_free_m_s = 0.05;
  a.direction = Eigen::Vector3d(0, 3, 4);
  return a;
}

TEST(ActuatorParams, RotaryServoRangeIsTheHingesStopsElseAFullTurn) {
  ActuatorDef a;
  JointDef j;
  ServoParams world;
  world.kp = 7.0;
  j.lo = -0.5;
  j.hi = 1.25;
  RotaryServo::Params p = RotaryServo::params_of(a, j, world);
  EXPECT_EQ(p.lo_rad, -0.5);
  EXPECT_EQ(p.hi_rad, 1.25);
  EXPECT_EQ(p.motor.kp, 7.0);  // the world's model when the actuator has none
  j = JointDef{};              // no stops
  ServoParams own;
  own.kp = 20.0;
  a.servo = own;
  p = RotaryServo::params_of(a, j, world);
  EXPECT_EQ(p.lo_rad, -kPi);
  EXPECT_EQ(p.hi_rad, kPi);
  EXPECT_EQ(p.motor.kp, 20.0);  // its own model wins
}

TEST(ActuatorParams, ForceActuatorsTakeTheWorldsCurrentSenseAndStallCurrent) {
  ServoParams world;
  world.supply_v = 6.0;
  world.r = 10.0;
  world.adc_full_scale_a = 0.8;
  world.current_filter_tau_s = 0.002;
  JointDef slider;
  slider.lo = 0.0;
  slider.hi = 0.02;
  const double h = 5e-4;
  LinearServo::Params lp = LinearServo::params_of(force_def(ActuatorType::LinearServo), slider, world, h);
  EXPECT_EQ(lp.stall_current_a, 0.6);  // Vs / R of the world's servo
  EXPECT_EQ(lp.adc_full_scale_a, 0.8);
  EXPECT_EQ(lp.filter_decay, std::exp(-h / 0.002));
  EXPECT_EQ(lp.lo_m, 0.0);
  EXPECT_EQ(lp.hi_m, 0.02);
  EXPECT_EQ(lp.l0_m, 0.004);
  ActuatorDef sd = force_def(ActuatorType::ScrewDrive);
  sd.stall_current_a = 0.3;  // its own
  ScrewDrive::Params sp = ScrewDrive::params_of(sd, world, h);
  EXPECT_EQ(sp.stall_current_a, 0.3);
  EXPECT_NEAR((sp.direction - Eigen::Vector3d(0, 0.6, 0.8)).norm(), 0.0, 1e-15);  // unit
  world.current_filter_tau_s = 0;
  EXPECT_EQ(ScrewDrive::params_of(sd, world, h).filter_decay, 0.0);  // no filter
}

TEST(ForceMotor, LawWithDampingIsImplicitWithoutItAConstantForce) {
  const ForceLaw damped = make_force_law(1.5, 30.0);
  EXPECT_EQ(damped.damping_n_s_m, 30.0);
  EXPECT_EQ(damped.target_rate_m_s, 0.05);
  EXPECT_EQ(damped.force_n, 0.0);
  // F = D (v* - v'), clamped to fmax
  EXPECT_NEAR(force_after_step(damped, 0.02, 2.0), 0.9, 1e-15);
  EXPECT_EQ(force_after_step(damped, -1.0, 2.0), 2.0);
  EXPECT_EQ(force_after_step(damped, 1.0, 2.0), -2.0);
  const ForceLaw plain = make_force_law(-0.7, 0.0);
  EXPECT_EQ(plain.damping_n_s_m, 0.0);
  EXPECT_EQ(force_after_step(plain, 123.0, 2.0), -0.7);  // whatever the rate
}

TEST(ForceMotor, CurrentFollowsTheForceAndItsFilterSettles) {
  ForceMotorCurrent c;
  const double decay = std::exp(-5e-4 / 0.003);
  c.update(-1.0, 2.0, 0.4, true, decay);
  EXPECT_EQ(c.current_a, -0.2);                       // |F| / fmax * stall, signed
  EXPECT_NEAR(c.filtered_current_a, 0.2 * (1 - decay), 1e-15);  // one step into the RC filter
  for (int k = 0; k < 200; ++k) c.update(-1.0, 2.0, 0.4, true, decay);
  EXPECT_NEAR(c.filtered_current_a, 0.2, 1e-12);
  EXPECT_EQ(c.adc_counts(0.5), 409);   // round(0.2 / 0.5 * 1023)
  EXPECT_EQ(c.adc_counts(0.1), 1023);  // beyond full scale: clamped
  EXPECT_EQ(c.adc_counts(0.0), 0);     // no current sense
  c.update(-1.0, 2.0, 0.4, false, decay);             // not driven: no current
  EXPECT_EQ(c.current_a, 0.0);
  EXPECT_LT(c.filtered_current_a, 0.2);
}

}  // namespace
}  // namespace chainsim
