// Mistakes that are right on a PC and wrong on the 8-bit board, planted in a
// firmware developer's own project of two programs (tests/scenario/pic-planted,
// built native and for the PIC by tools/pic-build.sh --project): each is
// caught in PIC mode by a wrong value in the comparison with the native run
// or by a named fault; the build's own catches (SDCC's warnings as errors, a
// RAM bank that a local array overflows, a sensor channel the board lacks)
// are told in words (docs/pic-in-the-loop.md, "What it catches").
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>

#include <cstdlib>
#include <fstream>
#include <mutex>

#include "pic_tree.h"
#include "scenario_util.h"

using namespace scenario;

namespace {

std::string repo() {
  const std::string here = __FILE__;
  return here.substr(0, here.rfind("/tests/scenario/"));
}

std::string build_dir() {
  const std::string exe = CHAINSIM_EXE;
  return exe.substr(0, exe.rfind("/bin/"));
}

bool toolchain_built() {
  const char* home = std::getenv("HOME");
  const char* cache = std::getenv("CHAINSIM_PIC_CACHE");
  const std::string dir = cache ? cache : std::string(home ? home : "") + "/.cache/chainsim-pic";
  struct stat st {};
  return stat((dir + "/stamps/runtime").c_str(), &st) == 0 && stat(CHAINSIM_PIC_EXE, &st) == 0;
}

// tools/pic-build.sh --project DIR OUT: output and exit code
std::pair<std::string, int> pic_build(const std::string& project, const std::string& out, bool strict = false) {
  const std::string cmd = "chainsim_DIR=" + build_dir() + " " + repo() + "/tools/pic-build.sh " +
                          (strict ? "--strict " : "") + "--project " +
                          repo() + "/tests/scenario/" + project + " " + out + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  std::string text;
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) text.append(buf, n);
  const int st = pclose(p);
  return {text, WIFEXITED(st) ? WEXITSTATUS(st) : -1};
}

// the planted project, built in one folder of this build tree for every
// test here (under a lock: ctest may run them at once; an incremental build
// after the first)
const std::string& planted() {
  static std::string dir;
  static std::once_flag once;
  std::call_once(once, [] {
    dir = build_dir() + "/tests/scenario/pic-planted-build";
    std::filesystem::create_directories(dir);
    const int lock = open((dir + ".lock").c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644);
    flock(lock, LOCK_EX);
    const auto [text, code] = pic_build("pic-planted", dir);
    close(lock);
    if (code != 0) {
      ADD_FAILURE() << text;
      dir.clear();
    }
  });
  return dir;
}

#define REQUIRE_TOOLCHAIN()                                                                               \
  if (!toolchain_built())                                                                                 \
  GTEST_SKIP() << "the PIC toolchain is not built (tools/pic-toolchain.sh, which tools/test-all.sh runs)"

// a run of the planted project also runs the tree's own programs for the PIC
// (the central control's fw-central.hex): the toolchain can be in the shared
// cache while this build tree's programs were never built
#define REQUIRE_TREE_PIC_PROGRAMS()                                                                       \
  REQUIRE_TOOLCHAIN();                                                                                    \
  if (!tree_pic_built())                                                                                  \
  GTEST_SKIP() << "this build tree's PIC programs are not built (" << tree_pic_dir()                      \
               << "): run tools/pic-build.sh, as tools/test-all.sh does"

nlohmann::json read_json(const std::string& path) {
  std::ifstream f(path);
  return nlohmann::json::parse(f);
}

}  // namespace

TEST(PicPlanted, TwoProgramsOfOneProjectBuildForTheBoardAndSdccWarnsOfTwo) {
  REQUIRE_TOOLCHAIN();
  const std::string& b = planted();
  ASSERT_FALSE(b.empty());
  struct stat st {};
  for (const char* f : {"fw-planted", "fw-planted.hex", "fw-planted.pic.json", "fw-planted-clock",
                        "fw-planted-clock.hex"})
    EXPECT_EQ(stat((b + "/" + f).c_str(), &st), 0) << f;
}

TEST(PicPlanted, StrictMakesSdccsEightBitTruthsErrors) {
  REQUIRE_TOOLCHAIN();
  const std::string dir = temp_dir("pic-planted-strict");
  const auto [text, code] = pic_build("pic-planted", dir, true);
  EXPECT_NE(code, 0) << text;
  EXPECT_NE(text.find("planted.c:31: error (8-bit truth, warning 165): integer overflow in expression: arithmetic "
                      "on int constants that overflows 16 bits"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("planted.c:36: error (8-bit truth, warning 116)"), std::string::npos) << text;
}

TEST(PicPlanted, ALocalArrayOverARamBankFailsTheBuildInWords) {
  REQUIRE_TOOLCHAIN();
  const std::string dir = temp_dir("pic-planted-ram");
  const auto [text, code] = pic_build("pic-planted-ram", dir);
  EXPECT_NE(code, 0) << text;
  EXPECT_NE(text.find("pic-link: the RAM section udata_ram_0 of"), std::string::npos) << text;
  EXPECT_NE(text.find("ram.c holds 300 bytes (local variable main_samples"), std::string::npos) << text;
  EXPECT_NE(text.find("a variable of more than 256 bytes cannot be placed at all"), std::string::npos) << text;
}

TEST(PicPlanted, EachMistakeIsAWrongValueOrANamedFaultOnTheBoard) {
  REQUIRE_TREE_PIC_PROGRAMS();
  const std::string& b = planted();
  ASSERT_FALSE(b.empty());
  const std::string dir = temp_dir("pic-planted-run");
  const std::string scene = write_file(dir, "planted.yaml",
                                       "name: planted\nduration_s: 1\nchain:\n"
                                       "  - {type: passive, params: {case: 1}}\n"
                                       "  - {type: passive, params: {case: 2}}\n"
                                       "  - {type: passive, params: {case: 3}}\n"
                                       "  - {type: passive, params: {case: 4}}\n"
                                       "  - {type: passive, params: {case: 5}}\n"
                                       "programs: {all: {firmware: fw-planted, may_stay_silent: true}}\n");
  const auto [text, code] = chainsim_stdout("run " + scene + " --compare native,pic --on-module-fault limp -q "
                                            "--firmware-dir " + b + " --out " + dir + "/run");
  ASSERT_EQ(code, 0) << text;
  const nlohmann::json c = read_json(dir + "/run/compare.json");
  const struct {
    int module;
    const char* native;
    const char* pic;
  } want[] = {{0, "case 1: 300 * 200 = 60000", "case 1: 300 * 200 = -5536"},
              {1, "case 2: 1 << 20 = 1048576", "case 2: 1 << 20 = 0"},
              {2, "case 3: amp * 20 = 60000", "case 3: amp * 20 = -5536"},
              {3, "case 4: amp * amp = 9000000", "case 4: amp * amp = 21568"}};
  for (const auto& w : want) {
    const auto& d = c["endpoints"][w.module]["divergences"];
    ASSERT_FALSE(d.empty()) << w.module;
    EXPECT_EQ(d[0]["channel"], "log");
    EXPECT_EQ(d[0]["a"], w.native);
    EXPECT_EQ(d[0]["b"], w.pic);
  }
  // the recursion: the hardware return stack overflows, the chip resets
  const auto& r = c["endpoints"][4]["divergences"];
  ASSERT_EQ(r.size(), 2u) << r.dump();
  EXPECT_EQ(r[0]["a"], "case 5: depth(40) = 40");
  EXPECT_EQ(r[0]["b"], "(none)");
  EXPECT_EQ(r[1]["channel"], "fault");
  const std::string fault = r[1]["b"];
  EXPECT_NE(fault.find("the chip reset: stack overflow: more than 31 calls and interrupts nested"), std::string::npos)
      << fault;
  EXPECT_NE(fault.find("in depth(), "), std::string::npos) << fault;
  EXPECT_NE(fault.find("pic-planted/planted.c:21 (return depth(n - 1) + 1;)"), std::string::npos) << fault;
  EXPECT_NE(fault.find("called from depth() x29, main(), __startup()"), std::string::npos) << fault;
  // the native runs of all five agree with what C on a PC says, and the
  // board's flash and RAM are in summary.json
  const nlohmann::json s = read_json(dir + "/run/pic/summary.json");
  EXPECT_EQ(s["modules"][0]["pic"]["memory"]["flash_total"], 32768);
  EXPECT_GT(s["modules"][0]["pic"]["memory"]["ram_bytes"].get<int>(), 256);
}

TEST(PicPlanted, AMillisecondClockInAnUnsignedIntWrapsAfter65Seconds) {
  REQUIRE_TREE_PIC_PROGRAMS();
  const std::string& b = planted();
  ASSERT_FALSE(b.empty());
  const std::string dir = temp_dir("pic-planted-clock");
  const std::string scene = write_file(dir, "clock.yaml",
                                       "name: clock\nduration_s: 71\nchain: [{type: passive, may_stay_silent: true}]\n"
                                       "programs: {all: {firmware: fw-planted-clock}}\n");
  const auto [text, code] = chainsim_stdout("run " + scene + " --compare native,pic -q --firmware-dir " + b +
                                            " --out " + dir + "/run");
  ASSERT_EQ(code, 0) << text;
  const nlohmann::json c = read_json(dir + "/run/compare.json");
  const auto& d = c["endpoints"][0]["divergences"];
  ASSERT_FALSE(d.empty());
  EXPECT_EQ(d[0]["channel"], "log");
  EXPECT_NEAR(d[0]["t_a_s"].get<double>(), 70.0, 0.01);
  EXPECT_EQ(d[0]["a"], "clock: t_s = 70");
  EXPECT_EQ(d[0]["b"], "clock: t_s = 4") << "65.536 s wrapped: 70 - 65.536";
  EXPECT_EQ(c["endpoints"][0]["channels"]["log"]["agreed"], 14);
}
