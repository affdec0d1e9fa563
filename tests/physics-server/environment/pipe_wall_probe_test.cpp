// The wall along a ray (pipe_wall_probe.h): exact against the bore of
// straight and bent pipes, nothing past an open end or beyond the reach, the
// mesh twin and a plane through ODE rays.
#include <gtest/gtest.h>

#include <ode/ode.h>

#include <cmath>
#include <limits>

#include "environment/environment_geoms.h"
#include "environment/pipe_path.h"
#include "environment/pipe_wall_probe.h"

namespace chainsim {
namespace {

constexpr double kDeg = M_PI / 180.0;

struct OdeInit {
  OdeInit() { dInitODE2(0); dAllocateODEDataForThread(dAllocateMaskAll); }
};

PipeSpec elbow_pipe(PipeCollider collider) {
  PipeSpec p;
  p.inner_diameter_m = 0.04;
  p.collider = collider;
  p.mesh_segments = 64;
  PipeSegment a;
  a.length_m = 0.3;
  PipeSegment e;
  e.type = PipeSegment::Type::Elbow;
  e.bend_radius_m = 0.08;
  e.angle_deg = 90;
  e.direction_deg = 90;  // left: towards +y
  PipeSegment b;
  b.length_m = 0.3;
  p.segments = {a, e, b};
  return p;
}

Eigen::Vector3d unit(double x, double y, double z) { return Eigen::Vector3d(x, y, z).normalized(); }

TEST(WallProbe, StraightPipeExactFromAnyPointAndDirection) {
  const PipeLayout l = layout_pipe(elbow_pipe(PipeCollider::Analytic));
  WallProbe probe(&l, {});
  int hint = -1;
  WallHit hit;
  // from the axis, radially: the radius
  ASSERT_TRUE(probe.cast(Eigen::Vector3d(0.1, 0, 0), unit(0, 0, 1), 0.03, &hint, &hit));
  EXPECT_NEAR(hit.t, 0.02, 1e-9);
  EXPECT_NEAR((hit.normal - Eigen::Vector3d(0, 0, -1)).norm(), 0, 1e-9);
  // off the axis, slanted: the point found is on the circle of radius 20 mm
  const Eigen::Vector3d o(0.15, 0.005, -0.004), d = unit(0.3, -0.4, 0.8);
  ASSERT_TRUE(probe.cast(o, d, 0.05, &hint, &hit));
  EXPECT_NEAR(std::hypot(hit.point.y(), hit.point.z()), 0.02, 1e-9);
  EXPECT_NEAR((hit.point - (o + hit.t * d)).norm(), 0, 1e-12);
  EXPECT_NEAR(hit.normal.x(), 0, 1e-9);  // radial, inwards
  EXPECT_LT(hit.normal.dot(Eigen::Vector3d(0, hit.point.y(), hit.point.z())), 0);
  // out of reach: nothing
  EXPECT_FALSE(probe.cast(Eigen::Vector3d(0.1, 0, 0), unit(0, 0, 1), 0.019, &hint, &hit));
  // along the axis: no wall within 0.1 m
  EXPECT_FALSE(probe.cast(Eigen::Vector3d(0.1, 0, 0), unit(1, 0, 0), 0.1, &hint, &hit));
}

TEST(WallProbe, ElbowWallIsOnTheTorus) {
  const PipeLayout l = layout_pipe(elbow_pipe(PipeCollider::Analytic));
  ASSERT_EQ(l.pieces[1].kind, PipePiece::Kind::Elbow);
  WallProbe probe(&l, {});
  // mid-bend axis point, rays towards the bend's centre and away from it,
  // up, and slanted: each hit lies on the wall (depth 0 against the bore)
  const PipeFrame mid = pipe_piece_frame(l.pieces[1], 0.5);
  const Eigen::Vector3d in = (l.pieces[1].centre - mid.point).normalized();
  int hint = -1;
  for (const Eigen::Vector3d& d : {in, Eigen::Vector3d(-in), Eigen::Vector3d(mid.up),
                                   Eigen::Vector3d((in + mid.up + 0.5 * mid.tangent).normalized())}) {
    WallHit hit;
    ASSERT_TRUE(probe.cast(mid.point, d, 0.03, &hint, &hit));
    EXPECT_NEAR(pipe_depth(l, hit.point, 0.0), 0.0, 2e-7) << d.transpose();
    EXPECT_GT(hit.normal.dot(-d), 0.5);  // faces the ray
  }
  WallHit hit;
  ASSERT_TRUE(probe.cast(mid.point, in, 0.03, &hint, &hit));
  EXPECT_NEAR(hit.t, 0.02, 1e-7);
}

TEST(WallProbe, RayCrossingIntoTheNextPieceFindsItsWall) {
  const PipeLayout l = layout_pipe(elbow_pipe(PipeCollider::Analytic));
  WallProbe probe(&l, {});
  // from the straight's axis 5 mm before the bend, slanted forward and left:
  // the ray leaves through the elbow's wall
  const Eigen::Vector3d o(0.295, 0, 0), d = unit(1, 1, 0);
  int hint = 0;
  WallHit hit;
  ASSERT_TRUE(probe.cast(o, d, 0.05, &hint, &hit));
  EXPECT_NEAR(pipe_depth(l, hit.point, 0.0), 0.0, 2e-7);
  EXPECT_EQ(hint, 1);  // the elbow piece
}

TEST(WallProbe, NothingPastAnOpenEnd) {
  PipeSpec p;
  p.inner_diameter_m = 0.04;
  PipeSegment a;
  a.length_m = 0.1;
  p.segments = {a};
  const PipeLayout l = layout_pipe(p);
  WallProbe probe(&l, {});
  int hint = -1;
  WallHit hit;
  EXPECT_TRUE(probe.cast(Eigen::Vector3d(0.09, 0, 0), unit(0, 0, 1), 0.03, &hint, &hit));
  // the ray leaves through the exit's plane before it reaches the radius
  EXPECT_FALSE(probe.cast(Eigen::Vector3d(0.095, 0, 0), unit(1, 0, 1), 0.05, &hint, &hit));
  // a pivot beyond the exit: free space
  EXPECT_FALSE(probe.cast(Eigen::Vector3d(0.12, 0, 0), unit(0, 0, 1), 0.03, &hint, &hit));
}

// how far a point lies in the wall, and the wall point nearest to it
TEST(WallProbe, PipeWallGapOfAPoint) {
  const PipeLayout l = layout_pipe(elbow_pipe(PipeCollider::Analytic));
  WallProbe probe(&l, {});
  int hint = -1;
  WallHit hit;
  // in the first straight's wall, 5 mm beyond the bore
  EXPECT_NEAR(probe.pipe_wall_gap(Eigen::Vector3d(0.1, 0, -0.025), &hint, &hit), 0.005, 1e-12);
  EXPECT_TRUE(hit.pipe);
  EXPECT_NEAR((hit.point - Eigen::Vector3d(0.1, 0, -0.02)).norm(), 0, 1e-12);
  EXPECT_NEAR((hit.normal - Eigen::Vector3d(0, 0, 1)).norm(), 0, 1e-12);
  // in the bore: negative
  EXPECT_NEAR(probe.pipe_wall_gap(Eigen::Vector3d(0.1, 0.01, 0), &hint, &hit), -0.01, 1e-12);
  // in the elbow's outer wall (centre of the bend at (0.3, 0.08, 0)), 45
  // degrees round: 0.08 + 0.02 + 0.003 from the centre
  const Eigen::Vector3d c(0.3, 0.08, 0), radial = unit(1, -1, 0);
  EXPECT_NEAR(probe.pipe_wall_gap(c + 0.103 * radial, &hint, &hit), 0.003, 1e-9);
  EXPECT_NEAR((hit.normal + radial).norm(), 0, 1e-9);
  // past the open entry: no piece owns it
  EXPECT_EQ(probe.pipe_wall_gap(Eigen::Vector3d(-0.01, 0, -0.025), &hint, &hit),
            -std::numeric_limits<double>::infinity());
  // no analytic pipe
  WallProbe none(nullptr, {});
  EXPECT_EQ(none.pipe_wall_gap(Eigen::Vector3d(0.1, 0, -0.025), &hint, &hit), -std::numeric_limits<double>::infinity());
}

TEST(WallProbe, MeshPipeAndPlaneThroughOdeRays) {
  OdeInit ode;
  EnvironmentConfig env;
  env.type = EnvironmentType::Pipe;
  env.pipe = elbow_pipe(PipeCollider::Mesh);
  env.ground_plane = true;
  env.pipe.entry_m = Eigen::Vector3d(0, 0, 0.1);
  dSpaceID space = dSimpleSpaceCreate(nullptr);
  {
    EnvironmentGeoms geoms(env, space);
    WallProbe probe(geoms.pipe_layout() && env.pipe.collider == PipeCollider::Analytic
                        ? geoms.pipe_layout()
                        : nullptr,
                    geoms.geoms());
    const double r_in = 0.02 * std::cos(M_PI / 64);  // the 64-gon's inscribed radius
    int hint = -1;
    for (double a : {0.0, 37.0, 90.0, 200.0}) {
      WallHit hit;
      const Eigen::Vector3d d(0, std::cos(a * kDeg), std::sin(a * kDeg));
      ASSERT_TRUE(probe.cast(Eigen::Vector3d(0.1, 0, 0.1), d, 0.03, &hint, &hit)) << a;
      EXPECT_GE(hit.t, r_in - 1e-9) << a;
      EXPECT_LE(hit.t, 0.02 + 1e-9) << a;
      EXPECT_GT(hit.normal.dot(-d), 0.9) << a;  // the face, seen from inside
    }
    // outside the pipe, down: the ground plane at z = 0
    WallHit hit;
    ASSERT_TRUE(probe.cast(Eigen::Vector3d(-0.2, 0.3, 0.05), unit(0, 0, -1), 0.1, &hint, &hit));
    EXPECT_NEAR(hit.t, 0.05, 1e-9);
    EXPECT_NEAR(hit.normal.z(), 1.0, 1e-9);
  }
  dSpaceDestroy(space);
}

}  // namespace
}  // namespace chainsim
