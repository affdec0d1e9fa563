// EarlyStop: when a run has stopped mattering, from the positions of its
// trace rows: no progress of the furthest position within a window, or a
// mark not reached by a time (with the trace's micrometre of slack).
#include <gtest/gtest.h>

#include "cosim/early_stop.h"
#include "environment/pipe_path.h"

using namespace chainsim;

namespace {

StopRule no_progress(double by_m, double within_s) {
  StopRule r;
  r.kind = StopRule::Kind::NoProgress;
  r.by_m = by_m;
  r.within_s = within_s;
  return r;
}

StopRule not_reached(double reach_m, double by_s, bool tail = false) {
  StopRule r;
  r.kind = StopRule::Kind::NotReached;
  r.reach_m = reach_m;
  r.by_s = by_s;
  r.tail = tail;
  return r;
}

Eigen::Vector3d at_x(double x) { return {x, 0, 0}; }

}  // namespace

TEST(EarlyStop, NoProgressLooksAtTheFurthestPositionOverTheWindow) {
  EarlyStop e({no_progress(0.01, 1.0)}, nullptr);
  // 10 ms rows: 2 cm in the first second, then back and forth below the best
  int64_t t = 0;
  for (; t <= 1000000; t += 10000) ASSERT_FALSE(e.check(t, at_x(0.02 * t / 1e6), at_x(0)));
  // a chain that slides back and comes again is not progressing: its best stays 0.02
  bool stopped = false;
  for (; t <= 3000000 && !stopped; t += 10000) {
    const double x = 0.02 - 0.005 * ((t / 10000) % 2);
    stopped = e.check(t, at_x(x), at_x(0));
  }
  ASSERT_TRUE(stopped);
  // the first row whose last second holds less than 1 cm of gain: at 1.51 s
  // it holds the 9.8 mm from 0.51 to 1.0 s
  EXPECT_EQ(t - 10000, 1510000);
  EXPECT_EQ(e.why().rfind("early stop at 1.510 s: the head got 9.8 mm further in the last 1 s", 0), 0u) << e.why();
  EXPECT_EQ(e.rule()->kind, StopRule::Kind::NoProgress);
}

TEST(EarlyStop, NoProgressNeverFiresBeforeAWholeWindowNorOnAChainThatMoves) {
  EarlyStop e({no_progress(0.01, 2.0)}, nullptr);
  for (int64_t t = 0; t < 2000000; t += 10000) EXPECT_FALSE(e.check(t, at_x(0), at_x(0)));  // standing, but not 2 s yet
  EXPECT_TRUE(e.check(2000000, at_x(0), at_x(0)));
  EarlyStop moving({no_progress(0.01, 2.0)}, nullptr);
  for (int64_t t = 0; t <= 20000000; t += 10000) ASSERT_FALSE(moving.check(t, at_x(0.006 * t / 1e6), at_x(0)));
}

TEST(EarlyStop, NotReachedFiresOnlyPastItsTimeAndOnlyWhenClearlyShort) {
  EarlyStop e({not_reached(0.5, 1.0, true)}, nullptr);
  for (int64_t t = 0; t <= 1000000; t += 10000) ASSERT_FALSE(e.check(t, at_x(1), at_x(0.4)));  // the head is past: not its rule
  EXPECT_TRUE(e.check(1010000, at_x(1), at_x(0.4)));
  EXPECT_EQ(e.why(), "early stop at 1.010 s: the tail got no further than 0.4000 m, short of 0.5 m by 1 s "
                     "(not_reached: tail along x to 0.5 m by 1 s)");
  // reached in time (or within the trace's resolution of it): never
  EarlyStop ok({not_reached(0.5, 1.0)}, nullptr);
  ASSERT_FALSE(ok.check(0, at_x(0.4999995), at_x(0)));
  for (int64_t t = 10000; t <= 3000000; t += 10000) ASSERT_FALSE(ok.check(t, at_x(0.3), at_x(0)));
}

TEST(EarlyStop, AlongThePipeUsesTheLengthOfItsAxis) {
  PipeSpec spec;
  spec.inner_diameter_m = 0.04;
  PipeSegment straight;
  straight.type = PipeSegment::Type::Straight;
  straight.length_m = 0.3;
  spec.segments = {straight};
  auto pipe = std::make_shared<PipeProgress>(layout_pipe(spec));
  const double here = pipe->at(Eigen::Vector3d::Zero());
  StopRule r = not_reached(here + 0.2, 0.5);
  r.along_pipe = true;
  EarlyStop e({r}, pipe);
  ASSERT_FALSE(e.check(0, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()));
  EXPECT_TRUE(e.check(510000, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()));
  EXPECT_NE(e.why().find("along the pipe"), std::string::npos) << e.why();
}
