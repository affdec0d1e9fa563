// trace.csv: the columns of each actuator kind, rows that read back as the
// world's state in the columns' units, the row clock.
#include <gtest/gtest.h>

#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "model/units.h"
#include "output/trace_writer.h"
#include "world_of.h"

namespace chainsim {
namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream s(line);
  std::string f;
  while (std::getline(s, f, ',')) out.push_back(f);
  return out;
}

std::string body_columns(const std::string& prefix) {
  std::string s;
  for (const char* c : {"x", "y", "z", "qw", "qx", "qy", "qz"}) s += "," + prefix + "." + c;
  return s;
}

TEST(TraceWriter, HeaderNamesEveryColumnInItsUnit) {
  WorldConfig c;
  c.head_position = Eigen::Vector3d(0, 0, 0.5);
  World w = world_of(c, {"rotation", "passive", "extension", "helicoidal"});
  const TraceWriter t(w, 10000);
  const std::string want =
      "t_s" + body_columns("m0.front") + body_columns("m0.body") + body_columns("m0.back") +
      ",m0.s0.setpoint_deg,m0.s0.angle_deg,m0.s0.current_a"
      ",m0.s1.setpoint_deg,m0.s1.angle_deg,m0.s1.current_a,m0.supply_a" +
      body_columns("m1.body") + ",m1.supply_a" + body_columns("m2.front") + body_columns("m2.front_box") +
      body_columns("m2.back_box") +
      ",m2.s0.setpoint_mm,m2.s0.position_mm,m2.s0.current_a"
      ",m2.s1.setpoint_deg,m2.s1.angle_deg,m2.s1.current_a,m2.supply_a" +
      body_columns("m3.pig") + body_columns("m3.head") +
      ",m3.s0.command,m3.s0.speed_rad_s,m3.s0.current_a,m3.supply_a"
      ",m3.head0.n_N,m3.head0.f_N,m3.head1.n_N,m3.head1.f_N,m3.head2.n_N,m3.head2.f_N"
      ",m3.stator0.n_N,m3.stator0.f_N,m3.stator1.n_N,m3.stator1.f_N,m3.stator2.n_N,m3.stator2.f_N\n";
  EXPECT_EQ(t.header(), want);
}

// every column of a row is the world's value in that column's unit, to the
// column's decimals
TEST(TraceWriter, RowReadsBackAsTheWorldsStateInTheColumnsUnits) {
  WorldConfig c;
  c.head_position = Eigen::Vector3d(0, 0, 0.5);
  c.gravity_m_s2 = 0;
  World w = world_of(c, {"rotation", "extension", "helicoidal"});
  w.pin_body(0, 0);
  w.set_servo_setpoint(0, 0, 30 * kRadPerDeg);
  w.set_servo_setpoint(1, 0, 0.006);
  w.set_servo_setpoint(2, 0, -0.75);
  for (int k = 0; k < 150; ++k) w.step();
  TraceWriter t(w, 500);
  std::string row;
  t.append_row(&row);
  ASSERT_EQ(row.back(), '\n');
  const std::vector<std::string> cols = split(t.header().substr(0, t.header().size() - 1));
  const std::vector<std::string> vals = split(row.substr(0, row.size() - 1));
  ASSERT_EQ(cols.size(), vals.size());
  EXPECT_EQ(vals[0], "0.075000");  // 150 steps of 500 us
  auto value = [&](const std::string& col) {
    for (size_t i = 0; i < cols.size(); ++i)
      if (cols[i] == col) return std::strtod(vals[i].c_str(), nullptr);
    ADD_FAILURE() << "no column " << col;
    return 0.0;
  };
  const World::BodyState b = w.body_state(1, 2);
  EXPECT_NEAR(value("m1.back_box.x"), b.position.x(), 5e-7);
  EXPECT_NEAR(value("m1.back_box.z"), b.position.z(), 5e-7);
  EXPECT_NEAR(value("m1.back_box.qw"), b.quaternion_wxyz[0], 5e-7);
  EXPECT_NEAR(value("m1.back_box.qz"), b.quaternion_wxyz[3], 5e-7);
  EXPECT_NEAR(value("m0.s0.setpoint_deg"), 30.0, 5e-5);
  EXPECT_NEAR(value("m0.s0.angle_deg"), w.servo_position(0, 0) * kDegPerRad, 5e-5);
  EXPECT_NEAR(value("m0.s0.current_a"), w.servo_current_a(0, 0), 5e-6);
  EXPECT_NEAR(value("m1.s0.setpoint_mm"), 6.0, 5e-5);
  EXPECT_NEAR(value("m1.s0.position_mm"), w.servo_position(1, 0) * 1e3, 5e-5);
  EXPECT_NEAR(value("m2.s0.command"), -0.75, 5e-5);
  EXPECT_NEAR(value("m2.s0.speed_rad_s"), w.servo_rate(2, 0), 5e-5);
  EXPECT_LT(value("m2.s0.speed_rad_s"), -1.0);  // the drive motor spins the head backwards
  EXPECT_EQ(value("m2.head0.n_N"), 0.0);        // in the air: its wheels touch nothing
  EXPECT_EQ(value("m2.stator2.f_N"), 0.0);
  EXPECT_NEAR(value("m2.s0.current_a"), w.servo_current_a(2, 0), 5e-6);
  EXPECT_NEAR(value("m0.supply_a"), w.module_supply_current_a(0), 5e-6);
  EXPECT_GT(value("m0.supply_a"), 0.0);
}

// each sensor of a module type under its own name, after the module's other
// columns, in the unit its firmware reads it in
TEST(TraceWriter, SensorColumnsAreNamedAfterTheModuleTypesSensors) {
  WorldConfig c;
  c.head_position = Eigen::Vector3d(0, 0, 0.5);
  const std::vector<std::string> chain{"touch", "rotation", "traveller"};
  World w = world_of(c, chain);
  const TraceWriter t(w, 10000, sensor_columns(compile_chain(c, chain)));
  const std::string& h = t.header();
  for (const char* col : {",m0.touch.0.in,m0.touch.1.in,m0.touch.2.in,m0.accel.x_counts,m0.accel.y_counts,m0.accel.z_counts,m1.",
                          ",m1.pitch_current.counts,m1.yaw_current.counts,m2.",
                          ",m2.encoder_top.counts,m2.encoder_right.counts,m2.encoder_left.counts,m2.accel.x_counts,"
                          "m2.accel.y_counts,m2.accel.z_counts\n"})
    EXPECT_NE(h.find(col), std::string::npos) << col << " not in " << h;
  // without sensor columns the trace is as before them
  EXPECT_EQ(TraceWriter(w, 10000).header().find(".counts"), std::string::npos);
}

// the sensor columns read what World::sample gives the firmware: a touch
// module at rest on the floor (tipped onto its cover) reads its cover's
// contact on the two lower switches (1 and 2, not 0 on top) and +1 g up
// (683 counts, 170.7 per g above 512)
TEST(TraceWriter, SensorColumnsReadWhatTheFirmwareReads) {
  WorldConfig c;
  const std::vector<std::string> chain{"touch"};
  World w = world_of(c, chain);  // alone it tips forward onto its cover (sensors_test.cpp)
  for (int k = 0; k < 2000; ++k) w.step();
  TraceWriter t(w, 500, sensor_columns(compile_chain(c, chain)));
  std::string row;
  t.append_row(&row);
  const std::vector<std::string> cols = split(t.header().substr(0, t.header().size() - 1));
  const std::vector<std::string> vals = split(row.substr(0, row.size() - 1));
  ASSERT_EQ(cols.size(), vals.size());
  auto value = [&](const std::string& col) -> std::string {
    for (size_t i = 0; i < cols.size(); ++i)
      if (cols[i] == col) return vals[i];
    ADD_FAILURE() << "no column " << col;
    return "";
  };
  ModuleSample s;
  w.sample(0, &s);
  EXPECT_EQ(value("m0.touch.0.in"), "0");
  EXPECT_EQ(value("m0.touch.1.in"), "1");
  EXPECT_EQ(value("m0.touch.2.in"), "1");
  for (int k = 0; k < 3; ++k)
    EXPECT_EQ(value("m0.touch." + std::to_string(k) + ".in"), std::to_string((s.digital_in >> k) & 1u));
  EXPECT_EQ(value("m0.accel.x_counts"), std::to_string(s.adc[0]));
  EXPECT_EQ(value("m0.accel.y_counts"), std::to_string(s.adc[1]));
  EXPECT_EQ(value("m0.accel.z_counts"), std::to_string(s.adc[2]));
  // tipped by a few degrees: nearly all of the 1 g on z
  EXPECT_NEAR(std::stoi(value("m0.accel.z_counts")), 683, 4);
  EXPECT_NEAR(std::stoi(value("m0.accel.y_counts")), 512, 4);
  w.set_module_powered(0, false);  // limp mode: sensors read zero
  row.clear();
  t.append_row(&row);
  EXPECT_EQ(row.substr(row.size() - 9), ",0,0,0,0\n");
}

// a row at t = 0 and then every interval, never more often than the step
TEST(TraceWriter, RowsComeEveryIntervalOfSimulatedTime) {
  WorldConfig c;
  World w = world_of(c, {"passive"});
  EXPECT_EQ(TraceWriter::interval_for(w, 100.0), 10000);
  EXPECT_EQ(TraceWriter::interval_for(w, 1e6), 500);  // not below the 500 us step
  TraceWriter t(w, 1500);
  std::string row;
  std::vector<int64_t> times;
  for (int k = 0; k < 10; ++k) {
    if (t.row_due(&row)) {
      times.push_back(w.time_us());
      EXPECT_EQ(row.rfind(std::to_string(w.time_us() / 1000000) + ".", 0), 0u) << row;
      EXPECT_EQ(std::count(row.begin(), row.end(), '\n'), 1);
    }
    w.step();
  }
  EXPECT_EQ(times, (std::vector<int64_t>{0, 1500, 3000, 4500}));
}

}  // namespace
}  // namespace chainsim
