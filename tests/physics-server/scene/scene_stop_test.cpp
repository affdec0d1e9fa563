// The scene key stop_when: its two rules, read back as written, and errors
// that name file:line:column and the key.
#include <gtest/gtest.h>

#include <yaml-cpp/yaml.h>

#include "scene/scene.h"
#include "scene/scene_stop.h"
#include "scene_error_of.h"

using namespace chainsim;
using chainsim::testing::scene_error_of;

namespace {

const char* kPipe = R"(name: p
duration_s: 1
environment:
  type: pipe
  pipe:
    inner_diameter_m: 0.04
    segments: [{type: straight, length_m: 0.4}]
chain: RR
placement: {at: pipe_entry, roll_deg: 30}
)";

}  // namespace

TEST(SceneStop, BothRulesAreReadAsWrittenAndWrittenBackAsRead) {
  const Scene s = load_scene_text(std::string(kPipe) + R"(stop_when:
  - no_progress: {of: tail, along: pipe, by_m: 0.005, within_s: 4}
  - not_reached: {along: [0, 1, 0], reach_m: 0.3, by_s: 0.8}
)",
                                  "s.yaml");
  ASSERT_EQ(s.stop_when.size(), 2u);
  const StopRule& a = s.stop_when[0];
  EXPECT_EQ(a.kind, StopRule::Kind::NoProgress);
  EXPECT_TRUE(a.tail);
  EXPECT_TRUE(a.along_pipe);
  EXPECT_EQ(a.by_m, 0.005);
  EXPECT_EQ(a.within_s, 4);
  const StopRule& b = s.stop_when[1];
  EXPECT_EQ(b.kind, StopRule::Kind::NotReached);
  EXPECT_FALSE(b.tail);
  EXPECT_EQ(b.axis, Eigen::Vector3d::UnitY());
  EXPECT_EQ(b.reach_m, 0.3);
  EXPECT_EQ(b.by_s, 0.8);
  EXPECT_EQ(stop_rule_text(a), "no_progress of tail along pipe by 0.005 m within 4 s");
  EXPECT_EQ(stop_rule_text(b), "not_reached: head along y to 0.3 m by 0.8 s");
  EXPECT_NEAR(s.world.roll_rad, 30 * M_PI / 180, 1e-15);
  // stop_rule_yaml is what the search writes into an individual's scene
  YAML::Node list(YAML::NodeType::Sequence);
  for (const StopRule& r : s.stop_when) list.push_back(stop_rule_yaml(r));
  YAML::Node root = YAML::Load(kPipe);
  root["stop_when"] = list;
  YAML::Emitter out;
  out << root;
  const Scene again = load_scene_text(out.c_str(), "again.yaml");
  ASSERT_EQ(again.stop_when.size(), 2u);
  EXPECT_EQ(stop_rule_text(again.stop_when[0]), stop_rule_text(a));
  EXPECT_EQ(stop_rule_text(again.stop_when[1]), stop_rule_text(b));
}

TEST(SceneStop, ErrorsNameTheRuleAndTheKey) {
  const std::string open = "chain: RR\n";
  EXPECT_EQ(scene_error_of(open + "stop_when: {no_progress: {by_m: 1, within_s: 1}}\n"),
            "s.yaml:2:12: 'stop_when' must be a list of {no_progress: {...}} or {not_reached: {...}}");
  EXPECT_EQ(scene_error_of(open + "stop_when: [{stall: {by_m: 1}}]\n"),
            "s.yaml:2:14: unknown key 'stall' in 'stop_when[0]' (known: no_progress, not_reached)");
  EXPECT_EQ(scene_error_of(open + "stop_when: [{no_progress: {by_m: 0.01}}]\n"),
            "s.yaml:2:27: 'stop_when[0].no_progress' needs 'within_s'");
  EXPECT_EQ(scene_error_of(open + "stop_when: [{no_progress: {by_m: 0, within_s: 2}}]\n").rfind(
                "s.yaml:2:34: 'stop_when[0].no_progress.by_m'", 0),
            0u);
  EXPECT_EQ(scene_error_of(open + "stop_when: [{not_reached: {reach_m: 1, by_s: 2, along: pipe}}]\n"),
            "s.yaml:2:56: 'stop_when[0].not_reached.along' is pipe but the environment is not a pipe");
  EXPECT_EQ(scene_error_of(open + "stop_when: [{not_reached: {reach_m: 1, by_s: 2}, no_progress: {by_m: 1, within_s: 1}}]\n"),
            "s.yaml:2:13: 'stop_when[0]' must be a mapping of one key: no_progress or not_reached");
}
