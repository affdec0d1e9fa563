// Touch edges: one bus-log line per change of a module's input 0, and one
// event per change of each touch sensor, named after it.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "output/touch_edges.h"

namespace chainsim {
namespace {

TEST(TouchEdges, OneLinePerChangeOfTheTouchInput) {
  WorldConfig c;
  c.head_position = Eigen::Vector3d(0, 0, 0.0126);
  World w(c, {"passive", "touch"});
  w.pin_body(0, 0);  // held straight behind a pinned module, the cover stays off the floor
  TouchEdges edges(w.module_count(), sensor_columns(c, {"passive", "touch"}));
  std::vector<std::string> lines, events;
  auto log = [&](const char* line) { lines.push_back(line); };
  auto event = [&](int m, const std::string& sensor, bool contact) {
    events.push_back("m" + std::to_string(m) + " " + sensor + " " + (contact ? "contact" : "released"));
  };
  for (int k = 0; k < 200; ++k) {
    w.step();
    edges.sample(w, log, event);
  }
  EXPECT_TRUE(lines.empty());
  w.set_module_powered(1, false);
  edges.sample(w, log, event);
  EXPECT_TRUE(lines.empty());  // unpowered reads 0: no change
  EXPECT_TRUE(events.empty());
  w.set_module_powered(1, true);

  World lone(c, {"touch"});  // alone it tips forward onto its cover (sensors_test.cpp)
  TouchEdges lone_edges(1, sensor_columns(c, {"touch"}));
  for (int k = 0; k < 1000; ++k) {
    lone.step();
    lone_edges.sample(lone, log, event);
  }
  ASSERT_FALSE(lines.empty());
  // the touch module's one touch sensor is its input 0: an event for every line
  ASSERT_EQ(events.size(), lines.size());
  EXPECT_EQ(events.front(), "m0 touch contact");
  EXPECT_EQ(lines.front(), "touch endpoint=0 level=1");
  EXPECT_EQ(lines.back(), "touch endpoint=0 level=1");  // resting on it at the end
  for (size_t i = 1; i < lines.size(); ++i) EXPECT_NE(lines[i], lines[i - 1]);  // only changes
  const size_t settled = lines.size();
  for (int k = 0; k < 200; ++k) {
    lone.step();
    lone_edges.sample(lone, log, event);
  }
  EXPECT_EQ(lines.size(), settled);  // still touching: nothing new
  lone.set_module_powered(0, false);
  lone_edges.sample(lone, log, event);
  lone_edges.sample(lone, log, event);
  EXPECT_EQ(lines.back(), "touch endpoint=0 level=0");  // unpowered inputs read 0
  EXPECT_EQ(lines.size(), settled + 1);
  EXPECT_EQ(events.back(), "m0 touch released");
  EXPECT_EQ(events.size(), lines.size());
}

}  // namespace
}  // namespace chainsim
