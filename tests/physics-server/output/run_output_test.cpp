// The run directory on disk: the files RunOutput writes, their formats, the
// trace hash, and summary/scene json replaced atomically.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>

#include "text/number_text.h"
#include "output/run_output.h"
#include "output/run_summary.h"
#include "output/sha256.h"
#include "temp_dir.h"

namespace chainsim {
namespace {

namespace fs = std::filesystem;

struct TempDir : chainsim_test::TempDir {
  TempDir() : chainsim_test::TempDir("chainsim-out") {}
};

std::string read_file(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string sha256_of(const std::string& bytes) {
  Sha256 h;
  h.update(bytes.data(), bytes.size());
  return h.hex();
}

TEST(Sha256, KnownDigests) {
  EXPECT_EQ(sha256_of(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_of("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

TEST(RunOutput, CreatesTheDirectoryAndWritesEachFileInItsFormat) {
  TempDir d;
  const fs::path dir = d.path / "runs" / "one";
  {
    RunOutput out(dir.string(), {"rotation", "passive", "central"});
    EXPECT_TRUE(fs::is_directory(dir / "modules"));
    EXPECT_EQ(out.module_file(2, "log"), (dir / "modules/02-central.log").string());
    out.trace("t_s,a\n");
    out.trace("0.000000,1\n");
    out.bus(1500, "sync endpoint=0 sout=1");
    out.bus(2000, "i2c from=2 to=0x10");
    out.module_log(0, 12000500, "hello");
    out.module_log(0, 12001000, "again");
    out.flush();
    // flushed: readable while the run goes on
    EXPECT_EQ(read_file(dir / "trace.csv"), "t_s,a\n0.000000,1\n");
    EXPECT_EQ(read_file(dir / "bus.log"), "1500 sync endpoint=0 sout=1\n2000 i2c from=2 to=0x10\n");
    EXPECT_EQ(read_file(dir / "modules/00-rotation.log"), "12.000500 hello\n12.001000 again\n");
    // every endpoint's log exists from the start, empty until it logs
    EXPECT_TRUE(fs::is_regular_file(dir / "modules/01-passive.log"));
    EXPECT_EQ(read_file(dir / "modules/01-passive.log"), "");
    EXPECT_EQ(out.trace_bytes(), 17u);
  }
}

TEST(RunOutput, TraceHashIsTheHashOfTheFile) {
  TempDir d;
  RunOutput out(d.path.string(), {"central"});
  std::string all;
  for (int k = 0; k < 1000; ++k) {
    const std::string row = seconds_text(k * 500) + "," + fixed_text(k * 0.1, 4) + "\n";
    out.trace(row);
    all += row;
  }
  out.flush();
  const std::string h = out.trace_sha256();
  EXPECT_EQ(h, sha256_of(read_file(d.path / "trace.csv")));
  EXPECT_EQ(h, sha256_of(all));
  EXPECT_EQ(out.trace_sha256(), h);  // asked again: the same
}

// what is on disk at any moment ends on a whole row, so a server killed
// outright (no flush of its own) leaves no torn row; rows of 97 bytes do not
// divide the 64 KiB buffer, which stdio would write out mid-row
TEST(RunOutput, TraceReachesTheFileInWholeRowsOnly) {
  TempDir d;
  RunOutput out(d.path.string(), {"central"});
  const std::string row = std::string(96, '7') + "\n";
  size_t seen_growing = 0;
  for (int k = 0; k < 3000; ++k) {
    out.trace(row);
    const auto on_disk = fs::file_size(d.path / "trace.csv");
    ASSERT_EQ(on_disk % row.size(), 0u) << "after row " << k << ": " << on_disk << " bytes";
    seen_growing += on_disk > 0;
  }
  EXPECT_GT(seen_growing, 0u);  // written as it went, not only at the end
}

TEST(RunOutput, DestructorFlushesEverything) {
  TempDir d;
  {
    RunOutput out(d.path.string(), {"touch", "central"});
    out.trace("t_s\n");
    out.bus(0, "touch endpoint=0 level=1");
    out.module_log(1, 0, "chain T");
  }
  EXPECT_EQ(read_file(d.path / "trace.csv"), "t_s\n");
  EXPECT_EQ(read_file(d.path / "bus.log"), "0 touch endpoint=0 level=1\n");
  EXPECT_EQ(read_file(d.path / "modules/01-central.log"), "0.000000 chain T\n");
}

// a reader that opened the old summary keeps the old bytes, one that opens
// it after sees all of the new: replaced by rename, never rewritten in place
TEST(RunOutput, JsonFilesAreReplacedAtomically) {
  TempDir d;
  RunOutput out(d.path.string(), {"central"});
  out.write_summary({{"sim_time_s", 1.5}, {"stopped_by", nullptr}});
  const std::string first = read_file(d.path / "summary.json");
  EXPECT_EQ(nlohmann::json::parse(first)["sim_time_s"], 1.5);
  const int old_fd = open((d.path / "summary.json").c_str(), O_RDONLY);
  ASSERT_GE(old_fd, 0);
  out.write_summary({{"sim_time_s", 10.0}, {"stopped_by", "interrupted"}});
  std::string kept(first.size() + 16, '\0');
  const ssize_t n = read(old_fd, kept.data(), kept.size());
  close(old_fd);
  kept.resize(n > 0 ? static_cast<size_t>(n) : 0);
  EXPECT_EQ(kept, first);
  const nlohmann::json now = nlohmann::json::parse(read_file(d.path / "summary.json"));
  EXPECT_EQ(now["sim_time_s"], 10.0);
  EXPECT_EQ(now["stopped_by"], "interrupted");
  EXPECT_FALSE(fs::exists(d.path / "summary.json.tmp"));
  out.write_json("scene.json", {{"scene", "x"}});
  EXPECT_EQ(read_file(d.path / "scene.json"), "{\n  \"scene\": \"x\"\n}\n");
}

TEST(RunOutput, UnwritableDirectoryIsNamed) {
  TempDir d;
  std::ofstream(d.path / "file") << "not a directory";
  const std::string dir = (d.path / "file" / "run").string();
  try {
    RunOutput out(dir, {"central"});
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("cannot create run directory " + dir + ": ", 0), 0u) << e.what();
  }
}

TEST(RunOutput, JsonThatCannotBeWrittenIsNamedAndTheOldFileKept) {
  TempDir d;
  RunOutput out(d.path.string(), {"central"});
  out.write_summary({{"a", 1}});
  fs::create_directory(d.path / "summary.json.tmp");  // the temp file cannot be opened
  try {
    out.write_summary({{"a", 2}});
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "cannot write " + (d.path / "summary.json.tmp").string() + ": Is a directory");
  }
  EXPECT_EQ(nlohmann::json::parse(read_file(d.path / "summary.json"))["a"], 1);
}

TEST(Decimal, FormatsAreExactAndPrintfs) {
  EXPECT_EQ(seconds_text(0), "0.000000");
  EXPECT_EQ(seconds_text(12000500), "12.000500");
  EXPECT_EQ(seconds_text(86400000001), "86400.000001");
  EXPECT_EQ(fixed_text(1.23456, 4), "1.2346");
  EXPECT_EQ(fixed_text(-0.00004, 4), "-0.0000");  // as printf: the sign stays
  EXPECT_EQ(fixed_text(2.5, 0), "2");             // as printf: halves to even
  EXPECT_EQ(fixed_text(10.0, 1), "10.0");
  std::string s = "x";
  append_fixed(&s, 0.1, 6);
  append_seconds(&s, 1);
  EXPECT_EQ(s, "x0.1000000.000001");
}

// fixed_text is printf's "%.Nf", byte for byte, for numbers of every size,
// halfway cases, signed zeros and the non-finite values
TEST(Decimal, FixedTextIsPrintfsTextForAnyDouble) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-30, 30), places(0, 20);
  std::vector<double> values = {0.0, -0.0, 0.5, 1.5, 2.5, -2.5, 0.125, 1e-300, 1.7976931348623157e308,
                                std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                                std::nan("")};
  for (int i = 0; i < 200000; ++i) values.push_back(std::ldexp(mantissa(rng), exponent(rng)));
  int checked = 0;
  for (double v : values) {
    const int n = places(rng);
    char buf[400];
    std::snprintf(buf, sizeof buf, "%.*f", n, v);
    ASSERT_EQ(fixed_text(v, n), buf) << "value " << v << " with " << n << " decimals";
    ++checked;
  }
  EXPECT_EQ(checked, 200012);
}

TEST(RunSummary, CarriesTheRunAndEachEndpoint) {
  Scene scene;
  scene.name = "snake";
  scene.source = "scenes/snake.yaml";
  scene.world.seed = 9;
  scene.world.dt_us = 250;
  scene.tick_us = 1000;
  RunSummary r;
  r.sim_time_us = 2000000;
  r.wall_time_s = 4.0;
  r.limp_mode = true;
  r.trace_sha256 = "abc";
  r.exchanges = 12;
  EndpointSummary m0, c;
  m0.index = 0, m0.type = "rotation", m0.program = "fw-rotation", m0.pid = 42, m0.exchanges = 7, m0.energy_j = 0.25;
  c.index = 1, c.type = "central", c.program = "fw-central", c.pid = 43, c.fault = "crashed", c.exchanges = 5;
  r.endpoints = {m0, c};
  r.displacement_m = Eigen::Vector3d(0.3, 0.4, 0);
  r.exit_code = 2;
  r.stopped_by = "module 0 crashed";
  const nlohmann::json j = summary_json(scene, r);
  EXPECT_EQ(j["scene"], "snake");
  EXPECT_EQ(j["scene_source"], "scenes/snake.yaml");
  EXPECT_EQ(j["seed"], 9);
  EXPECT_EQ(j["sim_time_s"], 2.0);
  EXPECT_EQ(j["real_time_factor"], 0.5);
  EXPECT_EQ(j["dt_us"], 250);
  EXPECT_EQ(j["tick_us"], 1000);
  EXPECT_EQ(j["on_module_fault"], "limp");
  EXPECT_EQ(j["trace_file"], "trace.csv");
  EXPECT_EQ(j["trace_sha256"], "abc");
  EXPECT_EQ(j["exchanges"], 12);
  EXPECT_EQ(j["chain"]["distance_m"], 0.5);
  EXPECT_EQ(j["chain"]["speed_m_s"], 0.25);
  EXPECT_EQ(j["exit_code"], 2);
  EXPECT_EQ(j["stopped_by"], "module 0 crashed");
  ASSERT_EQ(j["modules"].size(), 2u);
  EXPECT_TRUE(j["modules"][0]["fault"].is_null());
  EXPECT_EQ(j["modules"][0]["energy_j"], 0.25);
  EXPECT_EQ(j["modules"][1]["fault"], "crashed");
  EXPECT_FALSE(j["modules"][1].contains("energy_j"));  // the central control has no motors
  r.stopped_by.clear();
  r.sim_time_us = 0;
  r.wall_time_s = 0;
  const nlohmann::json k = summary_json(scene, r);
  EXPECT_TRUE(k["stopped_by"].is_null());
  EXPECT_EQ(k["chain"]["speed_m_s"], 0.0);
  EXPECT_EQ(k["real_time_factor"], 0.0);
}

TEST(RunSummary, NamesTheSolverWithItsIterationsOrItsDegenerateSteps) {
  Scene scene;
  scene.world.solver_iterations = 45;
  RunSummary r;
  r.degenerate_lcp_steps = 3;  // not the QuickStep's business: not shown
  const nlohmann::json q = summary_json(scene, r)["solver"];
  EXPECT_EQ(q, (nlohmann::json{{"name", "quickstep"}, {"iterations", 45}})) << q.dump();
  scene.world.solver = WorldConfig::Solver::Exact;
  const nlohmann::json e = summary_json(scene, r)["solver"];
  EXPECT_EQ(e, (nlohmann::json{{"name", "exact"}, {"degenerate_lcp_steps", 3}})) << e.dump();
}

}  // namespace
}  // namespace chainsim
