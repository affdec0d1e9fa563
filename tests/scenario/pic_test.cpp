// The board's own binaries in the loop (docs/pic-in-the-loop.md): the
// shipped scenes with every program's .hex in gpsim (chainsim-pic), against
// the same scenes with the programs built for this computer. They need the
// PIC build (tools/pic-build.sh, which the test command runs first); without
// it they are skipped with the reason.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>

#include "pic_tree.h"
#include "scenario_util.h"

using namespace scenario;

namespace {

#define REQUIRE_PIC_BUILD()                                                                               \
  if (!tree_pic_built())                                                                                  \
  GTEST_SKIP() << "the PIC build is missing (" << tree_pic_dir()                                          \
               << "/fw-rotation.hex, fw-central.hex): run tools/pic-build.sh, as tools/test-all.sh does"

nlohmann::json read_json(const std::string& path) {
  std::ifstream f(path);
  return nlohmann::json::parse(f);
}

double speed(const Outcome& o) { return o.summary["chain"]["speed_m_s"].get<double>(); }

}  // namespace

TEST(PicInTheLoop, TheDefaultSnakeOnTheBoardsBinariesMovesAsTheNativeOneAndComparesChannelByChannel) {
  REQUIRE_PIC_BUILD();
  const std::string dir = temp_dir("pic-default");
  const auto [text, code] = chainsim_stdout("run --compare native,pic --duration 6 -q --out " + dir);
  ASSERT_EQ(code, 0) << text;
  const nlohmann::json n = read_json(dir + "/native/summary.json"), p = read_json(dir + "/pic/summary.json");
  // every module on the PIC took its address in discovery, and ran its steps
  for (const auto& m : p["modules"]) {
    EXPECT_EQ(m["target"], "pic");
    EXPECT_FALSE(m["i2c_address"].is_null()) << m.dump();
    EXPECT_GT(m["pic"]["cpu"]["steps"].get<int>(), 10) << m.dump();
    EXPECT_GT(m["pic"]["stack"]["hardware_levels_high"].get<int>(), 2);
    EXPECT_LT(m["pic"]["stack"]["hardware_levels_high"].get<int>(), 31);
    EXPECT_GT(m["pic"]["stack"]["software_bytes_high"].get<int>(), 8);
    EXPECT_EQ(m["pic"]["memory"]["flash_total"], 32768);
  }
  for (const auto& m : n["modules"]) EXPECT_EQ(m["target"], "native");
  // every servo pulse the boards sent lay within 0.5-2.5 ms (a pulse outside
  // is a glitch of the firmware's pulse schedule or of the simulated chip)
  int pic_reports = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir + "/pic/modules")) {
    const std::string f = e.path().string();
    if (f.size() < 9 || f.compare(f.size() - 9, 9, ".pic.json") != 0) continue;
    ++pic_reports;
    EXPECT_EQ(read_json(f)["pins"]["servo_glitches"], 0) << f;
  }
  EXPECT_EQ(pic_reports, static_cast<int>(p["modules"].size()));
  // a rotation module's gait step takes a few ms of its 10 ms period on the board
  const auto& cpu = p["modules"][3]["pic"]["cpu"];
  EXPECT_GT(cpu["busy_mean_us"].get<double>(), 1000.0);
  EXPECT_LT(cpu["busy_worst_us"].get<double>(), 10000.0);
  EXPECT_NEAR(cpu["period_mean_us"].get<double>(), 10000.0, 200.0);
  // the same gait, so nearly the same motion (measured over 10 s: 0.3002
  // against 0.2979 m, the board's gait starting 80 ms later)
  const double dn = n["chain"]["distance_m"].get<double>(), dp = p["chain"]["distance_m"].get<double>();
  EXPECT_GT(dn, 0.1);
  EXPECT_NEAR(dp, dn, 0.05 * dn);
  EXPECT_NE(read_file(dir + "/pic/modules/08-central.log").find("chain: RRRRRRRR (8 modules)"), std::string::npos);

  const nlohmann::json c = read_json(dir + "/compare.json");
  // the board starts the gait later: discovery and the commands take longer
  // on its I2C (a 40-byte send queue, each frame 1.7 ms on the wire)
  const auto& central = c["endpoints"][8];
  ASSERT_FALSE(central["divergences"].empty());
  EXPECT_EQ(central["divergences"][0]["channel"], "log");
  EXPECT_EQ(central["divergences"][0]["a"].get<std::string>().rfind("start at ms ", 0), 0u);
  EXPECT_GE(central["channels"]["log"]["agreed"].get<int>(), 2) << "the chain and the gait lines agree";
  EXPECT_GE(central["channels"]["i2c"]["agreed"].get<int>(), 16) << "discovery and SET_GAIT frames agree";
  // and then every set-point follows the native one, some 80 ms later
  ASSERT_EQ(c["setpoint_lags"].size(), 16u);
  for (const auto& l : c["setpoint_lags"]) {
    EXPECT_GT(l["lag_s"].get<double>(), 0.03) << l.dump();
    EXPECT_LT(l["lag_s"].get<double>(), 0.15) << l.dump();
    EXPECT_LT(l["rms"].get<double>(), l["rms_unshifted"].get<double>() / 3) << l.dump();
  }
  EXPECT_NE(read_file(dir + "/compare.txt").find("first divergence of each endpoint"), std::string::npos);
}

TEST(PicInTheLoop, SameSceneAndSeedGiveTheSameBytesOnThePicToo) {
  REQUIRE_PIC_BUILD();
  const std::string dir = temp_dir("pic-det");
  const Outcome a = run({"--target", "pic", "--duration", "1", "--seed", "3", "-q"}, dir + "/a");
  const Outcome b = run({"--target", "pic", "--duration", "1", "--seed", "3", "-q"}, dir + "/b");
  ASSERT_EQ(a.exit_code, 0) << a.stderr_text;
  ASSERT_EQ(b.exit_code, 0) << b.stderr_text;
  EXPECT_EQ(a.summary["trace_sha256"], b.summary["trace_sha256"]);
  EXPECT_EQ(read_file(a.dir + "/bus.log"), read_file(b.dir + "/bus.log"));
  EXPECT_EQ(read_file(a.dir + "/modules/08-central.log"), read_file(b.dir + "/modules/08-central.log"));
  EXPECT_EQ(a.summary["modules"][0]["pic"]["cpu"], b.summary["modules"][0]["pic"]["cpu"]);
}

TEST(PicInTheLoop, TheInchwormOnTheBoardsBinariesCrawlsAsFast) {
  REQUIRE_PIC_BUILD();
  const Outcome p = run_scene("pic-inchworm", "inchworm-0", 6.0, {{"chain: SES", "chain: SES\ntarget: pic"}});
  const Outcome n = run_scene("native-inchworm", "inchworm-0", 6.0);
  ASSERT_EQ(p.exit_code, 0) << p.stderr_text;
  ASSERT_EQ(n.exit_code, 0) << n.stderr_text;
  for (const auto& m : p.summary["modules"]) EXPECT_EQ(m["target"], "pic");
  // The board's speed depends on when the gait starts against its servos'
  // 20 ms pulse frame (a step's set-point waits for the next frame): over 6 s
  // 2.20-2.22 cm/s for about 12 ms of each 20 ms of START times and
  // 1.94-1.98 (0.85-0.87 of native) for the rest (start_ms 80-116,
  // 2026-11-29), native 2.15-2.28
  // for any start (docs/pic-in-the-loop.md)
  EXPECT_GT(speed(n), 0.015);
  EXPECT_GT(speed(p), 0.80 * speed(n));
  EXPECT_LT(speed(p), 1.05 * speed(n));
}

TEST(PicInTheLoop, TheElbowWithTouchAndHelicoidalModulesOnTheBoardsBinaries) {
  REQUIRE_PIC_BUILD();
  const Outcome p = run_scene("pic-elbow", "elbow-TRRH", 30.0, {{"chain: TRRH", "chain: TRRH\ntarget: pic"}});
  ASSERT_EQ(p.exit_code, 0) << p.stderr_text;
  const std::string log = central_log(p, 4);
  EXPECT_NE(log.find("chain: TRRH (4 modules)"), std::string::npos) << log;
  EXPECT_NE(log.find("touch 0x20: contact"), std::string::npos) << "the touch module's board saw the wall:\n" << log;
  // the drive's command through the board's servo pulse: full speed is a
  // 2.0 ms pulse, exactly 1 (it was 0.972 when the firmware used 5.6 us of
  // the pulse's range)
  const auto tr = read_trace(p.dir + "/trace.csv");
  const auto& cmd = tr.at("m3.s0.command");
  EXPECT_EQ(*std::max_element(cmd.begin(), cmd.end()), 1.0);
  EXPECT_GT(speed(p), 0.005);
  // the rotation modules' boards take the bend the central control sends at
  // the elbow (16.7-17 s): their yaw set-points reach its -38.95 deg. They
  // stayed at 0, limp, while an edge at Timer3 = 0 stopped the boards'
  // servo pulses for good (gpsim never matches a compare at 0), 16.4 s in
  ASSERT_FALSE(log_times(log, "elbow: bend").empty()) << log;
  for (const char* yaw : {"m1.s1.setpoint_deg", "m2.s1.setpoint_deg"}) {
    const auto& sp = tr.at(yaw);
    EXPECT_LT(*std::min_element(sp.begin(), sp.end()), -38.0) << yaw;
  }
}

// a board's servo keeps its pulses, 50 a second, however long the run: a
// rotation module idle at 0 deg (no gait) for 42 s has its slot 0's falling
// edge at Timer3 = 0 at 16.4 s and slot 7's start there at 41 s, where gpsim
// matches no compare (hal-pic/hal_servo.c moves such an edge one count on)
TEST(PicInTheLoop, ABoardsServosKeepTheirPulsesPastTimer3AtZero) {
  REQUIRE_PIC_BUILD();
  const double duration = 42.0;
  const Outcome o = run_scene("pic-idle", "default", duration,
                              {{"chain: RRRRRRRR", "chain: R\nprograms:\n  rotation: {target: pic}"},
                               {"gait: 1 ", "gait: 0 "}});
  ASSERT_EQ(o.exit_code, 0) << o.stderr_text;
  const auto& pins = o.summary["modules"][0]["pic"]["pins"];
  ASSERT_EQ(pins["servo_pulses"].size(), 2u) << pins.dump();
  for (const auto& n : pins["servo_pulses"]) EXPECT_GE(n.get<double>(), 50 * duration - 5) << pins.dump();
  EXPECT_EQ(pins["servo_glitches"], 0);
}

TEST(PicInTheLoop, NativeAndPicModulesMixInOneChain) {
  REQUIRE_PIC_BUILD();
  const std::string dir = temp_dir("pic-mixed");
  const std::string scene = write_file(dir, "mixed.yaml",
                                       "name: mixed\nduration_s: 2\nchain:\n"
                                       "  - {type: rotation, target: pic}\n  - {type: rotation}\n"
                                       "  - {type: rotation, target: pic}\n  - {type: rotation}\n"
                                       "central: {target: pic}\n");
  const Outcome o = run({scene, "-q"}, dir);
  ASSERT_EQ(o.exit_code, 0) << o.stderr_text;
  const char* want[] = {"pic", "native", "pic", "native", "pic"};
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(o.summary["modules"][i]["target"], want[i]);
    EXPECT_EQ(o.summary["modules"][i].contains("pic"), std::string(want[i]) == "pic");
    EXPECT_FALSE(o.summary["modules"][i]["i2c_address"].is_null());
  }
  EXPECT_NE(central_log(o, 4).find("chain: RRRR (4 modules)"), std::string::npos);
}

TEST(PicInTheLoop, AStepOverTheCpuBudgetIsANamedFaultOrAWarning) {
  REQUIRE_PIC_BUILD();
  const std::string dir = temp_dir("pic-budget");
  // a rotation module's gait step takes about 4 ms: a 2 ms budget is
  // overrun (the central control, native here, has no budget)
  const std::string scene = write_file(dir, "tight.yaml",
                                       "name: tight\nduration_s: 1\nchain: RR\ntarget: pic\n"
                                       "central: {target: native}\npic: {cpu_budget_us: 2000}\n");
  const Outcome stop = run({scene, "-q"}, dir);
  EXPECT_EQ(stop.exit_code, 2) << stop.stderr_text;
  EXPECT_NE(stop.stderr_text.find("took more than its CPU budget of 2000 us of busy time"), std::string::npos)
      << stop.stderr_text;
  EXPECT_NE(stop.stderr_text.find("module 0 (rotation"), std::string::npos) << stop.stderr_text;
  // where: the instruction that went over, its function and C line
  EXPECT_TRUE(std::regex_search(stop.stderr_text, std::regex(R"(, at 0x[0-9A-F]{4} in \w+\(\), /\S+\.c:\d+ \()")))
      << stop.stderr_text;
  const Outcome warn = run({scene, "-q", "--on-overrun", "warn"}, temp_dir("pic-budget-warn"));
  ASSERT_EQ(warn.exit_code, 0) << warn.stderr_text;
  const auto& cpu = warn.summary["modules"][0]["pic"]["cpu"];
  EXPECT_EQ(cpu["budget_us"], 2000);
  EXPECT_GT(cpu["overruns"].get<int>(), 10);
  EXPECT_GT(cpu["busy_worst_us"].get<double>(), 2000.0);
  EXPECT_NE(read_file(warn.dir + "/modules/00-rotation.out").find("warning: a step of the program took more than"),
            std::string::npos);
}

TEST(PicInTheLoop, AMissingHexIsNamedWithHowToBuildIt) {
  REQUIRE_PIC_BUILD();
  const std::string dir = temp_dir("pic-missing");
  const std::string scene = write_file(dir, "s.yaml",
                                       "name: s\nduration_s: 1\nchain: R\ntarget: pic\n"
                                       "programs: {rotation: {firmware: fw-nothing}}\n");
  const Outcome o = run({scene, "-q", "--firmware-dir", dir}, dir);
  EXPECT_EQ(o.exit_code, 1);
  EXPECT_NE(o.stderr_text.find("s.yaml:4:9: module 0 (rotation) runs on the PIC: fw-nothing.hex not found "
                               "(looked in --firmware-dir " + dir),
            std::string::npos)
      << o.stderr_text;
  EXPECT_NE(o.stderr_text.find("build the shipped programs with tools/pic-build.sh"), std::string::npos);
}

TEST(PicInTheLoop, CheckRefusesASensorChannelTheBoardLacks) {
  REQUIRE_PIC_BUILD();
  const std::string dir = temp_dir("pic-check");
  const std::string scene = write_file(
      dir, "s.yaml",
      "name: s\nduration_s: 1\nchain: [{type: probe, may_stay_silent: true}]\n"
      "programs: {probe: {firmware: fw-passive}}\n"
      "module_types: {probe: probe.yaml}\n");
  write_file(dir, "probe.yaml",
             "type: probe\n"
             "bodies: [{name: a, shape: box, size_m: [0.02, 0.02, 0.02], mass_kg: 0.01}]\n"
             "sensors: [{name: accel, type: accelerometer, body: a, channel: 5}]\n"
             "docking: {front: {body: a, position_m: [0.01, 0, 0]}, back: {body: a, position_m: [-0.01, 0, 0]}}\n");
  const auto native = chainsim_stdout("run " + scene + " --check");
  EXPECT_EQ(native.second, 0) << native.first;
  const auto pic = chainsim_stdout("run " + scene + " --check --target pic");
  EXPECT_EQ(pic.second, 1) << pic.first;
  EXPECT_NE(pic.first.find("module 0 (probe) runs on the PIC, and its module type does not fit the board: sensor "
                           "'accel' reads ADC channels 5..7"),
            std::string::npos)
      << pic.first;
}

TEST(PicInTheLoop, ChainsimTestRunsEachTestOnBothTargetsAndComparesThem) {
  REQUIRE_PIC_BUILD();
  const std::string dir = temp_dir("pic-test-compare");
  const std::string scene = write_file(dir, "s.yaml", "name: s\nduration_s: 1.5\nchain: RRRR\n");
  write_file(dir, "crawl.test.yaml",
             "name: crawl\nscene: s.yaml\nexpect:\n  - no_faults\n"
             "  - \"log central /chain: RRRR \\\\(4 modules\\\\)/ before 0.2\"\n");
  (void)scene;
  const auto [text, code] = chainsim_stdout("test " + dir + "/crawl.test.yaml --compare native,pic --keep " + dir +
                                            "/runs --junit " + dir + "/j.xml");
  EXPECT_EQ(code, 0) << text;
  EXPECT_NE(text.find("PASS  crawl on native seed 1"), std::string::npos) << text;
  EXPECT_NE(text.find("PASS  crawl on pic seed 1"), std::string::npos) << text;
  EXPECT_NE(text.find("COMPARE crawl seed 1: first divergence: central control (central), log: \"start at ms"),
            std::string::npos)
      << text;
  EXPECT_NE(read_file(dir + "/runs/crawl-seed1-compare.txt").find("first divergence of each endpoint"),
            std::string::npos);
  const std::string junit = read_file(dir + "/j.xml");
  EXPECT_NE(junit.find("crawl on pic"), std::string::npos) << junit;
  // --target pic runs every test on the board's binaries only
  const auto [t2, c2] = chainsim_stdout("test " + dir + "/crawl.test.yaml --target pic --keep " + dir + "/runs2");
  EXPECT_EQ(c2, 0) << t2;
  EXPECT_EQ(read_json(dir + "/runs2/crawl-seed1/summary.json")["modules"][0]["target"], "pic");
}

// every shipped program on the board: each module type answers the central
// control's READ_SENSORS through its own board's I2C (the traveller's three
// encoder inputs counting included)
TEST(PicInTheLoop, EveryModuleTypesBoardAnswersReadSensors) {
  REQUIRE_PIC_BUILD();
  const std::string dir = temp_dir("pic-sensors");
  const std::string scene = write_file(dir, "s.yaml",
                                       "chain: THSEWPR\nduration_s: 0.6\ntarget: pic\n"
                                       "central:\n  params: {gait: 0, poll_ms: 200}\n");
  const Outcome o = run({scene, "-q"}, dir);
  ASSERT_EQ(o.exit_code, 0) << o.stderr_text;
  const std::string log = central_log(o, 7);
  EXPECT_EQ(log.find("unexpected frame"), std::string::npos) << log;
  // values per type: touch 4, helicoidal 2, support 2, extension 3, traveller 4, passive 0, rotation 2
  const int nvals[] = {4, 2, 2, 3, 4, 0, 2};
  for (int k = 0; k < 7; ++k) {
    char want[32];
    std::snprintf(want, sizeof want, "sensors 0x%02x:", 0x20 + k);
    const size_t at = log.find(want);
    ASSERT_NE(at, std::string::npos) << want << "\n" << log;
    const std::string line = log.substr(at, log.find('\n', at) - at);
    EXPECT_EQ(std::count(line.begin(), line.end(), ' ') - 1, nvals[k]) << line;
  }
  // the still chain's traveller counted nothing; the touch module's
  // accelerometer reads 1 g up on z (683 counts), through the board's ADC
  EXPECT_NE(log.find("sensors 0x24: 0 0 0 0"), std::string::npos) << log;
  const size_t t = log.find("sensors 0x20: ");
  ASSERT_NE(t, std::string::npos);
  int contact = -1, x = 0, y = 0, z = 0;
  ASSERT_EQ(std::sscanf(log.c_str() + t, "sensors 0x20: %d %d %d %d", &contact, &x, &y, &z), 4);
  EXPECT_NEAR(z, 683, 3);
  EXPECT_NEAR(x, 512, 3);
}

// the traveller's wheels through the board's counter inputs: pulses counted
// on T13CKI, RB4 and INT2, but without direction (the board's counters have
// none: the native build's signed counts go backwards, the board's do not)
TEST(PicInTheLoop, TheTravellersBoardCountsItsWheelsWithoutDirection) {
  REQUIRE_PIC_BUILD();
  const std::string dir = temp_dir("pic-traveller");
  const std::string scene = write_file(dir, "s.yaml",
                                       "name: trav\nduration_s: 2.6\nchain: RRRWRRR\n"
                                       "central:\n  params: {poll_ms: 500}\n");
  const auto [text, code] = chainsim_stdout("run " + scene + " --compare native,pic -q --out " + dir + "/run");
  ASSERT_EQ(code, 0) << text;
  auto last = [&](const std::string& target) {
    const std::string log = read_file(dir + "/run/" + target + "/modules/07-central.log");
    const size_t at = log.rfind("sensors 0x23: ");
    EXPECT_NE(at, std::string::npos) << log;
    int v[4] = {0, 0, 0, 0};
    std::sscanf(log.c_str() + at, "sensors 0x23: %d %d %d %d", &v[0], &v[1], &v[2], &v[3]);
    return std::vector<int>(v, v + 4);
  };
  const auto n = last("native"), p = last("pic");
  // every wheel turned: the board counted each (with no sign). Which wheel
  // rolls most depends on the snake's motion, which a few ms of the board's
  // start (its central control's) change, so the pulses are compared in all
  int board = 0, native = 0;
  for (int w = 1; w <= 3; ++w) {
    EXPECT_GT(p[w], 0) << "wheel " << w;
    board += p[w];
    native += std::abs(n[w]);
  }
  EXPECT_GE(board, native / 2);
  EXPECT_LT(n[2], 0) << "natively the right wheel turned backwards";
  EXPECT_GT(p[0], 0) << "the board's distance only grows";
}
