// The undulating terrain between walls (paper Fig. 12): its surface, and a
// snake crawling at an angle into a wall stays between the walls and on the
// surface.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>

#include "pipe_probe.h"
#include "environment/terrain.h"
#include "model/units.h"
#include "physics/world.h"
#include "world_of.h"

namespace chainsim {
namespace {

// how far a body reaches from its centre along unit direction d, m
double reach(const BodyDef& b, const World::BodyState& s, const Eigen::Vector3d& d) {
  const Eigen::Matrix3d r =
      Eigen::Quaterniond(s.quaternion_wxyz[0], s.quaternion_wxyz[1], s.quaternion_wxyz[2],
                         s.quaternion_wxyz[3])
          .toRotationMatrix();
  const double a = std::fabs(r.col(2).dot(d));  // capsule and cylinder axes: body z
  switch (b.shape) {
    case Shape::Sphere: return b.radius_m;
    case Shape::Capsule: return a * b.length_m / 2 + b.radius_m;
    case Shape::Cylinder: return a * b.length_m / 2 + b.radius_m * std::sqrt(std::max(0.0, 1 - a * a));
    case Shape::Box:
      return 0.5 * (std::fabs(r.col(0).dot(d)) * b.box_m.x() + std::fabs(r.col(1).dot(d)) * b.box_m.y() +
                    a * b.box_m.z());
  }
  return 0;
}

TEST(Terrain, MeshFollowsTheHeightFunctionAndFacesUp) {
  TerrainSpec t;
  t.amplitude_m = 0.02;
  t.wavelength_m = 0.2;
  t.length_m = 1.0;
  const TriMesh m = terrain_mesh(t);
  for (const auto& v : m.vertices) EXPECT_NEAR(v.z(), terrain_height_m(t, v.x()), 1e-12);
  EXPECT_NEAR(terrain_height_m(t, 0), 0, 1e-12);          // a valley at x = 0
  EXPECT_NEAR(terrain_height_m(t, 0.1), 0.04, 1e-12);     // a crest half a wavelength on
  for (const auto& tri : m.triangles) {
    const Eigen::Vector3d n =
        (m.vertices[tri[1]] - m.vertices[tri[0]]).cross(m.vertices[tri[2]] - m.vertices[tri[0]]);
    EXPECT_GT(n.z(), 0);
  }
  const auto walls = terrain_walls(t);
  ASSERT_EQ(walls.size(), 2u);
  EXPECT_NEAR(walls[0].centre_m.y() - 0.5 * walls[0].size_m.y(), 0.15, 1e-12);  // inner face at width/2
}

// eight rotation modules, dropped from 4 cm onto the terrain, crawl with the
// gait of gait_test.cpp heading 25 degrees to the left of the terrain's
// axis: they reach the wall at y = +width/2 and keep pushing into it. No
// body gets past a wall (1 mm tolerance) or below the surface.
TEST(Terrain, CrawlingSnakeStaysBetweenTheWalls) {
  WorldConfig c;
  c.environment.type = EnvironmentType::Terrain;
  c.environment.ground_plane = false;
  TerrainSpec& t = c.environment.terrain;
  t.amplitude_m = 0.01;
  t.wavelength_m = 0.3;
  t.width_m = 0.2;
  t.length_m = 2.0;
  c.heading_rad = 25 * kRadPerDeg;
  c.head_position = Eigen::Vector3d(0.1, 0.075, 0.04);
  const std::vector<std::string> chain(8, "rotation");
  World w = world_of(c, chain);
  for (int m = 0; m < 8; ++m) w.set_servo_setpoint(m, 1, (m == 0 ? 25 : (m % 2 ? -50 : 50)) * kRadPerDeg);
  const std::vector<ModuleDef> defs = chain_defs(c, chain);
  double max_y = 0, min_gap = 1, max_abs_y = 0;  // max_y, max_abs_y: the bodies' outer surfaces
  for (int k = 0; k < 16000; ++k) {  // 8 s
    if (k % 20 == 0) {
      const double time = w.time_us() * 1e-6;
      for (int m = 0; m < 8; ++m) w.set_servo_setpoint(m, 0, 20 * kRadPerDeg * std::sin(14 * time + m * 1.36));
    }
    w.step();
    if (k % 10) continue;
    for (int m = 0; m < 8; ++m)
      for (int b = 0; b < w.body_count(m); ++b) {
        const World::BodyState s = w.body_state(m, b);
        const Eigen::Vector3d p = s.position;
        const double side = reach(defs[m].bodies[b], s, Eigen::Vector3d::UnitY());
        max_y = std::max(max_y, p.y() + side);
        max_abs_y = std::max(max_abs_y, std::fabs(p.y()) + side);
        min_gap = std::min(min_gap, p.z() - terrain_height_m(t, p.x()));
      }
  }
  std::printf("largest |y| of a body's surface %.4f m (wall at %.4f m), lowest centre %.4f m above the surface\n",
              max_abs_y, t.width_m / 2, min_gap);
  EXPECT_GT(max_y, t.width_m / 2 - 0.002);  // it got to the wall
  EXPECT_LT(max_abs_y, t.width_m / 2 + 0.001);
  EXPECT_GT(min_gap, 0.0);  // centres stay above the surface
}

}  // namespace
}  // namespace chainsim
