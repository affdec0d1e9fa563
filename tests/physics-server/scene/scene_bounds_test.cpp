// Scene sizes are bounded before anything is built, the bound in the error.
#include <gtest/gtest.h>

#include <string>

#include "scene/scene.h"
#include "scene_error_of.h"

using chainsim::load_scene_text;
using chainsim::testing::scene_error_of;

namespace {

std::string pipe_of(int segments) {
  std::string segs;
  for (int i = 0; i < segments; ++i) segs += std::string(i ? ", " : "") + "{type: straight, length_m: 0.01}";
  return "chain: R\nenvironment:\n  type: pipe\n  pipe:\n    inner_diameter_m: 0.1\n    segments: [" + segs + "]\n";
}
}  // namespace

TEST(SceneBounds, ChainOfMoreThan64ModulesNamesTheCountAndTheLimit) {
  EXPECT_EQ(scene_error_of("chain: " + std::string(65, 'R') + "\n"),
            "s.yaml:1:8: 'chain' has 65 modules, more than the limit of 64");
  std::string list = "chain:\n";
  for (int i = 0; i < 100; ++i) list += "  - {type: rotation}\n";
  EXPECT_EQ(scene_error_of(list), "s.yaml:2:3: 'chain' has 100 modules, more than the limit of 64");
  EXPECT_EQ(load_scene_text("chain: " + std::string(64, 'R') + "\n", "s.yaml").modules.size(), 64u);
}

// 100 000 segments used to be accepted and the run never finished building
TEST(SceneBounds, PipeOfMoreThan1000SegmentsNamesTheCountAndTheLimit) {
  const std::string e = scene_error_of(pipe_of(1001));
  EXPECT_NE(e.find("s.yaml:6:15: 'environment.pipe.segments' has 1001 segments, more than the limit of 1000"),
            std::string::npos)
      << e.substr(0, 300);
  EXPECT_EQ(scene_error_of(pipe_of(1000)).find("more than the limit"), std::string::npos);
}
