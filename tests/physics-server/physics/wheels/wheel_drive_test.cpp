// The helicoidal module's drive through its wheels (scenes/modules/
// helicoidal.yaml, wheel_contacts.h): thrust only through wheels on the wall,
// each limited by friction on its own normal force; the drive's free speed
// and its force-speed line from the motor and the helix.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "model/module_def.h"
#include "model/units.h"
#include "physics/placement.h"
#include "physics/world.h"
#include "world_of.h"

namespace chainsim {
namespace {


// the built-in helicoidal module in a straight pipe of `diameter`, `slope`
WorldConfig pipe_scene(const ModuleDef& h, double diameter, double slope_deg, double gravity = 9.81) {
  WorldConfig c;
  c.module_types = {h};
  c.gravity_m_s2 = gravity;
  c.environment.type = EnvironmentType::Pipe;
  c.environment.pipe.inner_diameter_m = diameter;
  PipeSegment s;
  s.length_m = 0.4;
  s.slope_deg = slope_deg;
  c.environment.pipe.segments = {s};
  c.ground.mu = 0.3;
  place_types_at_pipe_entry(&c, {h.type}, 0.1);
  return c;
}

double along(const World& w, double slope_deg) {
  const double a = slope_deg * kPi / 180;
  return w.body_state(0, 0).position.dot(Eigen::Vector3d(std::cos(a), 0, std::sin(a)));
}

void run(World& w, double seconds) {
  const int n = static_cast<int>(std::lround(seconds / (w.dt_us() * 1e-6)));
  for (int k = 0; k < n; ++k) w.step();
}

const WheelSetDef& head_wheels(const ModuleDef& d) {
  for (const WheelSetDef& s : d.wheels)
    if (s.helix_deg > 0 && s.helix_deg < 90) return s;
  throw std::runtime_error("no helical wheel set");
}

const ActuatorDef& motor(const ModuleDef& d) {
  for (const ActuatorDef& a : d.actuators)
    if (a.type == ActuatorType::DcMotor) return a;
  throw std::runtime_error("no dc motor");
}

TEST(WheelDrive, ModuleFileDeclaresAHeadOnAHingeWithWheels) {
  const ModuleDef h = builtin_module_def("helicoidal");
  EXPECT_EQ(h.wheels.size(), 2u);
  EXPECT_EQ(motor(h).type, ActuatorType::DcMotor);
  World w = world_of(pipe_scene(h, 0.04, 0), {h.type});
  EXPECT_EQ(w.wheel_count(0), 6);
  EXPECT_EQ(w.servo_count(0), 1);
  EXPECT_EQ(w.servo_kind(0, 0), ServoKind::DcMotor);  // driven -1..1 like a screw drive
}

// the module with arms too short to reach any wall (within its own
// outline): lying on the pipe's bottom, its body pressed on the wall by its
// weight, and then by 0.5 N more from outside, it gets no thrust from its
// drive; no wheel has a force; the head spins (the motor runs unloaded)
ModuleDef short_arms() {
  ModuleDef h = builtin_module_def("helicoidal");
  for (WheelSetDef& s : h.wheels) {
    s.reach_min_m = 0.005;
    s.reach_max_m = 0.010;
  }
  return h;
}

TEST(WheelDrive, WheelsOffTheWallGiveNoForceAndNoThrust) {
  const ModuleDef h = short_arms();
  World w = world_of(pipe_scene(h, 0.04, 0), {h.type});
  run(w, 0.5);
  const double x0 = along(w, 0);
  w.set_servo_setpoint(0, 0, 1.0);
  run(w, 1.5);
  for (int k = 0; k < w.wheel_count(0); ++k) {
    EXPECT_FALSE(w.wheel_state(0, k).on) << w.wheel_name(0, k);
    EXPECT_EQ(w.wheel_state(0, k).normal_n, 0.0);
  }
  EXPECT_NEAR(along(w, 0) - x0, 0.0, 0.2e-3);
  EXPECT_GT(w.servo_rate(0, 0), 0.5 * motor(h).v_free_m_s);
}

TEST(WheelDrive, ABodyPressedOnTheWallGetsNoThrust) {
  const ModuleDef h = short_arms();
  World w = world_of(pipe_scene(h, 0.04, 0), {h.type});
  run(w, 0.5);
  const double x0 = along(w, 0);
  w.set_servo_setpoint(0, 0, 1.0);
  for (int k = 0; k < 3000; ++k) {
    w.add_body_force(0, 0, Eigen::Vector3d(0, 0, -0.5));
    w.step();
  }
  EXPECT_NEAR(along(w, 0) - x0, 0.0, 0.2e-3);
  // the same module with its wheels on the wall does move
  World on = world_of(pipe_scene(builtin_module_def("helicoidal"), 0.04, 0), {"helicoidal"});
  run(on, 0.5);
  const double y0 = along(on, 0);
  on.set_servo_setpoint(0, 0, 1.0);
  run(on, 1.5);
  EXPECT_GT(along(on, 0) - y0, 0.02);
}

// no gravity, no load: v = w_free r tan(helix) (r = 20 mm, the bore's radius)
TEST(WheelDrive, FreeSpeedIsTheHelixTimesTheMotorsFreeSpeed) {
  const ModuleDef h = builtin_module_def("helicoidal");
  World w = world_of(pipe_scene(h, 0.04, 0, 0.0), {h.type});
  w.set_servo_setpoint(0, 0, 1.0);
  run(w, 1.0);
  const double x0 = along(w, 0);
  run(w, 1.0);
  const double v = along(w, 0) - x0;
  const double ideal = motor(h).v_free_m_s * 0.02 * std::tan(head_wheels(h).helix_deg * kPi / 180);
  std::printf("free speed %.5f m/s, w_free r tan(helix) %.5f m/s\n", v, ideal);
  EXPECT_NEAR(v, ideal, 0.01 * ideal);
  for (int k = 0; k < w.wheel_count(0); ++k) EXPECT_TRUE(w.wheel_state(0, k).on);
}

// Climbing a vertical pipe with a load hung on the pig: the drive (made 10
// times stronger, so that the motor is never the limit) lifts it while the
// load is below the wheels' grip, sum over the head's wheels of mu N cos(helix),
// and slides back above it. Every wheel's force across it stays within
// mu times its own normal force.
TEST(WheelDrive, ThrustIsLimitedByMuTimesEachWheelsNormalForce) {
  ModuleDef h = builtin_module_def("helicoidal");
  for (ActuatorDef& a : h.actuators)
    if (a.type == ActuatorType::DcMotor) a.fmax_n *= 10;
  const WheelSetDef& head = head_wheels(h);
  const double cos_helix = std::cos(head.helix_deg * kPi / 180);
  auto climb = [&](double load_factor, double* grip_out) {
    World w = world_of(pipe_scene(h, 0.04, 90), {h.type});
    w.set_servo_setpoint(0, 0, 1.0);
    run(w, 0.3);
    // grip of the head's wheels (their normal forces barely depend on the load)
    double grip = 0;
    for (int k = 0; k < w.wheel_count(0); ++k)
      if (w.wheel_name(0, k).rfind(head.name, 0) == 0)
        grip += head.mu * w.wheel_state(0, k).normal_n * cos_helix;
    const double weight = 0.010 * 9.81;
    const double load = load_factor * grip - weight;  // hung below, besides its own weight
    const double z0 = along(w, 90);
    double worst = 0;
    for (int i = 0; i < 600; ++i) {
      w.add_body_force(0, 0, Eigen::Vector3d(0, 0, -load));
      w.step();
      for (int k = 0; k < w.wheel_count(0); ++k) {
        const World::WheelState s = w.wheel_state(0, k);
        worst = std::max(worst, std::fabs(s.across_n) - head.mu * s.normal_n);
      }
    }
    EXPECT_LT(worst, 1e-3) << "a wheel's friction beyond mu N by " << worst << " N";
    *grip_out = grip;
    return (along(w, 90) - z0) / 0.3;
  };
  double grip = 0;
  const double v_below = climb(0.8, &grip);
  const double v_above = climb(1.25, &grip);
  std::printf("grip %.3f N: at 0.8 grip %.4f m/s, at 1.25 grip %.4f m/s\n", grip, v_below, v_above);
  EXPECT_GT(grip, 0.5);
  EXPECT_GT(v_below, 0.005);
  EXPECT_LT(v_above, -0.005);
}

}  // namespace
}  // namespace chainsim

namespace chainsim {
namespace {

// a module type of one box body with no collision shape (pads touch for it)
ModuleDef box_module(const std::string& type, const Eigen::Vector3d& size_m, double mass_kg) {
  ModuleDef d;
  d.type = type;
  BodyDef b;
  b.name = "box";
  b.shape = Shape::Box;
  b.box_m = size_m;
  b.mass_kg = mass_kg;
  b.collides = false;
  d.bodies = {b};
  d.front.body = d.back.body = 0;
  return d;
}

// a 50 g plate (40 x 40 x 4 mm) standing on four friction pads at its
// corners (no collision shape of its own) on the floor
ModuleDef padded_plate(double mu) {
  ModuleDef d = box_module("padded_plate", Eigen::Vector3d(0.04, 0.04, 0.004), 0.05);
  for (int k = 0; k < 4; ++k) {
    PadDef p;
    p.name = "pad" + std::to_string(k);
    p.body = 0;
    p.position_m = Eigen::Vector3d(k % 2 ? 0.015 : -0.015, k / 2 ? 0.015 : -0.015, 0);
    p.direction = -Eigen::Vector3d::UnitZ();
    p.reach_m = 0.003;
    p.stiffness_n_m = 5000;
    p.damping_n_s_m = 2;
    p.mu = mu;
    d.pads.push_back(p);
  }
  return d;
}

// pushed sideways, it holds below mu m g and slides above; the pads' normal
// forces carry its weight
TEST(Pads, GripHoldsBelowMuNAndSlipsAbove) {
  const double mu = 0.5, weight = 0.05 * 9.81;
  for (const auto& [factor, holds] : {std::pair<double, bool>{0.8, true}, {1.2, false}}) {
    WorldConfig c;
    c.module_types = {padded_plate(mu)};
    c.head_position = Eigen::Vector3d(0.02, 0, 0.0029);
    World w = world_of(c, {"padded_plate"});
    run(w, 0.3);
    double n = 0;
    for (int k = 0; k < 4; ++k) {
      ASSERT_TRUE(w.wheel_state(0, k).on) << k;
      n += w.wheel_state(0, k).normal_n;
    }
    EXPECT_NEAR(n, weight, 0.02 * weight);
    const double x0 = w.body_state(0, 0).position.x();
    for (int k = 0; k < 1000; ++k) {
      w.add_body_force(0, 0, Eigen::Vector3d(factor * mu * weight, 0, 0));
      w.step();
    }
    const double moved = w.body_state(0, 0).position.x() - x0;
    std::printf("pads: push %.2f mu N: moved %.5f m in 0.5 s\n", factor, moved);
    if (holds)
      EXPECT_LT(std::fabs(moved), 1e-4);
    else
      EXPECT_GT(moved, 0.01);
  }
}

}  // namespace
}  // namespace chainsim

namespace chainsim {
namespace {

// The support module (scenes/modules/support.yaml) gripping a level pipe of
// 40 mm bore, arms driven fully open: pulled along the pipe by a force at
// its core for 0.5 s, how far it slides. The grip is friction on normal
// forces (the pads' and the core's own contact), so it has a limit: a pull
// below it holds, one above slides, and a wall of lower friction holds less.
double support_slide(double pull_n, double wall_mu, double pad_mu,
                     WorldConfig::Solver solver = WorldConfig::Solver::QuickStep) {
  ModuleDef s = builtin_module_def("support");
  for (PadDef& p : s.pads) p.mu = pad_mu;
  WorldConfig c;
  c.solver = solver;
  c.module_types = {s};
  c.environment.type = EnvironmentType::Pipe;
  c.environment.pipe.inner_diameter_m = 0.04;
  PipeSegment seg;
  seg.length_m = 0.4;
  c.environment.pipe.segments = {seg};
  c.ground.mu = wall_mu;
  place_types_at_pipe_entry(&c, {"support"}, 0.1);
  World w = world_of(c, {"support"});
  w.set_servo_setpoint(0, 0, kPi / 2);
  run(w, 1.0);  // the arms open (0.3 s) and the core settles on the wall
  const double x0 = w.body_state(0, 0).position.x();
  for (int k = 0; k < 1000; ++k) {
    w.add_body_force(0, 0, Eigen::Vector3d(pull_n, 0, 0));
    w.step();
  }
  return w.body_state(0, 0).position.x() - x0;
}

// a 10 g block (no collision shape) in a level pipe of 40 mm bore along
// +x from 0 to 0.4 m, no gravity, with one pad: the line from `origin` along
// `dir` (block frame = world at the start), reach 10 mm
World padded_block(const Eigen::Vector3d& at, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) {
  ModuleDef d = box_module("padded_block", Eigen::Vector3d(0.01, 0.01, 0.01), 0.01);
  PadDef p;
  p.name = "pad";
  p.body = 0;
  p.position_m = origin;
  p.direction = dir.normalized();
  p.reach_m = 0.010;
  p.stiffness_n_m = 5000;
  p.damping_n_s_m = 2;
  p.mu = 0.5;
  d.pads = {p};
  WorldConfig c;
  c.module_types = {d};
  c.gravity_m_s2 = 0;
  c.environment.type = EnvironmentType::Pipe;
  c.environment.pipe.inner_diameter_m = 0.04;
  PipeSegment seg;
  seg.length_m = 0.4;
  c.environment.pipe.segments = {seg};
  c.head_position = at;
  return world_of(c, {"padded_block"});
}

// a pad whose origin has gone into the wall (an arm's hinge while its module
// lies on the wall) still presses with its face, from the depth the face is
// at: it pushes the block back into the bore, gently (before, it let go
// until its origin came back and then pressed at once from the full depth)
TEST(Pads, OriginInTheWallStillPressesWithItsFace) {
  // origin 0.2 mm beyond the bore's 20 mm, the line at 30 degrees to the
  // axis: the face 5.2 mm beyond
  World w = padded_block(Eigen::Vector3d(0.2, 0, 0), Eigen::Vector3d(0, 0, 0.0202),
                         Eigen::Vector3d(std::cos(kPi / 6), 0, std::sin(kPi / 6)));
  w.step();
  ASSERT_TRUE(w.wheel_state(0, 0).on);
  EXPECT_GT(w.wheel_state(0, 0).normal_n, 1.0);
  double fastest = 0;
  for (int k = 0; k < 200; ++k) {
    w.step();
    fastest = std::max(fastest, w.body_state(0, 0).linear_velocity.norm());
  }
  // pushed down (towards the axis), away from the wall (no gravity: it
  // floats on), no faster than the pad's spring energy allows: 1/2 k d^2 =
  // 1/2 m v^2 gives 3.7 m/s for the 5.2 mm (before, starting from an origin
  // back in the bore, the pad pressed from its whole depth at ERP 0.83 per
  // step)
  const double z = w.body_state(0, 0).position.z();
  std::printf("pad with its origin in the wall: block moved %.4f m, fastest %.3f m/s\n", z, fastest);
  EXPECT_LT(z, -0.004);
  EXPECT_LT(fastest, 3.7);
}

// a pad whose face hangs past the pipe's open end touches nothing, though
// its line meets the wall before the end
TEST(Pads, FacePastAnOpenEndTouchesNothing) {
  const Eigen::Vector3d out(std::cos(kPi / 4), 0, std::sin(kPi / 4));
  // line from 16 mm off the axis at 45 degrees: meets the bore 5.7 mm along,
  // at x = 0.3985; the face (10 mm along) at x = 0.4016, past the exit at 0.4
  World past = padded_block(Eigen::Vector3d(0.3975, 0, 0), Eigen::Vector3d(-0.003, 0, 0.016), out);
  past.step();
  EXPECT_FALSE(past.wheel_state(0, 0).on);
  // 3 mm further in, the face inside the pipe's length: it presses
  World inside = padded_block(Eigen::Vector3d(0.3945, 0, 0), Eigen::Vector3d(-0.003, 0, 0.016), out);
  inside.step();
  EXPECT_TRUE(inside.wheel_state(0, 0).on);
  EXPECT_GT(inside.wheel_state(0, 0).normal_n, 1.0);
}

TEST(Pads, SupportGripHasAFrictionLimit) {
  // the inchworm's chain weighs 0.29 N: pulled forwards by that it holds
  // (backwards it creeps 2 mm in 0.5 s; unloaded 0.8 mm: docs/firmware.md)
  EXPECT_LT(std::fabs(support_slide(0.3, 0.6, 0.6)), 1e-3);
  // forwards (the arms' tips trail the hinges: the pull folds them) it slides
  // away at 4 N; backwards the arms wedge and it creeps a little (2 cm)
  EXPECT_GT(support_slide(4.0, 0.6, 0.6), 0.05);
  const double back = support_slide(-4.0, 0.6, 0.6);
  EXPECT_GT(back, -0.05);
  // on a wall and pads of half the friction the same pull pulls it out
  EXPECT_LT(support_slide(-4.0, 0.3, 0.3), -0.05);
  std::printf("support: pulled back by 4 N: slides %.4f m\n", back);
}

// The grip of a support well below its limit holds only as well as the
// solver converges: QuickStep's 30 iterations let the support creep under a
// steady pull (the inchworm loses speed by it: docs/firmware.md, "Inchworm";
// world.cpp), the exact solver holds it still.
TEST(Pads, AGripBelowItsLimitCreepsOnlyAsFarAsTheSolverIsUnconverged) {
  for (double pull : {0.3, -0.3, 1.0, -1.0}) {
    const double quick = support_slide(pull, 0.6, 0.6);
    const double exact = support_slide(pull, 0.6, 0.6, WorldConfig::Solver::Exact);
    std::printf("support pulled by %+.1f N for 0.5 s: slides %+.3f mm (QuickStep 30), %+.3f mm (exact)\n", pull,
                quick * 1e3, exact * 1e3);
    EXPECT_LT(std::fabs(exact), 2e-5) << "pull " << pull;   // measured: at most 0.007 mm
    if (std::fabs(pull) > 0.5) {
      EXPECT_GT(std::fabs(quick), 1e-3) << "pull " << pull;  // 3.0 and 6.4 mm
    }
  }
}

}  // namespace
}  // namespace chainsim
