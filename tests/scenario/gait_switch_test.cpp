// Paper 6.7 (a chain that switches gaits on a condition it senses): H S E S
// in scenes/gait-switch-HSES.yaml, a pipe of 40 mm bore running level, then
// turning up into a 30-degree slope. The helicoidal module drives the chain
// on the level; where the pipe climbs the screw labours (its current at
// stall) and the central control starts the supports' and extensions'
// inchworm, the screw still driving, trying the screw alone again every
// switch_ms. Controls: the screw alone stalls at the slope's foot, and the
// inchworm with the screw idle (back-driven) stalls in the elbow.
// docs/firmware.md, "Switching gaits on a sensed condition (paper 6.7)".
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "scenario_util.h"

using namespace scenario;

namespace {

using Trace = std::map<std::string, std::vector<double>>;

// the elbow turns up at x = 0.45 m; its end (30 degrees, bend radius 0.3 m)
// is 4.0 cm above the level leg, the slope's foot
constexpr double kSlopeFootZ = 0.3 * (1 - 0.8660254);

// the first time the H's pig is z_m above the level leg, -1 if never
double time_up(const Trace& tr, double z_m) {
  const auto &t = tr.at("t_s"), &z = tr.at("m0.pig.z");
  for (size_t i = 0; i < t.size(); ++i)
    if (z[i] > z_m) return t[i];
  return -1;
}

// the pig's x at time t_s (the first trace row at or after it)
double x_at(const Trace& tr, double t_s) {
  const auto& t = tr.at("t_s");
  for (size_t i = 0; i < t.size(); ++i)
    if (t[i] >= t_s - 1e-9) return tr.at("m0.pig.x")[i];
  return tr.at("m0.pig.x").back();
}

const std::pair<std::string, std::string> kQuickStep = {"  solver: exact\n", ""};

}  // namespace

// The verdict, with the solver converged (the scene) and under QuickStep's
// 30 iterations: on the level the screw alone drives the chain (over 2 cm/s);
// at the slope its current is taken for labouring once it is in the elbow,
// the inchworm starts, the screw is tried alone every 6 s and labours again;
// at 30 s the H is more than 3 cm up the slope (7 cm above the level).
TEST(GaitSwitch, HSESSwitchesToTheInchwormWhereTheScrewStallsAndClimbs) {
  for (const bool exact : {true, false}) {
    SCOPED_TRACE(exact ? "exact" : "QuickStep");
    std::vector<std::pair<std::string, std::string>> edits;
    if (!exact) edits.push_back(kQuickStep);
    const Outcome o = run_scene("gait-switch", "gait-switch-HSES", 30, edits);
    ASSERT_EQ(o.exit_code, 0) << o.stderr_text;
    const std::string log = central_log(o, 4);
    const std::vector<double> inch = log_times(log, "switch: inchworm"), heli = log_times(log, "switch: helicoidal");
    const Trace tr = read_trace(o.dir + "/trace.csv");
    const double level_speed = (x_at(tr, 4.0) - x_at(tr, 0.5)) / 3.5;
    const double z = tr.at("m0.pig.z").back(), t_up = time_up(tr, 0.05);
    std::printf("[ switch ] H S E S%s: %.2f cm/s on the level, inchworm at %.2f s (%zu times), 5 cm up at %.2f s, "
                "H at x %.3f z %.3f at 30 s\n",
                exact ? ", exact" : "", level_speed * 100, inch.empty() ? -1.0 : inch[0], inch.size(), t_up,
                tr.at("m0.pig.x").back(), z);
    ASSERT_FALSE(inch.empty()) << log;
    EXPECT_GT(level_speed, 0.02);               // the screw alone on the level
    EXPECT_GT(inch[0], 4.5) << log;             // the H in the elbow, not on the level
    EXPECT_LT(inch[0], 10.0) << log;
    EXPECT_GT(x_at(tr, inch[0]), 0.50);         // (its centre past the elbow's start, 0.45 m)
    ASSERT_GE(heli.size(), 2u) << log;          // the screw tried alone again, 6 s later each time
    ASSERT_GE(inch.size(), heli.size()) << log;
    for (size_t k = 0; k < heli.size(); ++k) EXPECT_NEAR(heli[k] - inch[k], 6.0, 1e-6) << k;
    // and labouring again: the inchworm starts after each retry
    EXPECT_GE(inch.size(), 3u) << log;
    for (size_t k = 1; k < inch.size(); ++k) EXPECT_GT(inch[k], heli[k - 1]) << k;
    EXPECT_GT(z, kSlopeFootZ + 0.03);           // up the slope
    EXPECT_GT(t_up, 0);
  }
}

// Controls (the scene's exact solver): the screw alone (no switching) stalls
// at the slope's foot at stall current; the inchworm alone (gait 8, the
// screw idle and back-driven) stalls in the elbow. Neither gets to the
// slope's foot (4 cm above the level leg; they stop 0.7 and 1.8 cm up) in
// 30 s, where the switching chain is 9 cm up.
TEST(GaitSwitch, NeitherGaitAloneGetsUpTheSlope) {
  struct Case {
    const char* name;
    std::vector<std::pair<std::string, std::string>> edits;
  };
  for (const Case& k : {Case{"screw alone", {{"switch_counts: 750", "switch_counts: 0"}}},
                        Case{"inchworm alone", {{"gait: 9", "gait: 8"}, {"switch_counts: 750", "switch_counts: 0"}}}}) {
    SCOPED_TRACE(k.name);
    const Outcome o = run_scene("gait-switch", "gait-switch-HSES", 30, k.edits);
    ASSERT_EQ(o.exit_code, 0) << o.stderr_text;
    const std::string log = central_log(o, 4);
    EXPECT_EQ(log.find("switch:"), std::string::npos) << log;
    const Trace tr = read_trace(o.dir + "/trace.csv");
    const double z = tr.at("m0.pig.z").back(), x = tr.at("m0.pig.x").back();
    // how far it moved in the last 8 s
    const double moved = x - x_at(tr, 22.0);
    std::printf("[ switch ] H S E S, exact, %s: H at x %.3f z %.3f at 30 s, %.1f mm in the last 8 s, %.3f A\n", k.name, x,
                z, moved * 1e3, tr.at("m0.s0.current_a").back());
    EXPECT_LT(z, kSlopeFootZ);
    EXPECT_LT(moved, 0.003);  // stalled
    if (std::string(k.name) == "screw alone") {
      EXPECT_GT(tr.at("m0.s0.current_a").back(), 0.9 * 5.0 / 12.0);  // at stall
    }
  }
}
