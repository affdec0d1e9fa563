// Measuring expectations in a run directory: a small one written here, with
// every file a run writes (summary.json, trace.csv, bus.log, module logs), so
// each measured value is known exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "testing/evaluate.h"
#include "testing/motion.h"
#include "output/run_reader.h"

using namespace chainsim;

namespace {

constexpr double kPi = 3.14159265358979323846;

// two rotation modules (m0 head, m1 tail, 0.1 m apart) crawl along +x at
// 0.1 m/s for 3 s; m0's body turns about its own axis at 90 deg/s; m0's
// servo current peaks at 0.4 A at t = 1 s; the central control is endpoint 2
class RunDir : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/chainsim-evaluate-XXXXXX";
    dir_ = mkdtemp(tmpl);
    std::filesystem::create_directories(dir_ + "/modules");
    std::ofstream(dir_ + "/summary.json") << R"({"scene": "two", "seed": 4, "sim_time_s": 3.0,
      "trace_sha256": "abc", "modules": [
        {"index": 0, "type": "rotation", "fault": null, "energy_j": 1.5},
        {"index": 1, "type": "rotation", "fault": )" << (fault_ ? "\"closed its socket\"" : "null") << R"(, "energy_j": 2.5},
        {"index": 2, "type": "central", "fault": null}],
      "chain": {"displacement_m": [0.3, 0.0, 0.0], "distance_m": 0.3, "speed_m_s": 0.1}, "exit_code": 0})";
    std::ofstream tr(dir_ + "/trace.csv");
    tr << "t_s,m0.body.x,m0.body.y,m0.body.z,m0.body.qw,m0.body.qx,m0.body.qy,m0.body.qz,m0.s0.current_a,"
          "m1.body.x,m1.body.y,m1.body.z,m1.body.qw,m1.body.qx,m1.body.qy,m1.body.qz\n";
    for (int i = 0; i <= 30; ++i) {
      const double t = i * 0.1, x = 0.1 * t, half = 0.5 * (kPi / 2) * t;
      tr << t << "," << x + 0.1 << ",0,0.01," << std::cos(half) << ",0,0," << std::sin(half) << ","
         << (i == 10 ? 0.4 : 0.1 + 0.001 * i) << "," << x << ",0,0.01,1,0,0,0\n";
    }
    std::ofstream(dir_ + "/bus.log") << "0 sync endpoint=2 sout=1\n"
                                        "1000 addr endpoint=0 address=0x20\n"
                                        "1000 sync endpoint=0 sout=1\n"
                                        "1000 i2c from=0 to=0x10 deliver_us=1290 data=022001\n"
                                        "3000 addr endpoint=1 address=0x21\n"
                                        "21000 i2c from=2 to=0x21 deliver_us=22000 data=1001a00f\n"
                                        "21000 i2c from=2 to=0x00 deliver_us=23000 data=11\n"
                                        "1500000 touch endpoint=0 level=1\n"
                                        "1700000 touch endpoint=0 level=0\n"
                                        "2500000 fault module 1 (rotation, pid 7) closed its socket at t=2.5 s\n";
    std::ofstream(dir_ + "/modules/02-central.log") << "0.021000 chain: RR (2 modules)\n"
                                                       "0.025000 start at ms 25\n"
                                                       "1.000000 sensors 0x20: 10 20\n"
                                                       "2.000000 sensors 0x20: 11 21\n";
    std::ofstream(dir_ + "/modules/00-rotation.log") << "0.500000 contact\n";
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  CheckResult check(const std::string& text) {
    RunReader run(dir_);
    return evaluate(parse_expectation(text), run);
  }
  std::string error(const std::string& text) {
    try {
      check(text);
    } catch (const EvaluationError& e) {
      return e.what();
    }
    return "";
  }

  std::string dir_;
  bool fault_ = false;
};

}  // namespace

TEST_F(RunDir, SummaryNumbersByDottedPath) {
  CheckResult r = check("chain.distance_m >= 0.2");
  EXPECT_TRUE(r.pass);
  EXPECT_DOUBLE_EQ(r.value, 0.3);
  EXPECT_EQ(r.measured, "0.3");
  EXPECT_FALSE(check("chain.distance_m >= 0.31").pass);
  EXPECT_DOUBLE_EQ(check("modules.1.energy_j < 3").value, 2.5);
  EXPECT_DOUBLE_EQ(check("chain.displacement_m.0 > 0").value, 0.3);
  const std::string e = error("chain.distanse_m >= 0.2");
  EXPECT_NE(e.find("unknown metric 'chain.distanse_m'"), std::string::npos) << e;
  EXPECT_NE(e.find("chain.distance_m"), std::string::npos) << e;  // the known ones listed
  EXPECT_NE(error("scene > 1").find("not a number (string)"), std::string::npos);
  EXPECT_NE(error("modules.3.energy_j > 1").find("no '3'"), std::string::npos);
}

TEST_F(RunDir, NoFaults) {
  EXPECT_TRUE(check("no_faults").pass);
  EXPECT_EQ(check("no_faults").measured, "0 faults");
  TearDown();
  fault_ = true;
  SetUp();
  const CheckResult r = check("no_faults");
  EXPECT_FALSE(r.pass);
  EXPECT_EQ(r.measured, "1 fault: closed its socket");
  EXPECT_DOUBLE_EQ(r.t_s, 2.5);  // the picture shows the fault
}

TEST_F(RunDir, TraceStatistics) {
  CheckResult r = check("trace.m0.s0.current_a max < 0.35");
  EXPECT_FALSE(r.pass);
  EXPECT_DOUBLE_EQ(r.value, 0.4);
  EXPECT_DOUBLE_EQ(r.t_s, 1.0);
  EXPECT_EQ(r.measured, "0.4 (at 1.000 s)");
  EXPECT_DOUBLE_EQ(check("trace.m0.s0.current_a min > 0").value, 0.1);
  EXPECT_NEAR(check("trace.m0.s0.current_a final > 0").value, 0.13, 1e-12);
  EXPECT_NEAR(check("trace.m1.body.x at 1.55 > 0").value, 0.15, 1e-12);  // the row at or before T
  EXPECT_NEAR(check("trace.m1.body.x mean > 0").value, 0.15, 1e-12);
  r = check("trace.m1.body.x at 4 > 0");
  EXPECT_FALSE(r.pass);
  EXPECT_EQ(r.measured, "the trace ends at 3 s");
  const std::string e = error("trace.m0.s0.current max < 1");
  EXPECT_NE(e.find("unknown trace column 'm0.s0.current' (columns of m0: m0.body.x"), std::string::npos) << e;
  EXPECT_NE(e.find("m0.s0.current_a"), std::string::npos) << e;
}

TEST_F(RunDir, TraceConditionsTakeTheFirstRowWhereTheyHold) {
  CheckResult r = check("trace.m1.body.x > 0.2 before 2.5");
  EXPECT_TRUE(r.pass);
  EXPECT_NEAR(r.value, 2.1, 1e-9);
  EXPECT_FALSE(check("trace.m1.body.x > 0.2 before 2").pass);
  EXPECT_TRUE(check("trace.m1.body.x > 0.2 after 2").pass);
  EXPECT_TRUE(check("trace.m1.body.x > 0.5 never").pass);
  r = check("trace.m1.body.x > 0.5 before 1");
  EXPECT_FALSE(r.pass);
  EXPECT_EQ(r.measured, "never (run ended at 3 s)");
}

TEST_F(RunDir, ModuleLogs) {
  CheckResult r = check("log central /chain: RR \\(2 modules\\)/ before 0.3");
  EXPECT_TRUE(r.pass);
  EXPECT_EQ(r.measured, "at 0.021 s: \"chain: RR (2 modules)\"");
  EXPECT_FALSE(check("log central /start at/ before 0.02").pass);
  EXPECT_TRUE(check("log central /sensors 0x20/ count == 2").pass);
  EXPECT_TRUE(check("log m0 /contact/ after 0.4").pass);
  EXPECT_TRUE(check("log m1 /anything/ never").pass);  // a module that logged nothing
  EXPECT_EQ(error("log m5 /x/ never"), "m5: the chain has 2 modules (m0..m1)");
}

TEST_F(RunDir, BusEvents) {
  EXPECT_TRUE(check("bus i2c to 0x21 before 0.03").pass);
  EXPECT_DOUBLE_EQ(check("bus i2c to 0x21 before 0.03").value, 0.021);
  EXPECT_FALSE(check("bus i2c to 0x21 before 0.02").pass);
  EXPECT_TRUE(check("bus i2c from central count == 2").pass);
  EXPECT_TRUE(check("bus i2c from central data 10 count == 1").pass);
  EXPECT_TRUE(check("bus i2c from m0 to 0x10 data 0220 before 0.01").pass);
  EXPECT_TRUE(check("bus i2c from m1 never").pass);
  EXPECT_TRUE(check("bus addr m1 0x21 before 0.01").pass);
  EXPECT_FALSE(check("bus addr m1 0x22 before 0.01").pass);
  EXPECT_TRUE(check("bus sout m0 1 before 0.002").pass);
  EXPECT_TRUE(check("bus sout m1 never").pass);
  EXPECT_TRUE(check("bus i2c-drop never").pass);
  EXPECT_TRUE(check("touch m0 before 2").pass);
  EXPECT_DOUBLE_EQ(check("touch m0 before 2").value, 1.5);
  EXPECT_TRUE(check("touch m0 count == 1").pass);  // the release is not a touch
  EXPECT_TRUE(check("touch m1 never").pass);
}

TEST_F(RunDir, ChainMotion) {
  RunReader run(dir_);
  const ChainMotion m = chain_motion(run);
  // centroid: mean of [0, 0.2] at 0.06 m, of [2, 3] at 0.30 m
  EXPECT_NEAR(m.dx_m, 0.24, 1e-9);
  EXPECT_NEAR(m.dy_m, 0, 1e-12);
  EXPECT_NEAR(m.heading_deg, 0, 1e-9);
  EXPECT_NEAR(m.axial_m, 0.3, 1e-9);
  EXPECT_NEAR(m.lateral_m, 0, 1e-12);
  EXPECT_NEAR(check("motion.m0.body.twist_deg > 0").value, 270, 0.01);  // quaternions printed to 6 digits
  EXPECT_NEAR(check("motion.distance_m > 0").value, 0.24, 1e-9);
  EXPECT_NE(error("motion.speed > 0").find("unknown motion metric 'motion.speed' (known: dx_m"), std::string::npos);
  EXPECT_NE(error("motion.m2.body.twist_deg > 0").find("no body 'm2.body' in trace.csv (bodies: m0.body, m1.body)"),
            std::string::npos);
}

TEST_F(RunDir, AMissingFileFailsTheExpectation) {
  std::filesystem::remove(dir_ + "/trace.csv");
  const CheckResult r = check("trace.m0.body.x final > 0");
  EXPECT_FALSE(r.pass);
  EXPECT_NE(r.measured.find(dir_ + "/trace.csv: cannot open"), std::string::npos) << r.measured;
}

// chainsim test interrupted: a run record whose stop check says so gives up
// reading and matching with RunReadStopped, a log as a trace or the bus
TEST_F(RunDir, AStopCheckEndsReadingAndMatching) {
  bool stop = false;
  RunReader run(dir_, {[&] { return stop; }, {}});
  EXPECT_TRUE(evaluate(parse_expectation("log central /sensors 0x20/ count == 2"), run).pass);
  stop = true;
  for (const char* e : {"log central /sensors 0x20/ count == 2", "log m0 /contact/ never", "bus i2c-drop never",
                        "trace.m0.s0.current_a max < 1"}) {
    RunReader fresh(dir_, {[&] { return stop; }, {}});
    EXPECT_THROW(evaluate(parse_expectation(e), fresh), RunReadStopped) << e;
  }
}
