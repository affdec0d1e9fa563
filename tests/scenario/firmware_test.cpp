// The real firmware on the real server: the gait the central control commands
// over I2C, as seen in the trace. Discovery through the sync lines is checked
// by the test files in discovery/ (chainsim test).
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "scenario_util.h"

using namespace scenario;

namespace {


}  // namespace

TEST(Gait, ServoSetPointsFollowTheCommandedTravellingWave) {
  const std::string dir = temp_dir("gait");
  // amplitude 30 deg, 4 rad/s, 0.8 rad between neighbours, on the yaw servo
  const std::string scene = write_file(dir, "s.yaml",
                                       "chain: RRRR\nduration_s: 2\ncentral:\n  params: {gait: 1, amplitude_cdeg: "
                                       "3000, omega_mrad_s: 4000, phase_mrad: 800, axis: 1}\n");
  const Outcome o = run({scene}, dir);
  ASSERT_EQ(o.exit_code, 0) << o.stderr_text;
  auto tr = read_trace(o.dir + "/trace.csv");
  const auto& t = tr["t_s"];
  ASSERT_GT(t.size(), 150u);
  // the gait starts once discovery is over; find that start time t0 (ms grid) by best fit
  auto max_error = [&](double t0) {
    double worst = 0;
    for (size_t i = 0; i < t.size(); ++i) {
      if (t[i] < t0 + 0.05) continue;
      for (int k = 0; k < 4; ++k) {
        const double want = 30.0 * std::sin(4.0 * (t[i] - t0) + k * 0.8);
        worst = std::max(worst, std::fabs(tr["m" + std::to_string(k) + ".s1.setpoint_deg"][i] - want));
      }
    }
    return worst;
  };
  double best = 1e9, best_t0 = 0;
  for (int ms = 0; ms <= 200; ++ms) {
    const double e = max_error(ms * 1e-3);
    if (e < best) best = e, best_t0 = ms * 1e-3;
  }
  // set-points change every 10 ms control step: at 30 deg * 4 rad/s that is at most 1.2 deg stale
  EXPECT_LT(best, 1.3) << "best start time " << best_t0;
  EXPECT_LT(best_t0, 0.1);
  // the pitch servos are held at zero
  for (int k = 0; k < 4; ++k)
    for (double v : tr["m" + std::to_string(k) + ".s0.setpoint_deg"]) EXPECT_EQ(v, 0.0);
}
