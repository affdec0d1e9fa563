// The servo model's catalogue variants (servo_model.h): the pwm frame phase,
// the linear-driver supply sag and the compliant backlash mesh, each on a
// one-hinge stand stepped in closed form ((Jl/h + D) w' = Jl w / h + D v + tau);
// the supply's rail capacitor on the model alone, its output held or driven.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "physics/actuators/servo_model.h"

namespace chainsim {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;
constexpr double kLoad = 3e-6;

struct Stand {
  ServoModel s;
  double theta = 0, w = 0, tau = 0, h = 1e-4;
  explicit Stand(const ServoParams& p) : s(p) {}
  void step() {
    const ServoModel::StepLaw law = s.begin_step(theta, w, h);
    const double jh = kLoad / h;
    w = (jh * w + law.damping * law.target_rate + tau) / (jh + law.damping);
    s.end_step(w);
    theta += h * w;
  }
  // runs to time t (s) from its current time, set-point sp (rad)
  void run(double seconds, double sp) {
    s.set_setpoint(sp);
    for (long k = std::lround(seconds / h); k > 0; --k) step();
  }
};

// the time (s) of the first step whose applied set-point is sp
double latch_time(const ServoParams& p, double change_at, double sp) {
  Stand st(p);
  const double h = st.h;
  for (int n = 0; n < 2000; ++n) {
    if (n * h >= change_at - 1e-12) st.s.set_setpoint(sp);
    st.step();
    if (st.s.applied_setpoint() == sp) return n * h;
  }
  return -1;
}

TEST(ServoVariants, FramesStartAtThePhaseAndRepeatEveryPeriod) {
  ServoParams p;
  p.pwm_frame_s = 0.02;
  // phase 0: frames at 0, 20, 40 ms; a change at 3 ms waits for 20 ms
  EXPECT_NEAR(latch_time(p, 0.003, 0.5), 0.020, 1e-9);
  // phase 7 ms: frames at 7, 27, 47 ms
  p.pwm_frame_phase_s = 0.007;
  EXPECT_NEAR(latch_time(p, 0.003, 0.5), 0.007, 1e-9);
  EXPECT_NEAR(latch_time(p, 0.0071, 0.5), 0.027, 1e-9);
  // a phase longer than the period: the first frame is at the phase
  p.pwm_frame_phase_s = 0.031;
  EXPECT_NEAR(latch_time(p, 0.0, 0.5), 0.031, 1e-9);
  // before the first frame the servo holds the set-point it had (0)
  Stand st(p);
  st.run(0.03, 0.5);
  EXPECT_EQ(st.s.applied_setpoint(), 0.0);
  EXPECT_EQ(st.theta, 0.0);
}

// the falling-edge variant: a frame starts a pulse 1.5 ms + k (sp + origin -
// 90 deg) wide for the set-point of that moment, acted on at its falling edge
// (RC servos decode so); k = 1/90 ms per deg (0.5-2.5 ms over 180 deg). The
// default origin, 90, is a module's: its joint angle 0 is the 1.5 ms centre
TEST(ServoVariants, AFallingEdgeDecoderActsAPulseWidthAfterTheFrame) {
  ServoParams p;
  p.pwm_frame_s = 0.02;
  p.pwm_frame_phase_s = 0.007;
  p.pwm_pulse_s_per_deg = 1e-3 / 90;
  // joint angle 30 deg: 1.8333 ms after the frame at 7 ms, in the step from
  // 8.8 ms
  EXPECT_NEAR(latch_time(p, 0.003, 30 * kDeg), 0.0088, 1e-9);
  // -30 deg: 1.1667 ms, in the step from 8.1 ms; the delay depends on the
  // set-point by 0.67 ms
  EXPECT_NEAR(latch_time(p, 0.003, -30 * kDeg), 0.0081, 1e-9);
  // the pulse's scale given as on a bench: 120 deg is 1.8333 ms again
  p.pwm_pulse_origin_deg = 0;
  EXPECT_NEAR(latch_time(p, 0.003, 120 * kDeg), 0.0088, 1e-9);
  // a change after the frame's start waits for the next pulse (27 ms)
  EXPECT_NEAR(latch_time(p, 0.0075, 60 * kDeg), 0.0281, 1e-9);
  // the set-point 0 of the model at 30 deg on the pulse's scale: 30 deg
  // more is 60 deg, again 1.1667 ms
  p.pwm_pulse_origin_deg = 30;
  EXPECT_NEAR(latch_time(p, 0.003, 30 * kDeg), 0.0081, 1e-9);
  // without the slope the frame latches at once (7 ms): the at-frame form
  p.pwm_pulse_s_per_deg = 0;
  EXPECT_NEAR(latch_time(p, 0.003, 30 * kDeg), 0.007, 1e-9);
}

// the deadband's comparator form: inside the window no drive; outside the
// whole error drives (the first step's current as without a deadband), where
// the dead zone drives with the error less the half-band
TEST(ServoVariants, AComparatorDeadbandDrivesTheWholeErrorOutsideItsWindow) {
  auto first_current = [](const ServoParams& p, double sp_deg) {
    Stand st(p);
    st.s.set_setpoint(sp_deg * kDeg);
    st.step();
    return st.s.mean_current_a();
  };
  ServoParams none, comparator, zone;
  comparator.deadband_comparator_deg = 4;
  zone.deadband_deg = 4;
  // 1.5 deg: inside the window, no drive for either form
  EXPECT_EQ(first_current(comparator, 1.5), 0.0);
  EXPECT_EQ(first_current(zone, 1.5), 0.0);
  // 3 deg: the comparator passes all of it, the dead zone 1 deg of it
  const double full = first_current(none, 3.0);
  ASSERT_GT(full, 0.0);
  EXPECT_EQ(first_current(comparator, 3.0), full);
  EXPECT_NEAR(first_current(zone, 3.0), full / 3, 0.05 * full);
  // from 10 deg away the comparator stops the drive once inside the window:
  // the servo comes to rest with the error within it, not at the set-point
  Stand st(comparator);
  st.run(0.5, 10 * kDeg);
  const double err = 10 - st.theta / kDeg;
  EXPECT_LE(std::fabs(err), 2.0 + 0.2);
  EXPECT_GT(std::fabs(err), 0.05);
}

// a frame inside a step acts for the part of the step after it: half-way
// through a 100 us step, the move lies half-way between the same frame
// latched at the step's start and at its end (latched at the next step, as
// it was, it was the late one: up to a step late, a jitter a calibration at
// 0.1 deg of noise took for another effect)
TEST(ServoVariants, AFrameInsideAStepActsForThePartOfTheStepAfterIt) {
  auto angle_at = [](double phase_s, double h, double t) {
    ServoParams p;
    p.pwm_frame_s = 0.02;
    p.pwm_frame_phase_s = phase_s;
    Stand st(p);
    st.h = h;
    st.s.set_setpoint(0.5);
    for (long k = std::lround(t / h); k > 0; --k) st.step();
    return st.theta;
  };
  const double t = 0.012;  // 4.95 ms after the frame: the servo is moving fast
  const double early = angle_at(0.0070, 1e-4, t), late = angle_at(0.0071, 1e-4, t);
  ASSERT_GT(std::fabs(early - late), 1e-3);
  const double mid = angle_at(0.00705, 1e-4, t), quarter = angle_at(0.007025, 1e-4, t);
  EXPECT_LT(std::fabs(mid - 0.5 * (early + late)), 0.05 * std::fabs(early - late)) << mid;
  EXPECT_LT(std::fabs(quarter - (0.75 * early + 0.25 * late)), 0.05 * std::fabs(early - late)) << quarter;
  // at 5 us steps the same frames give the same spread: the mean set-point
  // over a step stands for where the frame falls in it
  const double fine_early = angle_at(0.0070, 5e-6, t), fine_mid = angle_at(0.00705, 5e-6, t);
  EXPECT_NEAR(mid - early, fine_mid - fine_early, 0.1 * std::fabs(early - late));
}

TEST(ServoVariants, LinearDriverSagKeepsTheGainAndLowersTheLimit) {
  // hold the output still against a set-point error e and read the drive
  auto drive = [](const ServoParams& p, double err_rad) {
    ServoModel s(p);
    s.set_setpoint(err_rad);
    for (int k = 0; k < 400; ++k) {
      s.begin_step(0.0, 0.0, 1e-4);
      s.end_step(0.0);
    }
    return std::pair<double, double>(s.drive_voltage_v(), s.current_a());
  };
  ServoParams pwm, lin;
  pwm.supply_sag_ohm = 4.0;
  lin.supply_sag_linear_ohm = 4.0;
  // small error (Kp e = 0.84 V): the linear driver keeps Kp e, the bridge scales it
  const double e = 4 * kDeg;
  const auto [vl, il] = drive(lin, e);
  const auto [vp, ip] = drive(pwm, e);
  EXPECT_NEAR(vl, ServoParams{}.kp * e, 1e-9);
  EXPECT_NEAR(vp, ServoParams{}.kp * e * (1 - 4.0 * ip / 5.0), 1e-4);
  EXPECT_LT(vp, 0.97 * vl);   // 1 - Rs i / Vs = 0.94 at i = 70 mA
  // stalled at a large error: both reach Vs - Rs i (duty 1 / the limit),
  // i = Vs / (R + Rs)
  const auto [vl2, il2] = drive(lin, 1.0);
  const auto [vp2, ip2] = drive(pwm, 1.0);
  EXPECT_NEAR(il2, 5.0 / 16.0, 1e-6);
  EXPECT_NEAR(ip2, 5.0 / 16.0, 1e-6);
  EXPECT_NEAR(vl2, 5.0 - 4.0 * il2, 1e-6);
  EXPECT_NEAR(vp2, vl2, 1e-6);
}

// a servo stalled at a large error (output held), its drive voltage every
// 1 ms for 40 ms
std::vector<double> stalled_drive(const ServoParams& p) {
  ServoModel s(p);
  s.set_setpoint(1.0);
  std::vector<double> v;
  for (int k = 1; k <= 400; ++k) {
    s.begin_step(0.0, 0.0, 1e-4);
    s.end_step(0.0);
    if (k % 10 == 0) v.push_back(s.drive_voltage_v());
  }
  return v;
}

TEST(ServoVariants, ARailCapacitorDelaysTheSagByRsC) {
  // Rs 4 ohm, C 1000 uF: the rail sags with a time constant of 4 ms; at
  // stall both forms end at Vs - Rs i, i = Vs / (R + Rs), as without it
  for (const bool linear : {false, true}) {
    SCOPED_TRACE(linear ? "linear driver" : "PWM bridge");
    ServoParams p;
    (linear ? p.supply_sag_linear_ohm : p.supply_sag_ohm) = 4.0;
    const std::vector<double> plain = stalled_drive(p);
    p.supply_rail_f = 1000e-6;
    const std::vector<double> rail = stalled_drive(p);
    const double v_end = 5.0 - 4.0 * 5.0 / 16.0;
    EXPECT_NEAR(plain.back(), v_end, 1e-6);
    EXPECT_NEAR(rail.back(), v_end, 1e-3);
    // at 1 ms the sag without the capacitor is mostly there, with it mostly not
    EXPECT_LT(plain[0], 5.0 - 0.6 * (5.0 - v_end));
    EXPECT_GT(rail[0], 5.0 - 0.3 * (5.0 - v_end));
    // at 4 ms (one Rs C) the rail has made about 1 - 1/e of its way
    const double made = (5.0 - rail[3]) / (5.0 - v_end);
    EXPECT_GT(made, 0.45);
    EXPECT_LT(made, 0.7);
  }
}

TEST(ServoVariants, ABridgeBrakingChargesItsRailALinearDriverDrainsIt) {
  // the output driven backwards through the motor (back-EMF 2.8 V against a
  // small positive drive): the current flows against the duty, so a bridge
  // returns it to the rail (its drive rises above duty x Vs) while a linear
  // driver still draws |i| (its limit falls, its small drive is kept)
  const double err = 5 * kDeg;  // Kp e = 1.05 V, duty 0.21
  const double duty = ServoParams{}.kp * err / 5.0;
  for (const bool linear : {false, true}) {
    SCOPED_TRACE(linear ? "linear driver" : "PWM bridge");
    ServoParams p;
    (linear ? p.supply_sag_linear_ohm : p.supply_sag_ohm) = 4.0;
    p.supply_rail_f = 1000e-6;
    ServoModel s(p);
    double theta = 0;
    for (int k = 0; k < 300; ++k) {
      s.set_setpoint(theta + err);
      s.begin_step(theta, 20.0, 1e-4);
      s.end_step(20.0);
      theta += 20.0 * 1e-4;
    }
    EXPECT_LT(s.current_a(), -0.1);
    if (linear)
      EXPECT_NEAR(s.drive_voltage_v(), ServoParams{}.kp * err, 1e-9);
    else  // settled (30 ms, 7 x Rs C): duty x V with V = Vs - Rs duty i > Vs
      EXPECT_NEAR(s.drive_voltage_v(), duty * (5.0 - 4.0 * duty * s.current_a()), 1e-4);
    EXPECT_EQ(s.drive_voltage_v() > 1.01 * ServoParams{}.kp * err, !linear);
  }
}

TEST(ServoVariants, CompliantMeshDeflectsUnderLoadByTorqueOverStiffness) {
  ServoParams p;
  p.backlash_deg = 2.0;
  p.backlash_stiffness_nm_rad = 0.5;
  Stand st(p);
  st.tau = 0.01;  // pushes the output towards larger angles
  st.run(1.0, 0.0);
  // the servo holds the output near 0 by pulling against the load: the rotor
  // sits behind it by the half play plus tau / k
  const double expect = -(1.0 * kDeg + st.tau / p.backlash_stiffness_nm_rad);
  std::printf("compliant mesh under 0.01 N m: offset %.4f deg (half play + tau/k = %.4f)\n",
              st.s.backlash_offset() / kDeg, expect / kDeg);
  EXPECT_NEAR(st.s.backlash_offset(), expect, 1e-4);
  EXPECT_NEAR(st.s.motor_torque_nm(), -st.tau, 1e-6);
}

TEST(ServoVariants, AStiffMeshMovesLikeTheRigidContact) {
  // a 60 degree move and back: the stiff compliant mesh against the rigid one
  auto path = [](double k) {
    ServoParams p;
    p.backlash_deg = 3.0;
    p.backlash_stiffness_nm_rad = k;
    Stand st(p);
    st.tau = 0.004;
    std::vector<double> th;
    for (double sp : {0.0, 60.0, 20.0, 25.0}) {
      st.s.set_setpoint(sp * kDeg);
      for (int n = 0; n < 3000; ++n) {
        st.step();
        if (n % 10 == 0) th.push_back(st.theta / kDeg);
      }
    }
    return th;
  };
  const std::vector<double> rigid = path(0.0), stiff = path(200.0), soft = path(0.3);
  double d_stiff = 0, d_soft = 0;
  for (size_t k = 0; k < rigid.size(); ++k) {
    d_stiff = std::max(d_stiff, std::fabs(stiff[k] - rigid[k]));
    d_soft = std::max(d_soft, std::fabs(soft[k] - rigid[k]));
  }
  std::printf("mesh 200 N m/rad vs rigid: max %.3f deg; 0.3 N m/rad vs rigid: %.3f deg\n", d_stiff, d_soft);
  EXPECT_LT(d_stiff, 0.3);
  EXPECT_GT(d_soft, 1.0);   // a soft mesh is another servo
  EXPECT_NEAR(stiff.back(), 25.0, 2.0);
}

}  // namespace
}  // namespace chainsim
