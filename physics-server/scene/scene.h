// A scene: what to simulate (environment, chain, programs) and for how long.
// Loaded from YAML; every error names file:line:column and the key.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "physics/world.h"

namespace chainsim {

class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// one module of the chain and the program that runs it
struct SceneModule {
  std::string type;      // module type name, e.g. "rotation"
  std::string firmware;  // program name, e.g. "fw-rotation", or a path
  std::map<std::string, int32_t> params;
};

struct Scene {
  std::string source;          // file name, or "<built-in default>"
  std::string name;
  double duration_s = 10.0;
  int64_t tick_us = 1000;      // HAL timer tick
  // physics step, seed (the run's one seed: ODE, sensor noise, WELCOME),
  // placement, environment, materials, the scene's own module types
  WorldConfig world;
  // the chain, head first: each module's type and program. The one list of
  // modules: the World is built from chain_types().
  std::vector<SceneModule> modules;
  SceneModule central;         // the central control program
  double trace_hz = 100.0;     // trace rows per simulated second

  // the module types of the chain, head first (what World's constructor takes)
  std::vector<std::string> chain_types() const;
};

// letters of chain strings: T touch, R rotation, H helicoidal, S support,
// E extension, W traveller, P passive
std::string module_type_for_letter(char letter);

// default program for a module type: "fw-<type>"
std::string default_firmware(const std::string& type);

// parse a scene; name is used in error messages
Scene load_scene_text(const std::string& text, const std::string& name);
Scene load_scene_file(const std::string& path);
// the scene `chainsim run` uses with no argument
Scene default_scene();
const std::string& default_scene_text();

}  // namespace chainsim
