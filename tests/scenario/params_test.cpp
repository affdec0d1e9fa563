// Program parameters the way a firmware developer meets them: a misspelled
// or out-of-range parameter in a scene stops `chainsim run` before any module
// starts, naming file:line:column, the key, the endpoint and the program;
// `chainsim params` lists what a program declares; docs/firmware.md's tables
// are what the shipped programs declare.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "scenario_util.h"

using namespace scenario;


TEST(Params, MisspelledParameterStopsTheRunBeforeAnyModuleStarts) {
  const std::string dir = temp_dir("params-typo");
  const std::string scene = write_file(dir, "s.yaml",
                                       "name: typo\nduration_s: 1\nchain: RRR\ncentral:\n"
                                       "  params: {gait: 1, amplitud_cdeg: 3000}\n");
  const Outcome o = run({scene}, dir);
  EXPECT_EQ(o.exit_code, 1) << o.stderr_text;
  EXPECT_NE(o.stderr_text.find(scene + ":5:21: parameter 'amplitud_cdeg' of the central control: program "
                                        "fw-central declares no such parameter (did you mean 'amplitude_cdeg'?"),
            std::string::npos)
      << o.stderr_text;
  // nothing ran: no run directory, no module process
  EXPECT_FALSE(std::filesystem::exists(dir + "/run")) << "the run started";
}

TEST(Params, OutOfRangeParameterNamesTheDeclaredRange) {
  const std::string dir = temp_dir("params-range");
  const std::string scene = write_file(dir, "s.yaml",
                                       "name: range\nduration_s: 1\nchain:\n  - {type: touch}\n"
                                       "  - {type: rotation}\nprograms:\n  touch: {params: {release_ms: 70000}}\n");
  const Outcome o = run({scene}, dir);
  EXPECT_EQ(o.exit_code, 1) << o.stderr_text;
  EXPECT_NE(o.stderr_text.find(scene + ":7:20: parameter 'release_ms' of module 0 (touch) is 70000, outside the "
                                        "range 0..60000 that program fw-touch declares (a switch is released once its input "
                                        "was low this long, ms)"),
            std::string::npos)
      << o.stderr_text;
  EXPECT_FALSE(std::filesystem::exists(dir + "/run"));
}

// fw-central declares gaits 0 to 9: an unknown one used to start nothing, silently
TEST(Params, UnknownGaitOfTheShippedCentralControlIsAnError) {
  const std::string dir = temp_dir("params-gait");
  const std::string scene =
      write_file(dir, "s.yaml", "name: gait\nduration_s: 1\nchain: R\ncentral: {params: {gait: 12}}\n");
  const Outcome o = run({scene, "--check"}, dir);
  EXPECT_EQ(o.exit_code, 1) << o.stderr_text;
  EXPECT_NE(o.stderr_text.find(scene + ":4:20: parameter 'gait' of the central control is 12, outside the range 0..9 "
                                        "that program fw-central declares (0 none, 1 forward, 2 backward, 3 turn left, "
                                        "4 turn right, 5 roll, 6 rotate in place, 7 lateral shift, 8 inchworm, 9 "
                                        "helicoidal drive)"),
            std::string::npos)
      << o.stderr_text;
  // another central program is checked against its own declarations (fw-test-misbehave: mode 0..6)
  const std::string mine = write_file(dir, "s2.yaml",
                                      "name: gait\nduration_s: 1\nchain: R\ncentral: {program: " FW_MISBEHAVE
                                      ", params: {mode: 6}}\n");
  EXPECT_EQ(run({mine, "--check"}, dir).exit_code, 0);
}

// a value in range reaches the program (through WELCOME): control_ms 1000 makes module 0 step seldom
TEST(Params, ParameterInRangeReachesTheProgram) {
  const std::string dir = temp_dir("params-ok");
  const std::string scene = write_file(dir, "s.yaml",
                                       "name: ok\nduration_s: 0.2\nchain:\n  - {type: rotation, params: {control_ms: 1000}}\n"
                                       "  - {type: rotation}\ncentral: {params: {gait: 1}}\n");
  const Outcome o = run({scene, "-q"}, dir);
  EXPECT_EQ(o.exit_code, 0) << o.stderr_text;
  // module 0 steps every 1000 ms, module 1 every 10 ms: far fewer exchanges for module 0
  EXPECT_LT(o.summary["modules"][0]["exchanges"].get<int>() * 3, o.summary["modules"][1]["exchanges"].get<int>());
}

// a program that does not list its parameters (not linked with hal-sim) is
// refused only when the scene gives it some
TEST(Params, ParametersForAProgramThatListsNoneAreRefused) {
  const std::string dir = temp_dir("params-nolist");
  const std::string scene = write_file(dir, "s.yaml",
                                       "name: nolist\nduration_s: 1\nchain:\n  - {type: rotation, firmware: /bin/true, "
                                       "params: {mode: 1}}\n");
  const Outcome o = run({scene}, dir);
  EXPECT_EQ(o.exit_code, 1) << o.stderr_text;
  EXPECT_NE(o.stderr_text.find(scene + ":4:52: module 0 (rotation) is given parameters, but its program /bin/true "
                                        "did not list the ones it declares when run with --chainsim-params: it "
                                        "printed nothing"),
            std::string::npos)
      << o.stderr_text;
}

TEST(Params, ChainsimParamsListsWhatTheProgramDeclares) {
  const auto [out, rc] = chainsim_stdout("params fw-traveller");
  EXPECT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("fw-traveller ("), std::string::npos) << out;
  EXPECT_NE(out.find("): 2 parameters\n"), std::string::npos) << out;
  EXPECT_NE(out.find("parameter   type    range      default  meaning\n"
                     "control_ms  uint16  1..1000         50  control period, ms\n"
                     "wheel_r_um  int32   1..30000      6000  wheel radius, um (distance = deg x wheel_r_um / 57296)\n"),
            std::string::npos)
      << out;
  const auto [missing, rc2] = chainsim_stdout("params fw-not-built-anywhere");
  EXPECT_EQ(rc2, 1);
  EXPECT_NE(missing.find("fw-not-built-anywhere is not an executable file"), std::string::npos) << missing;
}

// docs/firmware.md's parameter tables are `chainsim params --markdown` of each shipped program
TEST(Params, DocsTablesAreWhatTheProgramsDeclare) {
  const std::string here = __FILE__;
  const std::string doc = read_file(here.substr(0, here.rfind("/tests/scenario/")) + "/docs/firmware.md");
  for (const char* p : {"fw-central", "fw-rotation", "fw-helicoidal", "fw-support", "fw-extension", "fw-touch",
                        "fw-traveller", "fw-passive"}) {
    const auto [table, rc] = chainsim_stdout(std::string("params --markdown ") + p);
    ASSERT_EQ(rc, 0) << table;
    const std::string block = std::string("<!-- chainsim params --markdown ") + p + " -->\n" + table;
    EXPECT_NE(doc.find(block), std::string::npos)
        << "docs/firmware.md does not hold this table (paste it there):\n" << block;
  }
}
