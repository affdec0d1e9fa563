// The robot calibration's fits and search on synthetic speed functions
// (no runs): a knob that explains the table is found with its factor, one
// that changes nothing is not accepted, n rows allow at most n - 2 knobs, two
// knobs are fitted jointly; pairs of knobs whose singles fall short are
// found together, a pair with a knob it does not need is refused, and a pair
// the table cannot tell from another is reported as an alias.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "analysis/robot_calibration/robot_search.h"

namespace chainsim {
namespace {

const int kThrust = robot_knob("drive_stall");
const int kFreeSpeed = robot_knob("drive_free_speed");
const int kFriction = robot_knob("wall_friction");

std::vector<SpeedRow> table(const std::vector<double>& real) {
  std::vector<SpeedRow> rows;
  for (size_t i = 0; i < real.size(); ++i) rows.push_back({std::to_string(30 * i), real[i], NAN});
  return rows;
}

const std::vector<SpeedRow> kRows = table({3.0, 2.1, 1.5, 1.2});

// the real speeds when the thrust factor is 1.3, proportional to it, plus
// `extra` per row that no knob changes
SpeedFunction thrust_model(std::vector<double> extra = {}) {
  return [extra](const KnobSetting& st) {
    std::vector<double> v;
    for (size_t i = 0; i < kRows.size(); ++i)
      v.push_back(kRows[i].real / 1.3 * factor_of(st, kThrust) + (extra.empty() ? 0.0 : extra[i]));
    return v;
  };
}

void quiet(const std::string&) {}

TEST(RobotFit, OneKnobFindsItsFactor) {
  const KnobFit f = fit_one_knob(thrust_model(), kRows, {}, kThrust, {});
  EXPECT_NEAR(f.st.at(kThrust), 1.3, 0.03);
  EXPECT_LT(f.gap, 0.05);
  EXPECT_EQ(f.evals, 7 + 2 + 6);  // grid, golden-section start, steps
  // a masked row does not count
  std::vector<double> sim = {3.0, 2.1, 1.5, 9.9};
  EXPECT_GT(speed_gap(sim, kRows), 4.0);
  EXPECT_DOUBLE_EQ(speed_gap(sim, kRows, {true, true, true, false}), 0.0);
}

TEST(RobotFit, TwoKnobsJointlyAndNeverWorseThanTheStart) {
  // speed = a f_thrust + b f_friction, truth 1.2 and 0.8
  const std::vector<double> a = {2.0, 1.0, 0.5, 0.2}, b = {1.0, 1.5, 1.0, 1.3};
  std::vector<double> real;
  for (size_t i = 0; i < 4; ++i) real.push_back(a[i] * 1.2 + b[i] * 0.8);
  const std::vector<SpeedRow> rows = table(real);
  const SpeedFunction model = [&](const KnobSetting& st) {
    std::vector<double> v;
    for (size_t i = 0; i < 4; ++i) v.push_back(a[i] * factor_of(st, kThrust) + b[i] * factor_of(st, kFriction));
    return v;
  };
  const KnobSetting start = {{kThrust, 1.0}, {kFriction, 1.0}};
  const double g0 = speed_gap(model(start), rows);
  const KnobFit f = fit_knobs(model, rows, start, {});
  std::printf("two knobs: gap %.4f -> %.4f (thrust %.3f, friction %.3f, %d evaluations)\n", g0, f.gap,
              f.st.at(kThrust), f.st.at(kFriction), f.evals);
  EXPECT_LT(f.gap, 0.1 * g0);
  EXPECT_NEAR(f.st.at(kThrust), 1.2, 0.05);
  EXPECT_NEAR(f.st.at(kFriction), 0.8, 0.05);
  // started at the optimum, it stays there
  const KnobFit at = fit_knobs(model, rows, {{kThrust, 1.2}, {kFriction, 0.8}}, {});
  EXPECT_LT(at.gap, 1e-9);
}

TEST(RobotSearch, AcceptsTheKnobThatExplainsTheTable) {
  const RobotSearch s = search_knobs(kRows, {kThrust, kFreeSpeed, kFriction}, thrust_model(), quiet);
  EXPECT_EQ(s.verdict, "explained");
  ASSERT_EQ(s.accepted, std::vector<int>{kThrust});
  EXPECT_NEAR(s.model.at(kThrust), 1.3, 0.03);
  EXPECT_NEAR(s.gap_before, std::sqrt((9.0 + 4.41 + 2.25 + 1.44) / 4) * 0.3 / 1.3, 1e-9);
  EXPECT_LE(s.gap_after, kTableResolution);
  ASSERT_EQ(s.candidates.size(), 3u);
  EXPECT_EQ(s.candidates[0].knob, kThrust);
  EXPECT_EQ(s.candidates[0].why, "accepted");
  EXPECT_EQ(s.candidates[1].why, "not the best of the round");
  // leave one row out: the other three rows fix the factor, the left-out row is predicted
  for (size_t i = 0; i < kRows.size(); ++i) EXPECT_NEAR(s.leave_one_out[i], kRows[i].real, 0.1) << i;
  EXPECT_LT(s.leave_one_out_gap, 0.1);
  EXPECT_TRUE(std::isnan(s.paper_gap));  // no paper column
}

TEST(RobotSearch, AKnobThatChangesNothingIsNotAccepted) {
  const SpeedFunction flat = [](const KnobSetting&) { return std::vector<double>{3.0, 2.6, 1.5, 1.2}; };
  const RobotSearch s = search_knobs(kRows, {kFreeSpeed, kFriction}, flat, quiet);
  EXPECT_EQ(s.verdict, "unexplained");
  EXPECT_TRUE(s.accepted.empty());
  ASSERT_FALSE(s.candidates.empty());
  EXPECT_NE(s.candidates[0].why.find("cuts the gap by 0 % (< 30 %)"), std::string::npos) << s.candidates[0].why;
  EXPECT_EQ(s.gap_after, s.gap_before);
  EXPECT_TRUE(std::isnan(s.leave_one_out_gap));
}

TEST(RobotSearch, ThreeRowsAllowOneKnob) {
  const std::vector<SpeedRow> rows(kRows.begin(), kRows.begin() + 3);
  const SpeedFunction model = [&](const KnobSetting& st) {
    return std::vector<double>{3.0 / 1.3 * factor_of(st, kThrust), 2.1 / 1.3 * factor_of(st, kThrust) + 0.5,
                               1.5 / 1.3 * factor_of(st, kThrust) * factor_of(st, kFriction)};
  };
  const RobotSearch s = search_knobs(rows, {kThrust, kFriction}, model, quiet);
  EXPECT_EQ(s.accepted.size(), 1u);            // n - 2 = 1, though the gap is still above the resolution
  EXPECT_GT(s.gap_after, kTableResolution);
  EXPECT_EQ(s.verdict, "unexplained");
}

// Speeds linear in the knobs' log factors: v = nominal + sum J_k log f_k,
// six rows. The truth sets `truth`; the rows' real speeds are the model's
// there plus `extra`.
struct LinearModel {
  std::vector<double> nominal;
  std::map<int, std::vector<double>> J;
  std::vector<double> speeds(const KnobSetting& st) const {
    std::vector<double> v = nominal;
    for (const auto& [k, col] : J)
      for (size_t i = 0; i < v.size(); ++i) v[i] += col[i] * std::log(factor_of(st, k));
    return v;
  }
  SpeedFunction fn() const {
    return [this](const KnobSetting& st) { return speeds(st); };
  }
  std::vector<SpeedRow> rows(const KnobSetting& truth, std::vector<double> extra = {}) const {
    std::vector<double> v = speeds(truth);
    for (size_t i = 0; i < extra.size(); ++i) v[i] += extra[i];
    return table(v);
  }
};

const int kWheelFriction = robot_knob("wheel_friction");

// a drive's force-speed line seen through a table: free speed raises every
// row alike, stall torque the loaded (steep) rows most
LinearModel drive_model() {
  LinearModel m;
  m.nominal = {3.0, 2.6, 2.1, 1.8, 1.5, 1.2};
  m.J[kThrust] = {0.0, 0.4, 0.8, 1.2, 1.6, 2.0};
  m.J[kFreeSpeed] = {3.0, 2.6, 2.1, 1.8, 1.5, 1.2};
  m.J[kFriction] = {0, 0, 0, 0, 0, 0};
  return m;
}

TEST(RobotSearch, APairWhoseSinglesFallShortIsFoundTogether) {
  const LinearModel m = drive_model();
  const auto rows = m.rows({{kThrust, 1.3}, {kFreeSpeed, 0.85}});
  const RobotSearch s = search_knobs(rows, {kThrust, kFreeSpeed, kFriction}, m.fn(), quiet);
  // neither knob alone cuts the gap by 30 %: the greedy rounds accept nothing
  for (const KnobCandidate& c : s.candidates) {
    EXPECT_EQ(c.round, 1);
    EXPECT_FALSE(c.accepted) << robot_knobs()[c.knob].name << " " << c.fit.gap << " of " << s.gap_before;
  }
  // wall friction changes nothing, so the one pair is thrust + free speed
  ASSERT_EQ(s.pairs.size(), 1u);
  EXPECT_TRUE(s.pairs[0].accepted) << s.pairs[0].why;
  EXPECT_EQ(s.verdict, "explained");
  ASSERT_EQ(s.accepted.size(), 2u);
  EXPECT_NEAR(s.model.at(kThrust), 1.3, 0.03);
  EXPECT_NEAR(s.model.at(kFreeSpeed), 0.85, 0.02);
  EXPECT_LE(s.gap_after, kTableResolution);
  EXPECT_LT(s.leave_one_out_gap, kTableResolution);
  EXPECT_TRUE(s.aliases.empty());
  // the other way round
  const auto rows2 = m.rows({{kThrust, 0.75}, {kFreeSpeed, 1.2}});
  const RobotSearch s2 = search_knobs(rows2, {kThrust, kFreeSpeed, kFriction}, m.fn(), quiet);
  EXPECT_EQ(s2.verdict, "explained");
  ASSERT_EQ(s2.accepted.size(), 2u);
  EXPECT_NEAR(s2.model.at(kThrust), 0.75, 0.02);
  EXPECT_NEAR(s2.model.at(kFreeSpeed), 1.2, 0.03);
}

TEST(RobotSearch, APairReplacesASingleThatLeavesTheGapAboveTheResolution) {
  // wall friction alone mimics the two drive changes' sum but for a pattern
  // of its own (alternating rows): accepted alone, it leaves 0.075 cm/s,
  // and no second knob fitted onto it helps; the drive pair explains all
  LinearModel m = drive_model();
  const KnobSetting truth = {{kThrust, 1.3}, {kFreeSpeed, 0.85}};
  const std::vector<double> nominal = m.speeds({}), changed = m.speeds(truth);
  const double d[] = {0.1, -0.1, 0.1, -0.1, 0.1, -0.1};
  std::vector<double> friction;
  for (size_t i = 0; i < 6; ++i) friction.push_back(4 * (changed[i] - nominal[i]) + 3 * d[i]);
  m.J[kFriction] = friction;
  const RobotSearch s = search_knobs(m.rows(truth), {kThrust, kFreeSpeed, kFriction}, m.fn(), quiet);
  ASSERT_FALSE(s.candidates.empty());
  EXPECT_EQ(s.candidates[0].knob, kFriction);   // round 1's best
  EXPECT_NE(s.candidates[0].why.find("accepted; replaced by the pair"), std::string::npos) << s.candidates[0].why;
  for (const KnobCandidate& c : s.candidates) EXPECT_FALSE(c.accepted) << robot_knobs()[c.knob].name;
  ASSERT_EQ(s.pairs.size(), 1u);
  EXPECT_TRUE(s.pairs[0].accepted) << s.pairs[0].why;
  EXPECT_EQ(std::set<int>(s.accepted.begin(), s.accepted.end()), (std::set<int>{kThrust, kFreeSpeed}));
  EXPECT_EQ(s.model.count(kFriction), 0u);
  EXPECT_NEAR(s.model.at(kThrust), 1.3, 0.03);
  EXPECT_NEAR(s.model.at(kFreeSpeed), 0.85, 0.02);
  EXPECT_EQ(s.verdict, "explained");
  EXPECT_TRUE(s.aliases.empty());
}

TEST(RobotSearch, APairWithAKnobItDoesNotNeedIsRefused) {
  // thrust explains most of the gap; free speed adds little beyond it, and
  // what is left no knob explains
  LinearModel m = drive_model();
  m.J[kFreeSpeed] = {0.6, -0.6, 0.6, -0.6, 0.6, -0.6};
  const auto rows = m.rows({{kThrust, 1.2}, {kFreeSpeed, 1.3}}, {0.25, 0.25, -0.25, -0.25, 0.1, 0.1});
  const RobotSearch s = search_knobs(rows, {kThrust, kFreeSpeed}, m.fn(), quiet);
  ASSERT_EQ(s.pairs.size(), 1u) << s.verdict;
  const PairCandidate& p = s.pairs[0];
  std::printf("alone %.3f / %.3f, together %.3f, before %.3f: %s\n", p.single_a, p.single_b, p.fit.gap,
              s.gap_before, p.why.c_str());
  EXPECT_LT(p.fit.gap, 0.7 * s.gap_before);  // the pair cuts the gap by the threshold...
  EXPECT_FALSE(p.accepted);                  // ...but the better single nearly as much
  EXPECT_NE(p.why.find("drive_free_speed not needed"), std::string::npos) << p.why;
  EXPECT_EQ(s.verdict, "unexplained");
  EXPECT_TRUE(s.accepted.empty());
  EXPECT_EQ(s.gap_after, s.gap_before);
}

TEST(RobotSearch, TwoPairsTheTableCannotTellApartAreReportedAsAliases) {
  // wheel friction moves the rows exactly as free speed does
  LinearModel m = drive_model();
  m.J[kWheelFriction] = m.J[kFreeSpeed];
  const auto rows = m.rows({{kThrust, 1.3}, {kFreeSpeed, 0.85}});
  const RobotSearch s = search_knobs(rows, {kThrust, kFreeSpeed, kWheelFriction}, m.fn(), quiet);
  EXPECT_EQ(s.verdict, "explained");
  ASSERT_EQ(s.accepted.size(), 2u);
  EXPECT_EQ(s.accepted[0] == kThrust || s.accepted[1] == kThrust, true);
  ASSERT_EQ(s.aliases.size(), 1u);
  const Alias& al = s.aliases[0];
  EXPECT_EQ(al.chosen, s.model);
  EXPECT_LE(al.difference, kTableResolution);
  EXPECT_LE(al.gap_other, kTableResolution);
  // the alias is the other of the two look-alike knobs with thrust
  std::set<int> both;
  for (const auto& [k, f] : al.chosen) both.insert(k);
  for (const auto& [k, f] : al.other) both.insert(k);
  EXPECT_EQ(both, (std::set<int>{kThrust, kFreeSpeed, kWheelFriction}));
  int named = 0;
  for (const PairCandidate& p : s.pairs) named += p.why.find("alias") != std::string::npos;
  EXPECT_EQ(named, 2);   // the accepted pair says it has one, the other that it is one
}

TEST(RobotSearch, AnAliasOfASingleKnobIsReported) {
  // wheel friction moves the rows exactly as thrust does: one knob explains the table either way
  LinearModel m = drive_model();
  m.J[kWheelFriction] = m.J[kThrust];
  const auto rows = m.rows({{kThrust, 0.6}});
  const RobotSearch s = search_knobs(rows, {kThrust, kFreeSpeed, kWheelFriction}, m.fn(), quiet);
  EXPECT_EQ(s.verdict, "explained");
  ASSERT_EQ(s.accepted.size(), 1u);
  ASSERT_EQ(s.aliases.size(), 1u);
  EXPECT_EQ(s.aliases[0].chosen.size(), 1u);
  EXPECT_EQ(s.aliases[0].other.size(), 1u);
  EXPECT_NE(s.aliases[0].chosen.begin()->first, s.aliases[0].other.begin()->first);
  EXPECT_TRUE(s.pairs.empty());
}

TEST(RobotSearch, ThreeRowsTryNoPairs) {
  const LinearModel m = drive_model();
  std::vector<SpeedRow> rows = m.rows({{kThrust, 1.3}, {kFreeSpeed, 0.85}});
  rows.resize(3);
  const RobotSearch s = search_knobs(rows, {kThrust, kFreeSpeed}, m.fn(), quiet);
  EXPECT_TRUE(s.pairs.empty());
  EXPECT_LE(s.accepted.size(), 1u);
}

}  // namespace
}  // namespace chainsim
