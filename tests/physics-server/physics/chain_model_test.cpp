// The chain compiled once (physics/chain_model.h): each type looked up (the
// scene's own first) and laid face to face from the head pose; the World
// built where the chain model lays it; placement laying it again.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "model/module_def.h"
#include "physics/chain_model.h"
#include "physics/module_builder.h"
#include "physics/placement.h"
#include "physics/world.h"

namespace chainsim {
namespace {

TEST(ChainModel, TheScenesOwnTypesComeBeforeTheBuiltins) {
  WorldConfig c;
  ModuleDef heavy = builtin_module_def("passive");
  heavy.bodies[0].mass_kg *= 2;
  c.module_types.push_back(heavy);  // a scene's own "passive"
  const ChainModel m = compile_chain(c, {"rotation", "passive", "rotation"});
  ASSERT_EQ(m.size(), 3);
  EXPECT_EQ(m.types(), (std::vector<std::string>{"rotation", "passive", "rotation"}));
  EXPECT_EQ(m.modules[1].bodies[0].mass_kg, heavy.bodies[0].mass_kg);
  EXPECT_EQ(m.modules[0].bodies[0].mass_kg, builtin_module_def("rotation").bodies[0].mass_kg);
  try {
    compile_chain(c, {"rotation", "wormhole"});
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'wormhole'"), std::string::npos) << e.what();
  }
}

TEST(ChainModel, LaysTheChainFaceToFaceFromTheHeadPose) {
  WorldConfig c;
  c.head_position = Eigen::Vector3d(0.1, -0.2, 0.3);
  c.heading_rad = 0.7;
  const std::vector<std::string> types{"touch", "rotation", "support", "extension", "passive"};
  const ChainModel m = compile_chain(c, types);
  ASSERT_EQ(m.frames.size(), m.modules.size());
  const Eigen::Isometry3d head = m.frames[0] * to_isometry(m.modules[0].front.frame);
  EXPECT_LT((head.translation() - c.head_position).norm(), 1e-12);
  EXPECT_LT((head.linear().col(0) - Eigen::Vector3d(std::cos(0.7), std::sin(0.7), 0)).norm(), 1e-12);
  for (int k = 0; k + 1 < m.size(); ++k) {
    const Eigen::Isometry3d back = m.frames[k] * to_isometry(m.modules[k].back.frame);
    const Eigen::Isometry3d front = m.frames[k + 1] * to_isometry(m.modules[k + 1].front.frame);
    EXPECT_TRUE(back.isApprox(front, 1e-12)) << "dock " << k;
  }
  const Eigen::Isometry3d tail = m.frames.back() * to_isometry(m.modules.back().back.frame);
  EXPECT_NEAR((head.translation() - tail.translation()).norm(), m.length_m, 1e-12);
  double sum = 0;  // the chain's length is its modules' lengths, each alone
  for (const std::string& t : types) sum += compile_chain(c, {t}).length_m;
  EXPECT_NEAR(m.length_m, sum, 1e-12);
  EXPECT_GT(m.length_m, 0.1);
}

TEST(ChainModel, TheWorldIsBuiltWhereTheChainModelLaysIt) {
  WorldConfig c;
  c.head_position = Eigen::Vector3d(0, 0, 0.5);
  ChainModel m = compile_chain(c, {"rotation", "passive"});
  WorldConfig moved = c;  // laid 1 m further along x: the World reads the model's frames
  moved.head_position.x() += 1.0;
  lay_chain(&m, moved);
  const World w(c, m);
  for (int k = 0; k < m.size(); ++k)
    for (int b = 0; b < static_cast<int>(m.modules[k].bodies.size()); ++b) {
      const Eigen::Vector3d want = (m.frames[k] * to_isometry(m.modules[k].bodies[b].pose)).translation();
      EXPECT_LT((w.body_state(k, b).position - want).norm(), 1e-9) << "module " << k << " body " << b;
    }
  EXPECT_GT(w.body_state(0, 0).position.x(), 0.5);
}

TEST(ChainModel, PlacementAtThePipeEntryLaysTheChainAgain) {
  WorldConfig c;
  c.environment.type = EnvironmentType::Pipe;
  PipeSegment straight;
  straight.length_m = 1.0;
  c.environment.pipe.segments = {straight};
  c.environment.pipe.heading_deg = 30;
  ChainModel m = compile_chain(c, {"rotation", "rotation", "rotation"});
  const Eigen::Isometry3d before = m.frames[0];
  place_chain_at_pipe_entry(&c, &m, 0.02);
  EXPECT_FALSE(m.frames[0].isApprox(before, 1e-6));
  const ChainModel fresh = compile_chain(c, m.types());  // compiled from the placed config
  for (int k = 0; k < m.size(); ++k) EXPECT_TRUE(m.frames[k].isApprox(fresh.frames[k], 0)) << k;
}

}  // namespace
}  // namespace chainsim
