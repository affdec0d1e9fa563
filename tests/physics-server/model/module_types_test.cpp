// The seven shipped module types in a World (masses and inertias as defined,
// each at rest on the floor, a docked chain of all of them hanging), and a
// scene's own type loaded from its file, end to end.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "model/module_def.h"
#include "scene/scene.h"
#include "output/scene_json.h"
#include "physics/world.h"
#include "world_of.h"

namespace chainsim {
namespace {

const std::vector<std::string> kShipped = {"rotation", "helicoidal", "support", "extension",
                                           "touch",    "traveller",  "passive"};

// each body ODE simulates has the mass of the file and the inertia of its
// solid shape (ODE's dMass against the analytic formula)
TEST(ShippedModules, BodiesHaveTheDefinedMassAndInertia) {
  for (const std::string& type : kShipped) {
    const ModuleDef d = builtin_module_def(type);
    WorldConfig c;
    c.gravity_m_s2 = 0;
    World w = world_of(c, {type});
    ASSERT_EQ(w.body_count(0), static_cast<int>(d.bodies.size())) << type;
    double total = 0;
    for (int b = 0; b < w.body_count(0); ++b) {
      const World::BodyState s = w.body_state(0, b);
      EXPECT_EQ(w.body_name(0, b), d.bodies[b].name);
      EXPECT_NEAR(s.mass_kg, d.bodies[b].mass_kg, 1e-15) << type << "." << d.bodies[b].name;
      const Eigen::Matrix3d expect = body_inertia_kg_m2(d.bodies[b]);
      EXPECT_LT((s.inertia_kg_m2 - expect).cwiseAbs().maxCoeff(), 1e-6 * expect.maxCoeff())
          << type << "." << d.bodies[b].name << "\nODE:\n"
          << s.inertia_kg_m2 << "\ndefined:\n"
          << expect;
      total += s.mass_kg;
    }
    // every shipped type is 10 g in total (the masses the module files give, each with its source)
    EXPECT_NEAR(total, 0.010, 1e-12) << type;
    std::printf("%-10s %d bodies, %zu joints, %d firmware servos, %.1f g, %.0f mm between faces\n",
                type.c_str(), w.body_count(0), d.joints.size(), w.servo_count(0), total * 1e3,
                (d.front.frame.position - d.back.frame.position).norm() * 1e3);
  }
}

// what each type offers firmware
TEST(ShippedModules, ServosAndSensorsPerType) {
  struct Want {
    const char* type;
    int servos, n_adc, n_counters;
  };
  const Want want[] = {{"rotation", 2, 2, 0},  {"helicoidal", 1, 4, 0}, {"support", 1, 4, 0},
                       {"extension", 2, 2, 0}, {"touch", 0, 3, 0},      {"traveller", 0, 3, 3},
                       {"passive", 0, 0, 0}};
  for (const Want& x : want) {
    WorldConfig c;
    World w = world_of(c, {x.type});
    ModuleSample s;
    w.sample(0, &s);
    EXPECT_EQ(s.n_servos, x.servos) << x.type;
    EXPECT_EQ(s.n_adc, x.n_adc) << x.type;
    EXPECT_EQ(s.n_counters, x.n_counters) << x.type;
  }
  // the support module's two follower arms are not addressable but move
  WorldConfig c;
  c.gravity_m_s2 = 0;
  c.head_position = Eigen::Vector3d(0, 0, 0.5);
  World w = world_of(c, {"support"});
  w.pin_body(0, 0);
  w.set_servo_setpoint(0, 0, 1.2);
  for (int k = 0; k < 1000; ++k) w.step();
  const Eigen::Vector3d front = w.body_state(0, 0).position;
  for (int arm = 2; arm <= 4; ++arm) {
    // an opened arm's centre has left the module's surface (14 mm from the axis)
    const Eigen::Vector3d p = w.body_state(0, arm).position - front;
    const double radial = std::hypot(p.y(), p.z());
    EXPECT_GT(radial, 0.020) << w.body_name(0, arm);
  }
}

// every type alone on the floor comes to rest without jitter
TEST(ShippedModules, EachComesToRestOnTheFloor) {
  for (const std::string& type : kShipped) {
    WorldConfig c;
    c.head_position = Eigen::Vector3d(0, 0, 0.014);
    World w = world_of(c, {type});
    for (int k = 0; k < 2000; ++k) w.step();  // 1 s
    double vmax = 0, zmin = 1;
    for (int b = 0; b < w.body_count(0); ++b) {
      const World::BodyState s = w.body_state(0, b);
      ASSERT_TRUE(s.position.allFinite()) << type;
      vmax = std::max(vmax, s.linear_velocity.norm());
      zmin = std::min(zmin, s.position.z());
    }
    EXPECT_LT(vmax, 0.01) << type;  // at rest (the round ones may roll slowly)
    EXPECT_GT(zmin, 0.0) << type;   // above the floor
  }
}

// a docked chain of all seven types hanging from its head: the docking joints
// stretch less than a millimetre while it swings and settles
TEST(ShippedModules, MixedChainHangingFromItsHeadHolds) {
  WorldConfig c;
  c.head_position = Eigen::Vector3d(0, 0, 0.6);
  World w = world_of(c, {"touch", "rotation", "support", "extension", "helicoidal", "traveller", "passive",
              "rotation"});
  w.pin_body(0, 0);
  double worst = 0;
  for (int k = 0; k < 6000; ++k) {  // 1 s powered (stiff), then 2 s limp (swinging)
    if (k == 2000)
      for (int m = 0; m < w.module_count(); ++m)
        for (int s = 0; s < w.servo_count(m); ++s) w.set_servo_enabled(m, s, false);
    w.step();
    worst = std::max(worst, w.max_docking_error_m());
  }
  double lowest = 1;
  for (int m = 0; m < w.module_count(); ++m)
    for (int b = 0; b < w.body_count(m); ++b)
      lowest = std::min(lowest, w.body_state(m, b).position.z());
  std::printf("8 mixed modules hanging: largest docking stretch %.3f mm, lowest body at %.3f m\n",
              worst * 1e3, lowest);
  EXPECT_LT(worst, 1e-3);
  EXPECT_LT(lowest, 0.45);  // it hangs (0.34 m of chain below the head)
}

class TempDir {
 public:
  TempDir() {
    path_ = std::filesystem::temp_directory_path() /
            ("chainsim_modules_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(path_ / "types");
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  std::string write(const std::string& name, const std::string& text) const {
    const std::string p = (path_ / name).string();
    std::ofstream(p) << text;
    return p;
  }

 private:
  std::filesystem::path path_;
};

const char* kBead = R"(# a user's own module type: a heavy sphere that reports touches
type: bead
bodies:
  - {name: ball, shape: sphere, radius_m: 0.0125, mass_kg: 0.02, position_m: [-0.0125, 0, 0]}
sensors:
  - {name: touch, type: touch, body: ball, channel: 3}
docking:
  front: {body: ball}
  back: {body: ball, position_m: [-0.025, 0, 0]}
)";

// a scene names its own type's file (relative to the scene); the World, the
// scene.json and the sample all see it; no C++ involved
TEST(SceneModuleTypes, UserTypeFromASceneFileWorksEndToEnd) {
  TempDir dir;
  dir.write("types/bead.yaml", kBead);
  const std::string scene = dir.write("s.yaml",
                                      "module_types: {bead: types/bead.yaml}\n"
                                      "chain:\n"
                                      "  - {type: rotation}\n"
                                      "  - {type: bead, firmware: /bin/true}\n"
                                      "placement: {position_m: [0, 0, 0.0125]}\n");
  const Scene s = load_scene_file(scene);
  ASSERT_EQ(s.world.module_types.size(), 1u);
  EXPECT_EQ(s.chain_types(), (std::vector<std::string>{"rotation", "bead"}));
  World w = world_of(s.world, s.chain_types());
  ASSERT_EQ(w.module_count(), 2);
  EXPECT_EQ(w.module_type(1), "bead");
  EXPECT_NEAR(w.body_state(1, 0).mass_kg, 0.02, 1e-15);
  for (int k = 0; k < 1000; ++k) w.step();
  ModuleSample smp;
  w.sample(1, &smp);
  EXPECT_EQ(smp.digital_in, 1u << 3);  // the bead rests on the floor
  EXPECT_LT(w.max_docking_error_m(), 1e-3);
  const nlohmann::json j = scene_json(s, compile_chain(s));
  EXPECT_EQ(j["modules"][1]["type"], "bead");
  EXPECT_EQ(j["modules"][1]["bodies"][0]["shape"], "sphere");
}

// a scene may also replace a built-in type for itself
TEST(SceneModuleTypes, SceneTypeReplacesABuiltInOne) {
  TempDir dir;
  std::string heavy = kBead;
  heavy.replace(heavy.find("type: bead"), 10, "type: passive");
  dir.write("heavy.yaml", heavy);
  const Scene s =
      load_scene_file(dir.write("s.yaml", "module_types: {passive: heavy.yaml}\nchain: RP\n"));
  World w = world_of(s.world, s.chain_types());
  EXPECT_EQ(w.module_type(1), "passive");
  EXPECT_NEAR(w.body_state(1, 0).mass_kg, 0.02, 1e-15);
}

TEST(SceneModuleTypes, ErrorsNameTheSceneLine) {
  TempDir dir;
  dir.write("bead.yaml", kBead);
  std::string bad = kBead;
  bad.replace(bad.find("radius_m"), 8, "radius");
  dir.write("bad.yaml", bad);
  auto error_of = [&](const std::string& text) -> std::string {
    try {
      load_scene_file(dir.write("s.yaml", text));
    } catch (const SceneError& e) {
      return e.what();
    }
    return "(no error)";
  };
  // a chain type nobody defines
  std::string e = error_of("chain:\n  - {type: rotation}\n  - {type: beed}\n");
  EXPECT_NE(e.find("s.yaml:3:12: module type 'beed' is not known"), std::string::npos) << e;
  // a file that is not there
  e = error_of("module_types:\n  bead: nothere.yaml\nchain: R\n");
  EXPECT_NE(e.find("s.yaml:2:9: module type 'bead': "), std::string::npos) << e;
  EXPECT_NE(e.find("nothere.yaml: cannot open"), std::string::npos) << e;
  // an error inside the module file: both places
  e = error_of("module_types: {bead: bad.yaml}\nchain: R\n");
  EXPECT_NE(e.find("s.yaml:1:22: module type 'bead': "), std::string::npos) << e;
  EXPECT_NE(e.find("bad.yaml:4:33: unknown key 'radius' in 'bodies[0]'"), std::string::npos) << e;
  // the file defines another type than the key says
  e = error_of("module_types: {pearl: bead.yaml}\nchain: R\n");
  EXPECT_NE(e.find("s.yaml:1:16: 'module_types.pearl': "), std::string::npos) << e;
  EXPECT_NE(e.find("defines type 'bead', not 'pearl'"), std::string::npos) << e;
}

}  // namespace
}  // namespace chainsim
