// The speed measurement on a synthetic trace whose answer is known, the pipe
// axis of a scene, and the speed table's reading.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>

#include "analysis/robot_calibration/head_speed.h"
#include "output/run_reader.h"
#include "analysis/robot_calibration/speed_table.h"
#include "readers/csv_table.h"
#include "model/units.h"

namespace chainsim {
namespace {


// the head moves 2 cm/s along axis u and wobbles across it (zero at whole seconds)
std::string trace(const Axis& u, double until_s = 2.0) {
  const Axis across = {-u[1], u[0], 0};
  std::string s = "t_s,m0.pig.x,m0.pig.y,m0.pig.z,m0.pig.qw,m0.s0.command\n";
  for (int k = 0; k * 0.1 <= until_s + 1e-9; ++k) {
    const double t = k * 0.1, along = 0.02 * t, side = 0.003 * std::sin(2 * kPi * t);
    char row[200];
    std::snprintf(row, sizeof row, "%.6f,%.9f,%.9f,%.9f,1,0.5\n", t, 0.1 + along * u[0] + side * across[0],
                  along * u[1] + side * across[1], 0.05 + along * u[2] + side * across[2]);
    s += row;
  }
  return s;
}

TEST(HeadSpeed, AlongTheAxisFromTheWindowStart) {
  const double c = std::cos(30 * kPi / 180), s = std::sin(30 * kPi / 180);
  const Axis u = {0, c, s};
  EXPECT_NEAR(head_speed_cm_s(trace(u), "run", 1.0, u), 2.0, 1e-6);
  // with no axis: along its own displacement (the same here)
  EXPECT_NEAR(head_speed_cm_s(trace(u), "run", 1.0, std::nullopt), 2.0, 1e-6);
  // across the motion: nothing
  EXPECT_NEAR(head_speed_cm_s(trace(u), "run", 1.0, Axis{1, 0, 0}), 0.0, 1e-6);
  // the window starts at the first row at or after t0: 0.5 s sees the wobble's half period too
  EXPECT_NEAR(head_speed_cm_s(trace(u), "run", 0.5, u), 2.0, 1e-6);
}

TEST(HeadSpeed, ATraceThatCannotBeMeasuredIsAnError) {
  const Axis u = {1, 0, 0};
  EXPECT_THROW(head_speed_cm_s(trace(u, 0.9), "run", 1.0, u), std::runtime_error);  // ends before
  EXPECT_THROW(head_speed_cm_s("t_s,m0.s0.command\n0,1\n1,1\n", "run", 0, u), std::runtime_error);
  std::string bad = trace(u);
  bad.replace(bad.find("0.100000,"), 9, "0.1x0000,");
  try {
    head_speed_cm_s(bad, "run", 0, u);
    FAIL() << "no error";
  } catch (const RunReadError& e) {
    EXPECT_NE(std::string(e.what()).find("run/trace.csv:3:1: '0.1x0000' in column 't_s' is not a number"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(head_speed_of_run("/no/such/run", 0, u), RunReadError);
}

TEST(HeadSpeed, PipeAxisFromTheScenesFirstStraightSegment) {
  const std::string pipe =
      "chain: H\nenvironment:\n  type: pipe\n  pipe: {heading_deg: 90, slope_deg: 10, segments: [{type: straight, "
      "length_m: 0.4";
  const auto a = pipe_axis(load_scene_text(pipe + ", slope_deg: 30}]}\n", "s.yaml"));
  ASSERT_TRUE(a);
  EXPECT_NEAR((*a)[0], 0.0, 1e-12);
  EXPECT_NEAR((*a)[1], std::cos(30 * kPi / 180), 1e-12);
  EXPECT_NEAR((*a)[2], 0.5, 1e-12);
  // no slope on the segment: the pipe's
  const auto b = pipe_axis(load_scene_text(pipe + "}]}\n", "s.yaml"));
  ASSERT_TRUE(b);
  EXPECT_NEAR((*b)[2], std::sin(10 * kPi / 180), 1e-12);
  EXPECT_FALSE(pipe_axis(load_scene_text("chain: H\n", "s.yaml")));  // open air
}

TEST(SpeedTable, TheShippedTableAndWhatIsWrongWithOthers) {
  const SpeedTable t = read_speed_table(std::string(CHAINSIM_SOURCE_DIR) + "/scenes/measured/helicoidal_speed_vs_slope.csv");
  EXPECT_EQ(t.key_name, "slope_deg");
  ASSERT_EQ(t.rows.size(), 4u);
  EXPECT_EQ(t.rows[1].key, "30");
  EXPECT_EQ(t.rows[1].real, 2.1);
  EXPECT_EQ(t.rows[1].paper, 2.3);
  const std::string path = testing::TempDir() + "/speed_table_test_" + std::to_string(getpid()) + ".csv";
  auto error_of = [&](const std::string& text) -> std::string {
    std::ofstream(path) << text;
    try {
      read_speed_table(path);
    } catch (const CsvError& e) {
      return e.what();
    }
    return "(no error)";
  };
  std::ofstream(path) << "# comment\nslope_deg,real_speed_cm_s,paper_sim_speed_cm_s\n0,3.0,\n\n30,2.1,2.2\n";
  const SpeedTable c = read_speed_table(path);
  ASSERT_EQ(c.rows.size(), 2u);
  EXPECT_TRUE(std::isnan(c.rows[0].paper));  // blank: not given
  EXPECT_NE(error_of("real_speed_cm_s,slope_deg\n3,0\n2,30\n").find(":1:1: the first column is the key"),
            std::string::npos);
  EXPECT_NE(error_of("slope_deg,speed\n0,3\n30,2\n").find(":1:1: missing column 'real_speed_cm_s'"),
            std::string::npos);
  EXPECT_NE(error_of("slope_deg,real_speed_cm_s\n0,fast\n30,2\n").find(":2:3: 'fast' in column 'real_speed_cm_s'"),
            std::string::npos);
  EXPECT_NE(error_of("slope_deg,real_speed_cm_s\n,3\n30,2\n").find(":2:1: empty key"), std::string::npos);
  EXPECT_NE(error_of("slope_deg,real_speed_cm_s\n0,3\n").find(":2:1: at least 2 rows are needed"), std::string::npos);
  // bounds: a key given twice, a key that is no short printable text, a speed
  // past 10 m/s, more rows than calibrate should run
  EXPECT_NE(error_of("slope_deg,real_speed_cm_s\n0,3\n30,2\n0,3\n").find(":4:1: the key '0' is given twice (first at line 2)"),
            std::string::npos)
      << error_of("slope_deg,real_speed_cm_s\n0,3\n30,2\n0,3\n");
  EXPECT_NE(error_of("slope_deg,real_speed_cm_s\n0\x1b[2J,3\n30,2\n").find(":2:1: the key '0\\x1B[2J' is not a printable"),
            std::string::npos)
      << error_of("slope_deg,real_speed_cm_s\n0\x1b[2J,3\n30,2\n");
  EXPECT_NE(error_of("slope_deg,real_speed_cm_s\n0,1e308\n30,2\n").find(":2:3: real_speed_cm_s 1e308 is beyond +-1000 cm/s"),
            std::string::npos)
      << error_of("slope_deg,real_speed_cm_s\n0,1e308\n30,2\n");
  std::string many = "slope_deg,real_speed_cm_s\n";
  for (int i = 0; i <= 100; ++i) many += std::to_string(i) + ",1\n";
  EXPECT_NE(error_of(many).find(":102:1: more than 100 rows"), std::string::npos) << error_of(many);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace chainsim
