// Touch lines of the bus log: one line per change of a module's input 0.
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
  TouchEdges edges(w.module_count());
  std::vector<std::string> lines;
  auto log = [&](const char* line) { lines.push_back(line); };
  for (int k = 0; k < 200; ++k) {
    w.step();
    edges.sample(w, log);
  }
  EXPECT_TRUE(lines.empty());
  w.set_module_powered(1, false);
  edges.sample(w, log);
  EXPECT_TRUE(lines.empty());  // unpowered reads 0: no change
  w.set_module_powered(1, true);

  World lone(c, {"touch"});  // alone it tips forward onto its cover (sensors_test.cpp)
  TouchEdges lone_edges(1);
  for (int k = 0; k < 1000; ++k) {
    lone.step();
    lone_edges.sample(lone, log);
  }
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines.front(), "touch endpoint=0 level=1");
  EXPECT_EQ(lines.back(), "touch endpoint=0 level=1");  // resting on it at the end
  for (size_t i = 1; i < lines.size(); ++i) EXPECT_NE(lines[i], lines[i - 1]);  // only changes
  const size_t settled = lines.size();
  for (int k = 0; k < 200; ++k) {
    lone.step();
    lone_edges.sample(lone, log);
  }
  EXPECT_EQ(lines.size(), settled);  // still touching: nothing new
  lone.set_module_powered(0, false);
  lone_edges.sample(lone, log);
  lone_edges.sample(lone, log);
  EXPECT_EQ(lines.back(), "touch endpoint=0 level=0");  // unpowered inputs read 0
  EXPECT_EQ(lines.size(), settled + 1);
}

}  // namespace
}  // namespace chainsim
