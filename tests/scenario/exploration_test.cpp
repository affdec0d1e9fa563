// Exploration (paper 6.4): scenes/pipe-network.yaml, a pipe that climbs,
// turns left, then right, and ends in a split whose left outlet goes on.
// Nothing tells the chain where the turns are: each elbow's turn is sensed
// from the touch module, and at the split (a wall ahead: every switch) the
// junction policy takes the left outlet. The verdict is the model's: the
// chain passes both elbows and chooses the left outlet, then stalls at the
// split's wedge (docs/firmware.md, "Exploration").
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "scenario_util.h"

using namespace scenario;

namespace {

struct Bend {
  int world_deg = -1;  // the turn as gravity gives it (0 up, 90 left, 180 down, 270 right)
  std::string why;     // sensed, junction, given
};

// the central control's "elbow: bend at ms T toward dir_deg=D world_deg=W (why...)" lines
std::vector<Bend> bends(const std::string& log) {
  std::vector<Bend> out;
  const std::string key = "elbow: bend at ms ";
  for (size_t p = log.find(key); p != std::string::npos; p = log.find(key, p + 1)) {
    const std::string line = log.substr(p, log.find('\n', p) - p);
    Bend b;
    const size_t w = line.find("world_deg=");
    if (w != std::string::npos) b.world_deg = std::atoi(line.c_str() + w + 10);
    const size_t open = line.find('(');
    if (open != std::string::npos) b.why = line.substr(open + 1, line.find(')', open) - open - 1);
    out.push_back(b);
  }
  return out;
}

int angle_off(int a, int b) { return std::abs(((a - b) % 360 + 540) % 360 - 180); }

}  // namespace

TEST(Exploration, TheChainSensesBothElbowsAndTakesTheLeftOutletAtTheSplit) {
  const Outcome o = run_scene("exploration", "pipe-network", 70);
  ASSERT_EQ(o.exit_code, 0) << o.stderr_text;
  const std::string log = central_log(o, 9);
  EXPECT_NE(log.find("elbow: sensed bend_cdeg=4500 bend_ms=8000 junction=left\n"), std::string::npos) << log;
  const std::vector<Bend> b = bends(log);
  ASSERT_EQ(b.size(), 3u) << log;
  // left, then right: within the 30 degrees of the cover's six directions
  // and the head's roll (measured 58 and 317)
  EXPECT_EQ(b[0].why, "sensed") << log;
  EXPECT_LE(angle_off(b[0].world_deg, 90), 45) << log;
  EXPECT_EQ(b[1].why, "sensed") << log;
  EXPECT_LE(angle_off(b[1].world_deg, 270), 60) << log;
  // the split: the wedge ahead closes every switch, the policy goes left
  EXPECT_NE(log.find("contact switches=7"), std::string::npos) << log;
  EXPECT_EQ(b[2].why, "junction, left") << log;
  EXPECT_LE(angle_off(b[2].world_deg, 90), 10) << log;

  // the layout (scene.json): the second elbow ends at x = 0.857 m, its
  // outgoing leg (the stem) runs along y = 0.72 m to the split at x = 1.152
  // m, whose left outlet ends at (1.31, 0.88)
  auto tr = read_trace(o.dir + "/trace.csv");
  const auto& t = tr.at("t_s");
  const auto& tail_x = tr.at("m8.pig.x");
  const auto& tail_y = tr.at("m8.pig.y");
  double tail_past = -1;
  for (size_t i = 0; i < t.size() && tail_past < 0; ++i)
    if (tail_x[i] > 0.87 && tail_y[i] > 0.70) tail_past = t[i];
  const double hx = tr.at("m0.cover.x").back(), hy = tr.at("m0.cover.y").back();
  std::printf("[ exploration ] bends at %d (%s), %d (%s), %d (%s); tail past the second elbow at %.1f s; "
              "head ends at (%.3f, %.3f)\n",
              b[0].world_deg, b[0].why.c_str(), b[1].world_deg, b[1].why.c_str(), b[2].world_deg,
              b[2].why.c_str(), tail_past, hx, hy);
  EXPECT_GT(tail_past, 0) << "the whole chain passes both elbows";
  // into the split and turned to its left side (y above the stem's 0.72)
  EXPECT_GT(hx, 1.152 + 0.06);
  EXPECT_GT(hy, 0.73);
  // and stalled at the wedge: not out of the left outlet (measured: head
  // at (1.240, 0.740), its helicoidal module at stall current)
  EXPECT_LT(hy, 0.80);
}
