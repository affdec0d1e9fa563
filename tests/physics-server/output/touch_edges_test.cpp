// Touch edges: one bus-log line per change of a module's touch level (any of
// its touch inputs), and one event per change of each touch input, named
// after its sensor (the touch module's three switches: touch.0, .1, .2).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "output/touch_edges.h"
#include "world_of.h"

namespace chainsim {
namespace {

TEST(TouchEdges, OneLinePerChangeOfTheTouchInput) {
  WorldConfig c;
  c.head_position = Eigen::Vector3d(0, 0, 0.0126);
  World w = world_of(c, {"passive", "touch"});
  w.pin_body(0, 0);  // held straight behind a pinned module, the cover stays off the floor
  TouchEdges edges(w.module_count(), sensor_columns(compile_chain(c, {"passive", "touch"})));
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

  World lone = world_of(c, {"touch"});  // alone it tips forward onto its cover (sensors_test.cpp)
  TouchEdges lone_edges(1, sensor_columns(compile_chain(c, {"touch"})));
  for (int k = 0; k < 1000; ++k) {
    lone.step();
    lone_edges.sample(lone, log, event);
  }
  ASSERT_FALSE(lines.empty());
  // the touch module's three switches: the floor below closes 1 and 2 (not
  // 0, on top); the bus line says the cover touched when either closes
  ASSERT_GE(events.size(), 2u);
  EXPECT_EQ(events[0], "m0 touch.1 contact");
  EXPECT_EQ(events[1], "m0 touch.2 contact");
  for (const std::string& e : events) EXPECT_EQ(e.find("touch.0"), std::string::npos) << e;
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
  ASSERT_GE(events.size(), 2u);
  EXPECT_EQ(events[events.size() - 2], "m0 touch.1 released");
  EXPECT_EQ(events.back(), "m0 touch.2 released");
}

}  // namespace
}  // namespace chainsim
