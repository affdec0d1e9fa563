// `chainsim run` end to end: real module processes, the default scene, bad input.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <filesystem>

#include "scenario_util.h"

using namespace scenario;

TEST(Run, DefaultSceneMovesTheChainMoreThan5cmIn10SimulatedSeconds) {
  const std::string dir = temp_dir("default");
  const Outcome o = run({"--duration", "10", "--progress-every", "0.2"}, dir);
  ASSERT_EQ(o.exit_code, 0) << o.stderr_text;
  // stderr is a file here, not a terminal: progress comes as whole lines (a CI log), no carriage returns
  EXPECT_NE(o.stderr_text.find("\nchainsim: t="), std::string::npos) << o.stderr_text;
  EXPECT_NE(o.stderr_text.find("/10.00 s, "), std::string::npos) << o.stderr_text;
  EXPECT_EQ(o.stderr_text.find('\r'), std::string::npos) << o.stderr_text;
  const auto& s = o.summary;
  ASSERT_TRUE(s.is_object()) << "no summary.json";
  EXPECT_EQ(s["scene"], "snake-open-air");
  EXPECT_EQ(s["seed"], 1);
  EXPECT_NEAR(s["sim_time_s"].get<double>(), 10.0, 1e-9);
  EXPECT_GT(s["wall_time_s"].get<double>(), 0.0);
  EXPECT_GT(s["real_time_factor"].get<double>(), 0.0);
  const auto& d = s["chain"]["displacement_m"];
  ASSERT_EQ(d.size(), 3u);
  // forward is the head's direction, +x for the default placement
  EXPECT_GT(d[0].get<double>(), 0.05) << "the chain moved only " << d[0] << " m forward";
  EXPECT_LT(std::fabs(d[1].get<double>()), std::fabs(d[0].get<double>()));
  EXPECT_GT(s["chain"]["speed_m_s"].get<double>(), 0.005);
  // eight rotation modules and the central control, each its own process
  ASSERT_EQ(s["modules"].size(), 9u);
  std::set<int> pids;
  for (int i = 0; i < 9; ++i) {
    const auto& m = s["modules"][i];
    EXPECT_EQ(m["index"], i);
    EXPECT_EQ(m["type"], i < 8 ? "rotation" : "central");
    EXPECT_TRUE(m["fault"].is_null()) << m["fault"];
    // discovery's answer: position k took address 0x20 + k, the central control 0x10
    char want[8];
    std::snprintf(want, sizeof want, "0x%02x", i < 8 ? 0x20 + i : 0x10);
    EXPECT_EQ(m["i2c_address"], want) << m;
    EXPECT_GE(m["addressed_at_s"].get<double>(), 0.0) << m;
    EXPECT_LT(m["addressed_at_s"].get<double>(), 2.0) << m;
    pids.insert(m["pid"].get<int>());
  }
  EXPECT_EQ(pids.size(), 9u);
  EXPECT_EQ(s["trace_sha256"], sha256_file(o.dir + "/trace.csv"));
  // the central control discovered the chain through the sync lines and commanded it over I2C
  const std::string central_log = read_file(o.dir + "/modules/08-central.log");
  EXPECT_NE(central_log.find("RRRRRRRR"), std::string::npos) << central_log;
  const std::string bus = read_file(o.dir + "/bus.log");
  EXPECT_NE(bus.find("i2c from=8"), std::string::npos);
  EXPECT_NE(bus.find("sync endpoint=0 sout=1"), std::string::npos);
}

TEST(Run, MalformedSceneIsRejectedWithFileLineAndColumn) {
  const std::string dir = temp_dir("badscene");
  const std::string scene = write_file(dir, "bad.yaml", "chain: RR\nphysics:\n  dt_us: fast\n");
  const Outcome o = run({scene}, dir);
  EXPECT_EQ(o.exit_code, 1);
  EXPECT_NE(o.stderr_text.find("bad.yaml:3:10"), std::string::npos) << o.stderr_text;
  EXPECT_NE(o.stderr_text.find("dt_us"), std::string::npos) << o.stderr_text;
}

TEST(Run, MissingModuleProgramIsNamed) {
  const std::string dir = temp_dir("noprog");
  const std::string scene =
      write_file(dir, "s.yaml", "chain:\n  - {type: rotation}\n  - {type: rotation, firmware: /nonexistent/fw}\n");
  const Outcome o = run({scene, "--duration", "0.1"}, dir);
  EXPECT_EQ(o.exit_code, 1);
  // named at the key, before any module starts (no run directory)
  EXPECT_NE(o.stderr_text.find(scene + ":3:32: program '/nonexistent/fw' of module 1 (rotation) not found or not "
                                        "executable: /nonexistent/fw"),
            std::string::npos)
      << o.stderr_text;
  EXPECT_FALSE(o.summary.is_object());
}

// --check does everything before the first process and nothing after: no
// program started, no file written, the same errors as a run
TEST(Run, CheckBuildsTheSceneAndFindsItsProgramsWithoutRunningAnything) {
  const std::string dir = temp_dir("check");
  const std::string marker = dir + "/started";
  const std::string prog = write_file(dir, "central.sh", "#!/bin/sh\ntouch " + marker + "\n");
  ASSERT_EQ(chmod(prog.c_str(), 0755), 0);
  const std::string good = write_file(dir, "good.yaml", "chain: RR\ncentral: {program: " + prog + "}\n");
  const std::string out = dir + "/out";
  const auto check = [&](const std::vector<std::string>& args) {
    std::vector<std::string> all{"run"};
    all.insert(all.end(), args.begin(), args.end());
    const std::string err = dir + "/stderr.txt";
    return wait_chainsim(start_chainsim(all, err), out, err);
  };
  // its one line goes to stdout, which this harness does not keep: stderr is empty
  Outcome o = check({good, "--check", "--out", out});
  EXPECT_EQ(o.exit_code, 0) << o.stderr_text;
  EXPECT_EQ(o.stderr_text, "");
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_FALSE(std::filesystem::exists(marker));
  // a missing program, a missing mesh, a tick longer than --duration: exit 1, named
  const std::string no_prog =
      write_file(dir, "noprog.yaml", "chain:\n  - {type: rotation, firmware: " + dir + "/nope}\n");
  o = check({no_prog, "--check"});
  EXPECT_EQ(o.exit_code, 1);
  EXPECT_EQ(o.stderr_text, "chainsim: " + no_prog + ":2:32: program '" + dir + "/nope' of module 0 (rotation) not found or not executable: " + dir + "/nope\n");
  const std::string no_mesh =
      write_file(dir, "nomesh.yaml", "chain: R\nenvironment:\n  type: mesh\n  mesh: {file: none.stl}\n");
  o = check({no_mesh, "--check"});
  EXPECT_EQ(o.exit_code, 1);
  EXPECT_NE(o.stderr_text.find(dir + "/none.stl"), std::string::npos) << o.stderr_text;
  o = check({good, "--check", "--duration", "0.0005"});
  EXPECT_EQ(o.exit_code, 1);
  EXPECT_EQ(o.stderr_text,
            "chainsim: --duration 0.000500 s is shorter than one tick of the scene (physics.tick_us = 1000 us)\n");
  EXPECT_FALSE(std::filesystem::exists(marker));
}

// stop_when ends a run early as a finished one (exit 0), says why in
// summary.json (and on stderr, unless quiet), and leaves the trace as it was up to there
TEST(Run, StopWhenEndsTheRunEarlyAndTheTraceUpToThereIsTheFullRunsOwn) {
  const Outcome full = run_scene("stop-full", "helicoidal-0", 2.0);
  ASSERT_EQ(full.exit_code, 0) << full.stderr_text;
  EXPECT_TRUE(full.summary["early_stop"].is_null());
  // 3 cm/s along the pipe: 5 cm by 1 s cannot be reached
  const Outcome cut = run_scene("stop-cut", "helicoidal-0", 2.0,
                                {{"name: helicoidal-0", "name: helicoidal-0\nstop_when:\n"
                                                        "  - not_reached: {along: pipe, reach_m: 0.5, by_s: 1}"}});
  ASSERT_EQ(cut.exit_code, 0) << cut.stderr_text;
  const std::string why = cut.summary["early_stop"].get<std::string>();
  EXPECT_EQ(why.rfind("early stop at 1.010 s: the head got no further than ", 0), 0u) << why;
  EXPECT_NEAR(cut.summary["sim_time_s"].get<double>(), 1.01, 1e-9);
  EXPECT_TRUE(cut.summary["stopped_by"].is_null());
  const std::string a = read_file(full.dir + "/trace.csv"), b = read_file(cut.dir + "/trace.csv");
  ASSERT_LT(b.size(), a.size());
  EXPECT_EQ(a.substr(0, b.size()), b);
}
