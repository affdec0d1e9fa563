// Measured records: calibrate simulates a record's whole span once per
// candidate model, so a record's span and rows are bounded, and a record too
// short to fit is refused; each at its row.
#include "analysis/calibration/measured_record.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <fstream>
#include <string>

#include "readers/csv_table.h"

namespace chainsim {
namespace {

// (a file of this test's own: ctest runs the tests of this file at once,
// and other checkouts' test runs may share the temporary directory)
std::string error_of(const std::string& text) {
  const std::string path = testing::TempDir() + "/measured_record_test_" +
                           testing::UnitTest::GetInstance()->current_test_info()->name() + "_" +
                           std::to_string(getpid()) + ".csv";
  std::ofstream(path) << text;
  try {
    read_measured(path, 3);
  } catch (const CsvError& e) {
    return std::string(e.what()).substr(path.size());
  }
  return "(no error)";
}

TEST(MeasuredRecord, SpanRowsAndLengthAreBounded) {
  EXPECT_EQ(error_of("t_s,setpoint_deg,angle_deg\n0,0,0\n0.1,1,0\n0.2,1,1\n"), "(no error)");
  // one time of 1e308, or rows hours apart: calibrate would simulate it all
  EXPECT_EQ(error_of("t_s,setpoint_deg,angle_deg\n0,0,0\n0.1,1,0\n1e308,1,1\n"),
            ":4:1: the record spans more than 600 s from its first row (calibrate simulates the whole span for every "
            "candidate)");
  EXPECT_EQ(error_of("t_s,setpoint_deg,angle_deg\n0,0,0\n3333,1,0\n6666,1,1\n").rfind(":3:1: the record spans more", 0),
            0u);
  // 3e-10 s: less than a servo frame, nothing to fit
  EXPECT_NE(error_of("t_s,setpoint_deg,angle_deg\n0,0,0\n1e-10,1,0\n3e-10,1,1\n").find("less than a servo frame"),
            std::string::npos);
}

// a set-point of 1e300 (or an angle, or a current) that no servo has is
// refused at its cell, not simulated
TEST(MeasuredRecord, ValuesNoServoHasAreRefusedAtTheirCell) {
  EXPECT_EQ(error_of("t_s,setpoint_deg,angle_deg\n0,0,0\n0.1,1e300,0\n0.2,1,1\n"),
            ":3:5: setpoint_deg 1e300 is beyond +-720 degrees");
  EXPECT_EQ(error_of("t_s,setpoint_deg,angle_deg\n0,0,0\n0.1,1,-800\n0.2,1,1\n"),
            ":3:7: angle_deg -800 is beyond +-720 degrees");
  EXPECT_EQ(error_of("t_s,setpoint_deg,angle_deg,current_a\n0,0,0,0\n0.1,1,0,1e9\n0.2,1,1,0\n"),
            ":3:9: current_a 1e9 is beyond +-100 A");
}

TEST(MeasuredRecord, TooManyRowsAreRefusedAtTheFirstOneOver) {
  std::string text = "t_s,setpoint_deg,angle_deg\n";
  for (size_t i = 0; i <= kMaxMeasuredRows; ++i) text += std::to_string(i * 0.001) + ",0,0\n";
  const std::string e = error_of(text);
  EXPECT_NE(e.find("more than 200000 rows"), std::string::npos) << e;
  EXPECT_EQ(e.rfind(":" + std::to_string(kMaxMeasuredRows + 2) + ":1: ", 0), 0u) << e;
}

}  // namespace
}  // namespace chainsim
