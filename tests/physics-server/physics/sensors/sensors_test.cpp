// Sensors of the shipped modules: touch, accelerometer, wheel encoders and the
// wheels' speed-proportional friction.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <string>

#include "model/module_def.h"
#include "model/units.h"
#include "physics/sensors/module_channels.h"
#include "physics/world.h"
#include "world_of.h"

namespace chainsim {
namespace {
// counts for +1 g of 9.81 m/s^2 at range 3 g: 512 + 9.81 / 9.80665 * 512 / 3
constexpr double kUp = 512.0 + 9.81 / 9.80665 * 512.0 / 3.0;    // 682.7
constexpr double kDown = 512.0 - 9.81 / 9.80665 * 512.0 / 3.0;  // 341.3

void run(World& w, double seconds) {
  const int n = static_cast<int>(std::lround(seconds * 1e6 / static_cast<double>(w.dt_us())));
  for (int k = 0; k < n; ++k) w.step();
}

ModuleSample sample(const World& w, int m) {
  ModuleSample s;
  w.sample(m, &s);
  return s;
}

// --- touch -------------------------------------------------------------------

// the cover reports the floor when the head is pushed into it, and nothing
// when the chain lies straight or the head is lifted
TEST(TouchSensor, ReportsTheFloorOnlyWhenTheHeadTouchesIt) {
  // fraction of the steps of [0.5 s, 1 s] with a switch closed, module 1's pitch at
  // `pitch_deg` (< 0: a peak at the joint, both ends down: the head dips;
  // > 0: both ends up: the head lifts); *seen: every bit set in any step
  auto touched = [](double pitch_deg, uint16_t* seen) {
    WorldConfig c;
    c.head_position = Eigen::Vector3d(0, 0, 0.0126);
    World w = world_of(c, {"touch", "rotation", "rotation", "rotation"});
    w.set_servo_setpoint(1, 0, pitch_deg * kRadPerDeg);
    run(w, 0.5);
    int n = 0;
    *seen = 0;
    for (int k = 0; k < 1000; ++k) {
      w.step();
      const uint16_t in = sample(w, 0).digital_in;
      *seen |= in;
      n += (in & 7u) != 0;
    }
    return n / 1000.0;
  };
  uint16_t seen = 0;
  // straight on its rings: the 20 mm cover hangs 2.5 mm above the floor
  EXPECT_EQ(touched(0, &seen), 0.0);
  const double dipped = touched(-20, &seen);
  EXPECT_EQ(seen, 6u);  // the floor is below: switches 1 and 2 (120 and 240 degrees), never 0 (on top)
  EXPECT_EQ(touched(20, &seen), 0.0);
  std::printf("touch: head dipped: %.3f of the steps\n", dipped);
  EXPECT_GT(dipped, 0.95);  // pressed by a servo, the contact may open for a step now and then
}

TEST(TouchSensor, LoneModuleTipsOntoItsCoverAndReadsNothingInTheAir) {
  WorldConfig c;
  c.head_position = Eigen::Vector3d(0, 0, 0.0126);
  World on_floor = world_of(c, {"touch"});
  run(on_floor, 0.5);  // centre of mass ahead of the ring: it tips forward onto the cover
  EXPECT_EQ(sample(on_floor, 0).digital_in, 6u);  // switches 1 and 2: the floor is below
  on_floor.set_module_powered(0, false);
  EXPECT_EQ(sample(on_floor, 0).digital_in, 0u);  // unpowered reads nothing
  c.head_position.z() = 0.2;
  World lifted = world_of(c, {"touch"});
  lifted.pin_body(0, 1);
  for (int k = 0; k < 1000; ++k) {
    lifted.step();
    ASSERT_EQ(sample(lifted, 0).digital_in, 0u) << "step " << k;
  }
}

// The three switches tell where the cover was touched: a lone module rolled
// about its axis tips forward onto its cover, so the floor meets the cover
// at the module-frame direction of "down"; the switches within 80 degrees of
// it close (switch k at 120 k degrees from the module's top, towards its
// left). Pointed down onto the floor, the push is along the axis: all three.
// the touch module's frame -> world, from its cover (a cylinder turned by 90
// degrees about y in the module frame: touch.yaml)
Eigen::Quaterniond touch_module_orientation(const World& w) {
  const Eigen::Vector4d q = w.body_state(0, 0).quaternion_wxyz;
  const Eigen::Quaterniond cover(q[0], q[1], q[2], q[3]);
  return cover * Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY())).conjugate();
}

TEST(TouchSensor, TheSwitchesOnTheSideOfTheContactClose) {
  int checked = 0;
  for (int roll = 0; roll < 360; roll += 15) {
    WorldConfig c;
    c.head_position = Eigen::Vector3d(0, 0, 0.0126);
    c.roll_rad = roll * kRadPerDeg;
    World w = world_of(c, {"touch"});
    run(w, 0.5);
    const uint16_t in = sample(w, 0).digital_in;
    // where the floor is in the module frame: world down seen from the module
    const Eigen::Quaterniond q = touch_module_orientation(w);
    const Eigen::Vector3d down = q.conjugate() * Eigen::Vector3d(0, 0, -1);
    const double dir = std::atan2(down.y(), down.z()) / kRadPerDeg;
    uint16_t want = 0;
    for (int k = 0; k < 3; ++k) {
      const double off = std::remainder(dir - 120.0 * k, 360.0);
      if (std::fabs(off) <= 80) want |= static_cast<uint16_t>(1u << k);
    }
    // within 2 degrees of a sector's edge either answer is right
    bool near_edge = false;
    for (int k = 0; k < 3; ++k)
      near_edge = near_edge || std::fabs(std::fabs(std::remainder(dir - 120.0 * k, 360.0)) - 80) < 2;
    std::printf("roll %3d: floor at %7.2f deg in the module frame, switches %u (expected %u)\n", roll, dir, in,
                want);
    if (near_edge) continue;
    EXPECT_EQ(in, want) << "roll " << roll;
    ++checked;
  }
  EXPECT_GE(checked, 20);
  {  // upright: below is 180 degrees, switches 1 and 2; upside down: switch 0
    WorldConfig c;
    c.head_position = Eigen::Vector3d(0, 0, 0.0126);
    World up = world_of(c, {"touch"});
    run(up, 0.5);
    EXPECT_EQ(sample(up, 0).digital_in, 0b110u);
    c.roll_rad = M_PI;
    World down = world_of(c, {"touch"});
    run(down, 0.5);
    EXPECT_EQ(sample(down, 0).digital_in, 0b001u);
    c.roll_rad = M_PI / 2;   // rolled a quarter turn: is its left or its right below?
    World side = world_of(c, {"touch"});
    run(side, 0.5);
    const Eigen::Vector3d below = touch_module_orientation(side).conjugate() * Eigen::Vector3d(0, 0, -1);
    EXPECT_EQ(sample(side, 0).digital_in, below.y() > 0 ? 0b010u : 0b100u);   // 120 (left) or 240 (right)
  }
  {  // head-on: pointing down onto the floor, the push is along the axis
    WorldConfig c;
    c.head_position = Eigen::Vector3d(0, 0, 0.0005);
    c.head_orientation = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()));   // x down
    World w = world_of(c, {"touch"});
    uint16_t first = 0;
    for (int k = 0; k < 400 && first == 0; ++k) {
      w.step();
      first = sample(w, 0).digital_in;
    }
    EXPECT_EQ(first, 0b111u);
  }
}

// --- accelerometer -------------------------------------------------------------

// the touch module's accelerometer (ADC 0, 1, 2 = module x, y, z) held still
// in the air in a given orientation of the module
Eigen::Vector3d held_reading(const Eigen::Quaterniond& orientation) {
  WorldConfig c;
  c.head_position = Eigen::Vector3d(0, 0, 0.3);
  c.head_orientation = orientation;
  World w = world_of(c, {"touch"});
  w.pin_body(0, 1);
  run(w, 0.1);
  const ModuleSample s = sample(w, 0);
  EXPECT_EQ(s.n_adc, 3);
  return Eigen::Vector3d(s.adc[0], s.adc[1], s.adc[2]);
}

// the switches from the resultant push on the cover: three switches at 0,
// 120, 240 degrees (0 = the module's up, 90 = its left), 80 degrees each way
TEST(TouchSensor, TheSwitchesFeelTheResultantPush) {
  ModuleChannels::Touch t;
  t.sectors = 3;
  t.first_rad = 0;
  t.half_width_rad = 80 * kRadPerDeg;
  EXPECT_EQ(touch_sectors(t, Eigen::Vector3d(0, 0, 1)), 6u);    // the floor pushes up: the obstacle below
  EXPECT_EQ(touch_sectors(t, Eigen::Vector3d(0, 0, -1)), 1u);   // the ceiling: switch 0 alone
  EXPECT_EQ(touch_sectors(t, Eigen::Vector3d(0, -1, 0)), 2u);   // pushed right: the obstacle on the left, 30 off switch 1
  EXPECT_EQ(touch_sectors(t, Eigen::Vector3d(-1, 0, 0)), 7u);   // a wall ahead
  // a split's wedge met in the middle: its two faces push back and to
  // either side; together they push along the axis
  const Eigen::Vector3d left_face(-0.46, 0.89, 0), right_face(-0.46, -0.89, 0);
  EXPECT_EQ(touch_sectors(t, left_face), 4u);                     // one face alone: the obstacle on the right
  EXPECT_EQ(touch_sectors(t, left_face + right_face), 7u);
  // pinched between two walls across the axis: balanced, no tilt
  EXPECT_EQ(touch_sectors(t, Eigen::Vector3d(0, 0.05, -0.1)), 0u);
  // the module's frame turned from the body's: rolled 90 degrees, the body's
  // up is the module's left
  t.module_from_body.linear() = Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  EXPECT_EQ(touch_sectors(t, Eigen::Vector3d(0, 0, -1)), touch_sectors(ModuleChannels::Touch{t.body, t.bit, 3, 0, t.half_width_rad}, Eigen::Vector3d(0, 1, 0)));
}

TEST(Accelerometer, ReadsGravityInThreeOrientations) {
  const double tol = 2.0;  // counts: rounding and noise (0.003 g = 0.5 count rms)
  // level: z up
  Eigen::Vector3d r = held_reading(Eigen::Quaterniond::Identity());
  EXPECT_NEAR(r.x(), 512, tol);
  EXPECT_NEAR(r.y(), 512, tol);
  EXPECT_NEAR(r.z(), kUp, tol);
  // nose up: the module's x points up
  r = held_reading(Eigen::Quaterniond(Eigen::AngleAxisd(-90 * kRadPerDeg, Eigen::Vector3d::UnitY())));
  EXPECT_NEAR(r.x(), kUp, tol);
  EXPECT_NEAR(r.y(), 512, tol);
  EXPECT_NEAR(r.z(), 512, tol);
  // rolled onto its right side: y (left) points up
  r = held_reading(Eigen::Quaterniond(Eigen::AngleAxisd(90 * kRadPerDeg, Eigen::Vector3d::UnitX())));
  EXPECT_NEAR(r.x(), 512, tol);
  EXPECT_NEAR(r.y(), kUp, tol);
  EXPECT_NEAR(r.z(), 512, tol);
  // upside down
  r = held_reading(Eigen::Quaterniond(Eigen::AngleAxisd(180 * kRadPerDeg, Eigen::Vector3d::UnitX())));
  EXPECT_NEAR(r.z(), kDown, tol);
  // tilted 30 degrees nose down: x reads -sin 30 g, z cos 30 g (paper eqs 6-7)
  r = held_reading(Eigen::Quaterniond(Eigen::AngleAxisd(30 * kRadPerDeg, Eigen::Vector3d::UnitY())));
  EXPECT_NEAR(r.x(), 512 - 0.5 * (kUp - 512), tol);
  EXPECT_NEAR(r.z(), 512 + std::cos(30 * kRadPerDeg) * (kUp - 512), tol);
}

// lying on the floor in a chain it reads 1 g up; falling freely it reads 0 g;
// pushed at 1 g in weightlessness it reads +1 g along the push
TEST(Accelerometer, MeasuresSpecificForce) {
  WorldConfig c;
  c.head_position = Eigen::Vector3d(0, 0, 0.0126);
  World flat = world_of(c, {"touch", "rotation"});
  run(flat, 0.5);
  ModuleSample s = sample(flat, 0);
  EXPECT_NEAR(s.adc[0], 512, 2);
  EXPECT_NEAR(s.adc[1], 512, 2);
  EXPECT_NEAR(s.adc[2], kUp, 2);

  c.head_position.z() = 0.5;
  World falling = world_of(c, {"touch"});
  run(falling, 0.1);  // falls 5 cm, still in the air
  s = sample(falling, 0);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(s.adc[a], 512, 2) << "axis " << a;

  c.gravity_m_s2 = 0;
  World pushed = world_of(c, {"touch"});
  for (int k = 0; k < 200; ++k) {  // 0.1 s; the module is 10 g, so 0.0981 N is 1 g
    pushed.add_body_force(0, 1, Eigen::Vector3d(0.010 * 9.80665, 0, 0));
    pushed.step();
  }
  s = sample(pushed, 0);
  EXPECT_NEAR(s.adc[0], 512 + 512.0 / 3.0, 2);
  EXPECT_NEAR(s.adc[1], 512, 2);
  EXPECT_NEAR(s.adc[2], 512, 2);
}

// the noise is Gaussian with the file's spread, and a function of the seed
TEST(Accelerometer, NoiseIsSeededAndDeterministic) {
  auto readings = [](uint64_t seed) {
    WorldConfig c;
    c.seed = seed;
    c.head_position = Eigen::Vector3d(0, 0, 0.3);
    World w = world_of(c, {"touch"});
    w.pin_body(0, 1);
    run(w, 0.05);
    std::vector<int> out;
    for (int k = 0; k < 2000; ++k) {
      w.step();
      out.push_back(sample(w, 0).adc[0]);
    }
    return out;
  };
  const std::vector<int> a = readings(7), b = readings(7), other = readings(8);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, other);
  double mean = 0, var = 0;
  for (int v : a) mean += v / 2000.0;
  for (int v : a) var += (v - mean) * (v - mean) / 2000.0;
  // 0.003 g rms = 0.51 counts, plus the rounding (1/sqrt(12) = 0.29): 0.59
  std::printf("x axis at rest: mean %.3f counts, rms noise %.3f counts\n", mean, std::sqrt(var));
  EXPECT_NEAR(mean, 512, 0.1);
  EXPECT_NEAR(std::sqrt(var), 0.59, 0.1);
}

TEST(Accelerometer, UnpoweredReadsZero) {
  WorldConfig c;
  c.head_position = Eigen::Vector3d(0, 0, 0.0126);
  World w = world_of(c, {"support"});
  run(w, 0.5);
  ModuleSample s = sample(w, 0);
  EXPECT_EQ(s.n_adc, 4);  // motor current on ADC 0, accelerometer on 1..3
  EXPECT_NEAR(s.adc[3], kUp, 3);
  w.set_module_powered(0, false);
  s = sample(w, 0);
  EXPECT_EQ(s.n_adc, 4);
  for (int a = 0; a < 4; ++a) EXPECT_EQ(s.adc[a], 0);
}

// --- traveller: wheel encoders and wheel friction ------------------------------

constexpr double kWheelRadius = 0.006;  // traveller.yaml
constexpr double kCountsPerRev = 360;

double wheel_distance_m(int32_t counts) { return counts / kCountsPerRev * 2 * kPi * kWheelRadius; }

// two docked travellers rest on their four lower wheels; towed along the
// floor, the wheels that touch it count the distance travelled within 5%
// (rolling without slip: within 1%); the top wheels, touching nothing, stay
// still (which is why the paper's firmware adds the largest increment)
TEST(Traveller, EncodersCountTheDistanceWhileTheWheelsTouch) {
  for (const double heading_deg : {0.0, 45.0}) {
    WorldConfig c;
    c.head_position = Eigen::Vector3d(0, 0, 0.0092);  // wheels 0.15 mm above the floor
    c.heading_rad = heading_deg * kRadPerDeg;
    World w = world_of(c, {"traveller", "traveller"});
    run(w, 0.3);  // settle on the four lower wheels
    const ModuleSample a0 = sample(w, 0), b0 = sample(w, 1);
    ASSERT_EQ(a0.n_counters, 3);
    const Eigen::Vector3d p0 = w.body_state(0, 0).position;
    const Eigen::Vector3d dir(std::cos(c.heading_rad), std::sin(c.heading_rad), 0);
    for (int k = 0; k < 3000; ++k) {  // 1.5 s at 5 mN: the wheel friction limits it to ~9 cm/s
      w.add_body_force(0, 0, 0.005 * dir);
      w.step();
    }
    run(w, 0.5);  // and rolling to a stop
    const double travelled = (w.body_state(0, 0).position - p0).dot(dir);
    for (int m = 0; m < 2; ++m) {
      const ModuleSample s0 = m == 0 ? a0 : b0, s1 = sample(w, m);
      double d[3];
      for (int e = 0; e < 3; ++e) d[e] = wheel_distance_m(s1.counter[e] - s0.counter[e]);
      std::printf(
          "heading %.0f deg: travelled %.1f mm; module %d encoders top %.1f, right %.1f, "
          "left %.1f mm\n",
          heading_deg, travelled * 1e3, m, d[0] * 1e3, d[1] * 1e3, d[2] * 1e3);
      EXPECT_GT(travelled, 0.05);
      EXPECT_NEAR(d[1], travelled, 0.05 * travelled);
      EXPECT_NEAR(d[2], travelled, 0.05 * travelled);
      EXPECT_EQ(s1.counter[0] - s0.counter[0], 0);
      EXPECT_NEAR(std::max({d[0], d[1], d[2]}), travelled, 0.01 * travelled);
    }
  }
}

// the wheel friction is a torque -c w: a constant torque T spins a free wheel
// up to w = T / c, and once released it coasts w0 I / c further
TEST(Traveller, WheelFrictionIsProportionalToSpeed) {
  const double c_fric = 5e-7;                           // traveller.yaml, N m s/rad
  const double inertia = 0.5 * 0.0006 * 0.006 * 0.006;  // the wheel about its axle
  const double torque = 2e-5;                           // N m: w_ss = 40 rad/s
  WorldConfig c;
  c.gravity_m_s2 = 0;
  c.head_position = Eigen::Vector3d(0, 0, 0.3);
  World w = world_of(c, {"traveller"});
  w.pin_body(0, 0);
  const Eigen::Vector3d axle(0, -1, 0);  // the top wheel's (traveller.yaml)
  auto spin = [&](double seconds) {
    for (int k = 0; k < std::lround(seconds * 2000); ++k) {
      w.add_body_torque(0, 1, torque * axle);
      w.step();
    }
  };
  spin(0.3);  // 14 time constants: at speed
  const int32_t a = sample(w, 0).counter[0];
  spin(1.0);
  const int32_t b = sample(w, 0).counter[0];
  run(w, 0.5);  // released
  const int32_t e = sample(w, 0).counter[0];
  const double rate = (b - a) / kCountsPerRev * 2 * kPi;   // rad/s
  const double coast = (e - b) / kCountsPerRev * 2 * kPi;  // rad
  std::printf(
      "wheel: %.3f rad/s under %.1e N m (expected %.3f), coasted %.4f rad (expected %.4f)\n", rate,
      torque, torque / c_fric, coast, torque / c_fric * inertia / c_fric);
  EXPECT_NEAR(rate, torque / c_fric, 0.01 * torque / c_fric);
  EXPECT_NEAR(coast, torque / c_fric * inertia / c_fric, 0.1 * torque / c_fric * inertia / c_fric);
  // the other two wheels did not move
  EXPECT_EQ(sample(w, 0).counter[1], 0);
  EXPECT_EQ(sample(w, 0).counter[2], 0);
}

}  // namespace
}  // namespace chainsim
