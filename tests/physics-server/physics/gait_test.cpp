// The key physics test: a chain of 8 rotation modules on the plane crawls with
// a vertical travelling wave on its pitch servos, driven directly (no
// firmware), set-points updated every 10 ms, dt = 500 us.
//
//   pitch_k(t) = A sin(omega t + sign k phi),  k = 0 (head) .. 7
//   A = 20 deg, omega = 14 rad/s, phi = 1.36 rad (the paper's GA optimum for
//   omega and phi, section 6.3; its 71 deg amplitude was for undulating
//   terrain between walls)
//   sign = +1 moves the chain forward (towards the head, +x), -1 backward.
//
// The yaw servos hold a static zig-zag: +25 deg on the head's yaw joint,
// then -50, +50, -50, ... (the chain's mean axis stays along the heading).
// Why: with every yaw at 0 the chain is a planar string of round bodies: all
// its ground contacts lie on one line, so any lifted arch makes it an inverted
// pendulum about that line. It rolls over within about a second, whatever the
// amplitude (measured: 8 to 40 degrees, all roll onto their side, after which
// the pitch wave is a lateral wave that goes nowhere on isotropic friction).
// The paper ran this gait between walls "to prevent the robot from falling to
// the side" (6.3). The zig-zag spreads the contacts sideways (about +-10 mm)
// and the chain stays upright; +-40 deg is the smallest that held in our sweep,
// +-50 deg leaves margin.
//
// Friction: mu = 0.8 (Material default; plastic rings on a rough floor). The
// distance hardly depends on it: 0.16 to 0.18 m in 10 s for mu 0.3 to 1.0 at
// A = 15 deg, omega = 12 rad/s, phi = 1.4 rad.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>

#include "model/units.h"
#include "physics/world.h"
#include "world_of.h"

namespace chainsim {
namespace {

struct Gait {
  double amplitude_deg = 20;
  double omega_rad_s = 14;
  double phase_rad = 1.36;
  int sign = +1;
  double yaw_zigzag_deg = 50;
};

struct Outcome {
  double forward_m;   // along the heading
  double lateral_m;   // to the left of the heading
  double max_mean_roll_deg;
};

Outcome crawl(const Gait& g, double heading, double mu, uint64_t seed, double seconds) {
  WorldConfig c;
  c.head_position = Eigen::Vector3d(0, 0, 0.0126);  // the rings' radius + 0.1 mm
  c.heading_rad = heading;
  c.ground.mu = mu;
  c.seed = seed;
  World w = world_of(c, std::vector<std::string>(8, "rotation"));
  for (int m = 0; m < 8; ++m)
    w.set_servo_setpoint(
        m, 1, (m == 0 ? 0.5 : (m % 2 ? -1.0 : 1.0)) * g.yaw_zigzag_deg * kRadPerDeg);
  const Eigen::Vector3d start = w.chain_com();
  const int steps = static_cast<int>(std::lround(seconds / 5e-4));
  double max_roll = 0;
  for (int k = 0; k < steps; ++k) {
    if (k % 20 == 0) {  // set-points every 10 ms
      const double t = w.time_us() * 1e-6;
      for (int m = 0; m < 8; ++m)
        w.set_servo_setpoint(m, 0,
                             g.amplitude_deg * kRadPerDeg *
                                 std::sin(g.omega_rad_s * t + g.sign * m * g.phase_rad));
      // mean over the modules of the tilt of the capsules' pitch axes: ~90
      // when the chain has rolled onto its side
      double mean = 0;
      for (int m = 0; m < 8; ++m) {
        const Eigen::Vector4d q = w.body_state(m, 1).quaternion_wxyz;
        const Eigen::Quaterniond qq(q[0], q[1], q[2], q[3]);
        mean += (qq * Eigen::Vector3d::UnitY()).z() / 8;
      }
      max_roll = std::max(max_roll, std::asin(std::min(1.0, std::fabs(mean))) / kRadPerDeg);
    }
    w.step();
  }
  const Eigen::Vector3d d = w.chain_com() - start;
  const Eigen::Vector3d fwd(std::cos(heading), std::sin(heading), 0);
  const Eigen::Vector3d left(-std::sin(heading), std::cos(heading), 0);
  return {d.dot(fwd), d.dot(left), max_roll};
}

TEST(Gait, EightRotationModulesCrawlForward) {
  const Outcome o = crawl(Gait{}, 0.0, 0.8, 1, 10.0);
  std::printf("forward gait: %.3f m forward, %.3f m lateral in 10 s, max mean roll %.1f deg\n",
              o.forward_m, o.lateral_m, o.max_mean_roll_deg);
  EXPECT_GT(o.forward_m, 0.05);
  EXPECT_LT(std::fabs(o.lateral_m), o.forward_m / 2);
  EXPECT_LT(o.max_mean_roll_deg, 45);  // upright
}

TEST(Gait, OppositePhaseSignCrawlsBackward) {
  Gait g;
  g.sign = -1;
  const Outcome o = crawl(g, 0.0, 0.8, 1, 10.0);
  std::printf("backward gait: %.3f m forward, %.3f m lateral in 10 s, max mean roll %.1f deg\n",
              o.forward_m, o.lateral_m, o.max_mean_roll_deg);
  EXPECT_LT(o.forward_m, -0.05);
  EXPECT_LT(std::fabs(o.lateral_m), -o.forward_m / 2);
}

// the same gait pointed elsewhere, on a less grippy floor, another seed
TEST(Gait, ForwardIsRobustToHeadingFrictionAndSeed) {
  const Outcome o = crawl(Gait{}, 2.0, 0.5, 42, 10.0);
  std::printf("heading 2 rad, mu 0.5, seed 42: %.3f m forward, %.3f m lateral\n", o.forward_m,
              o.lateral_m);
  EXPECT_GT(o.forward_m, 0.05);
  EXPECT_LT(std::fabs(o.lateral_m), o.forward_m / 2);
}

}  // namespace
}  // namespace chainsim
