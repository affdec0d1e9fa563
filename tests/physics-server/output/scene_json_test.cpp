// scene.json's module colours: the shipped types keep theirs; types of the
// user's get distinct ones, the same type the same colour.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>

#include "output/scene_json.h"
#include "temp_dir.h"

using namespace chainsim;

TEST(SceneJson, TypesOfYourOwnGetDistinctColours) {
  const chainsim_test::TempDir d("chainsim-scene-json-test");
  const std::string rotation = std::string(CHAINSIM_SOURCE_DIR) + "/scenes/modules/rotation.yaml";
  std::ifstream in(rotation);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const std::string own : {"mine", "yours"}) {  // the rotation module under another type name
    std::string t = text;
    t.replace(t.find("\ntype: rotation"), 15, "\ntype: " + own);
    std::ofstream(d.path / (own + ".yaml")) << t;
  }
  std::ofstream(d.path / "s.yaml") << "chain:\n  - {type: rotation}\n  - {type: mine}\n  - {type: yours}\n"
                                      "  - {type: mine}\n  - {type: helicoidal}\n"
                                      "module_types: {mine: mine.yaml, yours: yours.yaml}\n";
  const Scene s = load_scene_file((d.path / "s.yaml").string());
  const nlohmann::json j = scene_json(s, compile_chain(s));
  std::vector<std::string> c;
  for (const auto& m : j["modules"]) c.push_back(m["color"].get<std::string>());
  ASSERT_EQ(c.size(), 5u);
  EXPECT_EQ(c[0], module_color("rotation"));
  EXPECT_EQ(c[4], module_color("helicoidal"));
  EXPECT_EQ(c[1], c[3]);  // the same type, the same colour
  EXPECT_NE(c[1], c[2]);  // two types of one's own apart
  const std::set<std::string> shipped = {"#e4572e", "#29335c", "#f3a712", "#669bbc", "#a8c686", "#8e5572", "#9a9a9a"};
  for (const std::string& own : {c[1], c[2]}) EXPECT_EQ(shipped.count(own), 0u) << own;
  EXPECT_EQ(module_color("mine"), nullptr);
}
