// Measures, constraints and fitness from a run's outputs; progress along a pipe.
#include <gtest/gtest.h>

#include <cmath>

#include "optimize/objective.h"
#include "environment/pipe_progress.h"
#include "optimize/run_outcome.h"

using namespace chainsim;

namespace {

// summary.json of a run of two modules; exit_code and stopped_by as given
std::string summary(int exit_code, const std::string& stopped_by = "", const std::string& fault = "") {
  const std::string f = fault.empty() ? "null" : "\"" + fault + "\"";
  const std::string s = stopped_by.empty() ? "null" : "\"" + stopped_by + "\"";
  return R"({"sim_time_s": 2.0, "exit_code": )" + std::to_string(exit_code) + R"(, "stopped_by": )" + s +
         R"(, "chain": {"displacement_m": [0.3, 0.1, 0.0]},
  "modules": [{"index": 0, "fault": null, "energy_j": 1.5}, {"index": 1, "fault": )" + f +
         R"(, "energy_j": 2.5}, {"index": 2, "fault": null}]})";
}

// the head moves along x at 0.2 m/s, the tail 0.1 m behind; torn last row
const char* kTrace =
    "t_s,m0.core.x,m0.core.y,m0.core.z,m0.core.qw,m0.core.qx,m0.core.qy,m0.core.qz,m0.s0.angle_deg,"
    "m1.front.x,m1.front.y,m1.front.z,m1.front.qw,m1.front.qx,m1.front.qy,m1.front.qz,"
    "m1.back.x,m1.back.y,m1.back.z,m1.back.qw,m1.back.qx,m1.back.qy,m1.back.qz\n"
    "0.000000,0.0,0,0,1,0,0,0,5,-0.05,0,0,1,0,0,0,-0.1,0,0,1,0,0,0\n"
    "1.000000,0.2,0,0,1,0,0,0,5,0.15,0,0,1,0,0,0,0.1,0,0,1,0,0,0\n"
    "2.000000,0.4,0,0,1,0,0,0,5,0.35,0,0,1,0,0,0,0.3,0,0,1,0,0,0\n"
    "2.0100";

MeasureSpec measure(MeasureSpec::Kind k, MeasureSpec::Of of = MeasureSpec::Of::Head) {
  MeasureSpec m;
  m.kind = k;
  m.of = of;
  m.name = "m";
  return m;
}

}  // namespace

TEST(RunOutcome, ReadsTracksEnergyAndHowTheRunEnded) {
  const RunOutcome r = parse_run_outcome(summary(0), kTrace, "run");
  EXPECT_TRUE(r.finished);
  EXPECT_EQ(r.modules, 2);
  EXPECT_DOUBLE_EQ(r.energy_j, 4.0);
  ASSERT_EQ(r.t_s.size(), 3u);  // the torn row is dropped
  EXPECT_DOUBLE_EQ(r.head[2].x(), 0.4);
  EXPECT_DOUBLE_EQ(r.tail[2].x(), 0.3);  // the last module's last body
  const RunOutcome f = parse_run_outcome(summary(2, "module 1 (rotation, pid 7) closed its socket"), kTrace, "run");
  EXPECT_FALSE(f.finished);
  EXPECT_EQ(f.fault, "module 1 (rotation, pid 7) closed its socket");
  const RunOutcome limp = parse_run_outcome(summary(0, "", "crashed"), kTrace, "run");
  EXPECT_FALSE(limp.finished);  // finished its time, but with a module powered off
  EXPECT_EQ(limp.fault, "crashed");
  EXPECT_THROW(parse_run_outcome("{", kTrace, "run"), RunReadError);
  EXPECT_THROW(parse_run_outcome(summary(0), "t_s,a\n1,2\n", "run"), RunReadError);
}

TEST(Objective, MeasuresAlongAnAxis) {
  const RunOutcome r = parse_run_outcome(summary(0), kTrace, "run");
  EXPECT_NEAR(measure_value(measure(MeasureSpec::Kind::Distance), r, nullptr), 0.4, 1e-12);
  EXPECT_NEAR(measure_value(measure(MeasureSpec::Kind::Speed, MeasureSpec::Of::Tail), r, nullptr), 0.2, 1e-12);
  EXPECT_NEAR(measure_value(measure(MeasureSpec::Kind::Distance, MeasureSpec::Of::Chain), r, nullptr), 0.3, 1e-12);
  MeasureSpec t = measure(MeasureSpec::Kind::TimeToReach);
  t.reach_m = 0.15;
  EXPECT_EQ(measure_value(t, r, nullptr), 1.0);
  t.reach_m = 0.5;
  EXPECT_TRUE(std::isinf(measure_value(t, r, nullptr)));
  t.never_s = 25;  // a value for "never" instead of infinity
  EXPECT_EQ(measure_value(t, r, nullptr), 25.0);
  // how far short of a point the furthest position stayed: the tail got to 0.3
  MeasureSpec shortfall = measure(MeasureSpec::Kind::Shortfall, MeasureSpec::Of::Tail);
  shortfall.reach_m = 0.5;
  EXPECT_NEAR(measure_value(shortfall, r, nullptr), 0.2, 1e-12);
  shortfall.reach_m = 0.3;
  EXPECT_EQ(measure_value(shortfall, r, nullptr), 0.0);
  shortfall.reach_m = -0.05;  // passed before the run began: nothing short
  EXPECT_EQ(measure_value(shortfall, r, nullptr), 0.0);
  RunOutcome back = r;  // the tail slides back from 0.1 to -0.2 at the end: the furthest counts
  back.tail[2].x() = -0.2;
  shortfall.reach_m = 0.5;
  EXPECT_NEAR(measure_value(shortfall, back, nullptr), 0.4, 1e-12);
  EXPECT_NEAR(measure_value(measure(MeasureSpec::Kind::EnergyPerM), r, nullptr), 10.0, 1e-12);
  EXPECT_EQ(measure_value(measure(MeasureSpec::Kind::Modules), r, nullptr), 2);
  MeasureSpec y = measure(MeasureSpec::Kind::Distance, MeasureSpec::Of::Chain);
  y.axis = Eigen::Vector3d(1, 1, 0).normalized();
  EXPECT_NEAR(measure_value(y, r, nullptr), 0.4 / std::sqrt(2.0), 1e-12);
}

TEST(Objective, WeightedSumConstraintsAndFailures) {
  const RunOutcome r = parse_run_outcome(summary(0), kTrace, "run");
  std::vector<MeasureSpec> ms = {measure(MeasureSpec::Kind::Distance), measure(MeasureSpec::Kind::Energy)};
  ms[0].name = "x";
  ms[1].name = "e";
  ObjectiveSpec o;
  o.maximize = true;
  o.weights = {{0, 10.0}, {1, -0.5}};
  o.failed_fitness = -99;
  Score s = score_run(ms, o, {}, r, nullptr);
  EXPECT_FALSE(s.failed);
  EXPECT_NEAR(s.fitness, 4.0 - 2.0, 1e-12);
  ASSERT_EQ(s.measures.size(), 2u);
  ConstraintSpec c;
  c.measure = 0;
  c.min = 0.5;
  s = score_run(ms, o, {c}, r, nullptr);
  EXPECT_TRUE(s.failed);
  EXPECT_EQ(s.fitness, -99);
  EXPECT_EQ(s.why, "constraint: x = 0.4 < 0.5");
  EXPECT_NEAR(s.measures[0], 0.4, 1e-12);  // measured all the same
  const RunOutcome crashed = parse_run_outcome(summary(2, "module 1 (rotation) closed its socket"), kTrace, "run");
  s = score_run(ms, o, {}, crashed, nullptr);
  EXPECT_TRUE(s.failed);
  EXPECT_EQ(s.fitness, -99);
  EXPECT_EQ(s.why, "module 1 (rotation) closed its socket");
  // a weight on a measure never reached: not a fitness
  MeasureSpec t = measure(MeasureSpec::Kind::TimeToReach);
  t.reach_m = 9;
  t.name = "t";
  o.maximize = false;
  o.weights = {{0, 1.0}};
  s = score_run({t}, o, {}, r, nullptr);
  EXPECT_TRUE(s.failed);
  EXPECT_EQ(s.fitness, -99);
  EXPECT_TRUE(std::isinf(s.measures[0]));
  // ranked by how far short it stayed instead: the time for "never" plus 100 s per metre short
  t.never_s = 25;
  MeasureSpec sh = measure(MeasureSpec::Kind::Shortfall);
  sh.reach_m = 9;
  sh.name = "short";
  o.weights = {{0, 1.0}, {1, 100.0}};
  s = score_run({t, sh}, o, {}, r, nullptr);
  EXPECT_FALSE(s.failed);
  EXPECT_NEAR(s.fitness, 25 + 100 * (9 - 0.4), 1e-9);
}

TEST(PipeProgress, ArcLengthThroughStraightElbowStraight) {
  PipeSpec spec;
  spec.inner_diameter_m = 0.04;
  PipeSegment a, e, b;
  a.length_m = 0.3;
  e.type = PipeSegment::Type::Elbow;
  e.bend_radius_m = 0.08;
  e.angle_deg = 90;
  e.direction_deg = 90;  // left: from +x towards +y
  b.length_m = 0.3;
  spec.segments = {a, e, b};
  const PipeProgress p(layout_pipe(spec));
  const double arc = 0.08 * M_PI / 2;
  EXPECT_NEAR(p.exit_m(), 0.6 + arc, 1e-9);
  EXPECT_NEAR(p.at({0.1, 0.005, 0}), 0.1, 1e-9);
  EXPECT_NEAR(p.at({-0.05, 0, 0}), -0.05, 1e-9);  // before the entry
  // half way round the elbow (centre at (0.3, 0.08))
  const Eigen::Vector3d mid(0.3 + 0.08 * std::sin(M_PI / 4), 0.08 - 0.08 * std::cos(M_PI / 4), 0);
  EXPECT_NEAR(p.at(mid), 0.3 + arc / 2, 1e-9);
  EXPECT_NEAR(p.at({0.38, 0.08 + 0.2, 0.01}), 0.3 + arc + 0.2, 1e-9);
  EXPECT_NEAR(p.at({0.38, 0.08 + 0.35, 0}), 0.6 + arc + 0.05, 1e-9);  // past the exit
}

TEST(PipeProgress, ATeesBranchCountsFromTheMiddleOfItsRun) {
  PipeSpec spec;
  spec.inner_diameter_m = 0.03;
  PipeSegment a, t, b;
  a.length_m = 0.2;
  t.type = PipeSegment::Type::Tee;
  t.run_length_m = 0.1;
  t.branch_length_m = 0.06;
  t.direction_deg = 90;
  t.follow_branch = true;
  b.length_m = 0.2;
  spec.segments = {a, t, b};
  const PipeProgress p(layout_pipe(spec));
  EXPECT_NEAR(p.exit_m(), 0.2 + 0.05 + 0.06 + 0.2, 1e-9);
  EXPECT_NEAR(p.at({0.25, 0.03, 0}), 0.2 + 0.05 + 0.03, 1e-9);  // in the branch
}

TEST(Objective, TrialsScoreTheMeanAndFailWithTheFirstFailedOne) {
  ObjectiveSpec o;
  o.weights = {{0, 2.0}, {1, 1.0}};
  o.failed_fitness = -5;
  Score a, b, c;
  a.measures = {1.0, 10.0};
  b.measures = {3.0, 20.0};
  a.fitness = 12;
  b.fitness = 26;
  const Score m = combine_trials({a, b}, o);
  EXPECT_FALSE(m.failed);
  EXPECT_EQ(m.measures, (std::vector<double>{2.0, 15.0}));
  EXPECT_DOUBLE_EQ(m.fitness, 19.0);
  EXPECT_EQ(m.trials, 2);
  EXPECT_DOUBLE_EQ(m.fitness_sd, std::sqrt(98.0));  // (12, 26): sample sd
  EXPECT_EQ(m.fitness_min, 12);
  EXPECT_EQ(m.fitness_max, 26);
  c = failed_score(2, o, "constraint: x = 0 < 1");
  const Score f = combine_trials({a, c, b}, o);
  EXPECT_TRUE(f.failed);
  EXPECT_EQ(f.fitness, -5);
  EXPECT_EQ(f.why, "trial 2 of 3: constraint: x = 0 < 1");
  const Score one = combine_trials({b}, o);  // one run: as it is, no spread
  EXPECT_EQ(one.fitness, 26);
  EXPECT_EQ(one.trials, 1);
  EXPECT_TRUE(std::isnan(one.fitness_sd));
  EXPECT_EQ(one.fitness_min, 26);
}

TEST(Objective, TheWorstTrialOrAQuantileInTheObjectivesSense) {
  ObjectiveSpec mx;
  mx.weights = {{0, 1.0}};
  std::vector<Score> t(5);
  const double f[5] = {3, 1, 5, 2, 4};
  for (int i = 0; i < 5; ++i) {
    t[i].measures = {f[i]};
    t[i].fitness = f[i];
  }
  EXPECT_EQ(combine_trials(t, mx, TrialFitness::Worst).fitness, 1);
  EXPECT_EQ(combine_trials(t, mx, TrialFitness::Quantile, 0.0).fitness, 1);
  EXPECT_EQ(combine_trials(t, mx, TrialFitness::Quantile, 1.0).fitness, 5);
  EXPECT_EQ(combine_trials(t, mx, TrialFitness::Quantile, 0.5).fitness, 3);
  EXPECT_DOUBLE_EQ(combine_trials(t, mx, TrialFitness::Quantile, 0.125).fitness, 1.5);  // between 1 and 2
  EXPECT_EQ(combine_trials(t, mx, TrialFitness::Mean).fitness, 3);
  // minimising, the worst is the largest
  ObjectiveSpec mn = mx;
  mn.maximize = false;
  EXPECT_EQ(combine_trials(t, mn, TrialFitness::Worst).fitness, 5);
  EXPECT_EQ(combine_trials(t, mn, TrialFitness::Quantile, 0.25).fitness, 4);
  EXPECT_EQ(combine_trials(t, mn, TrialFitness::Quantile, 1.0).fitness, 1);
  // an early stop is said, with its trial
  t[3].early_stop = "early stop at 2.000 s: ...";
  EXPECT_EQ(combine_trials(t, mx).early_stop, "trial 4 of 5: early stop at 2.000 s: ...");
}
