// The one reader of a run directory: the trace's columns, the rows it keeps
// and those it refuses, the summary, bus.log and the module logs.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "output/run_reader.h"
#include "temp_dir.h"

namespace chainsim {
namespace {

const char* kSummary = R"({"sim_time_s": 2.5, "modules": [{"type": "rotation"}, {"type": "helicoidal"},
                          {"type": "central"}]})";

std::string error_of(RunReader r) {
  try {
    r.trace_columns();
  } catch (const RunReadError& e) {
    return e.what();
  }
  return "no error";
}

TEST(RunReader, ReadsTheTraceByColumnAndDropsATornLastRow) {
  RunReader r = RunReader::from_text("run", kSummary, "t_s,m0.a.x,m0.a.y\n0,1,2\n0.5,-nan,inf\n1.0,3");
  EXPECT_EQ(r.trace_columns(), (std::vector<std::string>{"t_s", "m0.a.x", "m0.a.y"}));
  EXPECT_EQ(r.trace_time(), (std::vector<double>{0, 0.5}));
  ASSERT_NE(r.trace_column("m0.a.x"), nullptr);
  EXPECT_TRUE(std::isnan((*r.trace_column("m0.a.x"))[1]));
  EXPECT_TRUE(std::isinf((*r.trace_column("m0.a.y"))[1]));
  EXPECT_EQ(r.trace_column("m9.b.x"), nullptr);
  EXPECT_EQ(r.end_s(), 2.5);
  EXPECT_EQ(r.module_count(), 2);
  EXPECT_EQ(r.endpoint_index(true, 0), 2);
}

TEST(RunReader, KeepsOnlyTheColumnsAskedFor) {
  RunReaderOptions o;
  o.keep_column = [](const std::string& n) { return n != "junk"; };
  // the cells of a column not kept are not read: no error for them
  RunReader r = RunReader::from_text("run", kSummary, "t_s,junk,v\n0,x,1\n1,y,2\n", o);
  EXPECT_EQ(r.trace_columns().size(), 3u);
  EXPECT_EQ(r.trace_column("junk"), nullptr);
  EXPECT_EQ(*r.trace_column("v"), (std::vector<double>{1, 2}));
}

TEST(RunReader, FindsEachModulesBodiesByTheirPositionColumns) {
  // module 0: two bodies, then a servo, a sensor whose channels end in
  // _counts and a column that ends in .x without .y, .z after it; module 1:
  // none; module 12: one, after a wheel's columns
  const std::string header =
      "t_s,m0.front.x,m0.front.y,m0.front.z,m0.front.qw,m0.back.x,m0.back.y,m0.back.z,m0.s0.angle_deg,"
      "m0.acc.x_counts,m0.acc.y_counts,m0.acc.z_counts,m0.odd.x,m0.odd.z,m12.w.n_N,m12.hull.x,m12.hull.y,m12.hull.z,"
      "mx.a.x,mx.a.y,mx.a.z,m3..x,m3..y,m3..z";
  std::string row = "0";
  for (size_t i = 0; i < header.size(); ++i)
    if (header[i] == ',') row += ",1";
  RunReader r = RunReader::from_text("run", kSummary, header + "\n" + row + "\n");
  EXPECT_EQ(r.body_columns(0), (std::vector<std::string>{"m0.front", "m0.back"}));
  EXPECT_TRUE(r.body_columns(1).empty());
  EXPECT_TRUE(r.body_columns(3).empty());   // no body name
  EXPECT_TRUE(r.body_columns(-1).empty());
  EXPECT_EQ(r.body_columns(12), (std::vector<std::string>{"m12.hull"}));
  EXPECT_EQ(r.body_column_modules(), 13);
  EXPECT_EQ(RunReader::from_text("run", kSummary, "t_s,v\n0,1\n").body_column_modules(), 0);
}

TEST(RunReader, AcceptsCrlfAndBlankLines) {
  RunReader r = RunReader::from_text("run", kSummary, "t_s,v\r\n0,1\r\n\r\n1,2\r\n");
  EXPECT_EQ(*r.trace_column("v"), (std::vector<double>{1, 2}));
}

TEST(RunReader, ADamagedTraceIsAnErrorNamingTheLine) {
  EXPECT_EQ(error_of(RunReader::from_text("run", kSummary, "t_s,v\n0,1\n1\n2,3\n")),
            "run/trace.csv:3: 1 cells, the header has 2");
  EXPECT_EQ(error_of(RunReader::from_text("run", kSummary, "t_s,v\n0,1\n1,2x\n")),
            "run/trace.csv:3:3: '2x' in column 'v' is not a number");
  EXPECT_EQ(error_of(RunReader::from_text("run", kSummary, "t_s,v\n0,\n1,2\n")),
            "run/trace.csv:2:3: '' in column 'v' is not a number");
  EXPECT_EQ(error_of(RunReader::from_text("run", kSummary, "")), "run/trace.csv: empty (no header)");
  EXPECT_EQ(error_of(RunReader::from_text("run", kSummary, std::nullopt)), "run/trace.csv: cannot open");
  RunReader no_time = RunReader::from_text("run", kSummary, "v\n1\n");
  EXPECT_THROW(no_time.trace_time(), RunReadError);
}

TEST(RunReader, AMissingOrBrokenSummaryNamesTheFile) {
  chainsim_test::TempDir t("chainsim-runreader");
  RunReader missing(t.path.string());
  try {
    missing.summary();
    FAIL() << "no error";
  } catch (const RunReadError& e) {
    EXPECT_EQ(std::string(e.what()), t.file("summary.json") + ": cannot open");
  }
  std::ofstream(t.file("summary.json")) << "{\"sim_time_s\": ";
  RunReader broken(t.path.string());
  try {
    broken.summary();
    FAIL() << "no error";
  } catch (const RunReadError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(t.file("summary.json") + ": ", 0), 0u) << e.what();
  }
}

TEST(RunReader, ReadsTheBusAndEachEndpointsLogFromADirectory) {
  chainsim_test::TempDir t("chainsim-runreader");
  std::filesystem::create_directories(t.file("modules"));
  std::ofstream(t.file("bus.log")) << "1000 i2c from=2 to=0 data=01ff\n2000 fault module 1 stopped\nnot a line\n";
  std::ofstream(t.file("modules/01-helicoidal.log")) << "0.001 started\n0.5 stall 0x20\n";
  std::ofstream(t.file("modules/10-central.log")) << "0.002 other endpoint\n";
  RunReader r(t.path.string());
  const auto& bus = r.bus();
  ASSERT_EQ(bus.size(), 2u);
  EXPECT_EQ(bus[0].t_us, 1000);
  EXPECT_EQ(bus[0].field.at("data"), "01ff");
  EXPECT_EQ(bus[1].event, "fault");
  EXPECT_EQ(bus[1].text, "module 1 stopped");
  EXPECT_TRUE(bus[1].field.empty());
  const auto& log = r.log(1);
  ASSERT_EQ(log.size(), 2u);
  EXPECT_EQ(log[1].t_s, 0.5);
  EXPECT_EQ(log[1].text, "stall 0x20");
  EXPECT_TRUE(r.log(3).empty());
}

TEST(RunReader, TheStopCheckEndsALongRead) {
  std::string trace = "t_s\n";
  for (int i = 0; i < 10000; ++i) trace += std::to_string(i) + "\n";
  int asked = 0;
  RunReaderOptions o;
  o.stop = [&] { return ++asked > 1; };
  RunReader r = RunReader::from_text("run", kSummary, trace, o);
  EXPECT_THROW(r.trace_columns(), RunReadStopped);
  EXPECT_EQ(asked, 2);  // at line 0 and at line 4096
}

}  // namespace
}  // namespace chainsim
