// A scene's parameters against the programs' declarations (scene_params.h):
// what the scene sets, where, merged from programs: and the module's own,
// checked name by name and value by value, with no program run (the
// declarations come from a table here; cosim's program_params_test and the
// scenario ParamsTest read them from real programs).
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "scene/scene_params.h"

namespace chainsim {
namespace {

ProgramParams decls(const std::string& program) {
  ProgramParams p;
  p.program = program;
  if (program == "fw-central") {
    p.params = {{"gait", "uint8", 0, 255, 1, "gait code"}, {"amplitude_cdeg", "int16", 0, 18000, 4000, "amplitude A, cdeg"}};
  } else {
    p.params = {{"control_ms", "uint16", 1, 1000, 10, "control period, ms"}};
  }
  return p;
}

// check_scene_params' message for the scene text, or "(no error)"; *asked: the programs it wanted
std::string check(const std::string& yaml, std::string* asked = nullptr) {
  std::map<std::string, ProgramParams> known;
  try {
    check_scene_params(load_scene_text(yaml, "s.yaml"),
                       [&](const SceneModule& e, const std::string& who) -> const ProgramParams& {
                         if (asked) *asked += who + "=" + e.firmware + ";";
                         return known.emplace(e.firmware, decls(e.firmware)).first->second;
                       });
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(SceneParams, DeclaredParametersInRangePass) {
  std::string asked;
  EXPECT_EQ(check("chain: RR\ncentral: {params: {gait: 0, amplitude_cdeg: 18000}}\n"
                  "programs: {rotation: {params: {control_ms: 1}}}\n",
                  &asked),
            "(no error)");
  // every endpoint given parameters, and only those, is looked up
  EXPECT_EQ(asked, "module 0 (rotation)=fw-rotation;module 1 (rotation)=fw-rotation;the central control=fw-central;");
  asked.clear();
  EXPECT_EQ(check("chain: RR\n", &asked), "(no error)");
  EXPECT_EQ(asked, "");
}

TEST(SceneParams, UndeclaredNameIsAnErrorAtItsKeyWithTheNearestName) {
  EXPECT_EQ(check("chain: RR\ncentral:\n  params: {gaitt: 1}\n"),
            "s.yaml:3:12: parameter 'gaitt' of the central control: program fw-central declares no such "
            "parameter (did you mean 'gait'? its parameters: gait, amplitude_cdeg; `chainsim params fw-central` "
            "lists them)");
  // nothing near: no guess
  EXPECT_NE(check("chain: RR\ncentral:\n  params: {speed: 1}\n").find("declares no such parameter (its parameters: "),
            std::string::npos);
  // a misspelling given to every rotation module is named at its one key, for the first module
  EXPECT_EQ(check("chain: RR\nprograms:\n  rotation: {params: {contrl_ms: 5}}\n"),
            "s.yaml:3:23: parameter 'contrl_ms' of module 0 (rotation): program fw-rotation declares no such "
            "parameter (did you mean 'control_ms'? its parameters: control_ms; `chainsim params fw-rotation` "
            "lists them)");
}

TEST(SceneParams, ValueOutsideTheDeclaredRangeIsAnErrorNamingTheRange) {
  EXPECT_EQ(check("chain:\n  - {type: rotation}\n  - {type: rotation, params: {control_ms: 0}}\n"),
            "s.yaml:3:31: parameter 'control_ms' of module 1 (rotation) is 0, outside the range 1..1000 that "
            "program fw-rotation declares (control period, ms)");
  EXPECT_EQ(check("chain: R\ncentral: {params: {amplitude_cdeg: 18001}}\n"),
            "s.yaml:2:20: parameter 'amplitude_cdeg' of the central control is 18001, outside the range 0..18000 "
            "that program fw-central declares (amplitude A, cdeg)");
}

TEST(SceneParams, TheModulesOwnValueIsCheckedWhereItIsSet) {
  // programs.all sets a good value; the module's own bad one wins and is named
  EXPECT_EQ(check("chain:\n  - {type: rotation, params: {control_ms: 2000}}\nprograms: {all: {params: {control_ms: 5}}}\n"),
            "s.yaml:2:31: parameter 'control_ms' of module 0 (rotation) is 2000, outside the range 1..1000 that "
            "program fw-rotation declares (control period, ms)");
}

TEST(SceneParams, MoreMergedParametersThanAWelcomeCarriesIsAnError) {
  std::string all, own;
  for (int i = 0; i < 9; ++i) all += (i ? ", a" : "a") + std::to_string(i) + ": 1";
  for (int i = 0; i < 8; ++i) own += (i ? ", b" : "b") + std::to_string(i) + ": 1";
  const std::string e =
      check("chain:\n  - {type: rotation, params: {" + own + "}}\nprograms: {all: {params: {" + all + "}}}\n");
  EXPECT_NE(e.find(": module 0 (rotation) is given 17 parameters (programs.all, programs.rotation and its own "
                   "together), more than the 16 a program can be given"),
            std::string::npos)
      << e;
}

TEST(SceneParams, NearestNameTakesSmallEditsAndPrefixes) {
  const ProgramParams p = decls("fw-central");
  EXPECT_EQ(nearest_param(p, "gaitt"), "gait");
  EXPECT_EQ(nearest_param(p, "amplitud_cdeg"), "amplitude_cdeg");
  EXPECT_EQ(nearest_param(p, "amplitude"), "amplitude_cdeg");
  EXPECT_EQ(nearest_param(p, "omega_mrad_s"), "");
}

}  // namespace
}  // namespace chainsim
