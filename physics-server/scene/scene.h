// A scene: what to simulate (environment, chain, programs) and for how long.
// Loaded from YAML; every error names file:line:column and the key.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "physics/chain_model.h"
#include "physics/world_config.h"

namespace chainsim {

// its message is shown_text'ed: a name from a file never reaches the terminal raw
class SceneError : public std::runtime_error {
 public:
  explicit SceneError(const std::string& message);
};

// what runs a module's program: the program built for this computer, linked
// with hal-sim (native), or the board's own binary, PROGRAM.hex, in gpsim
// (pic: chainsim-pic, docs/pic-in-the-loop.md)
enum class Target { Native, Pic };
const char* target_name(Target t);

// one module of the chain and the program that runs it
struct SceneModule {
  std::string type;      // module type name, e.g. "rotation"
  std::string firmware;  // program name, e.g. "fw-rotation", or a path
  std::map<std::string, int32_t> params;
  // where the scene file sets each parameter ("file:line:column" of its key)
  // and names the program (of `firmware`, or of the module or chain): for
  // the errors of check_scene_params (scene_params.h)
  std::map<std::string, std::string> param_at;
  std::string firmware_at;
  Target target = Target::Native;
  std::string target_at;  // where the scene says it ("" for the default)
  // the module may never answer discovery (its program takes no part in
  // it): no failure when it has no I2C address at discovery_s
  bool may_stay_silent = false;
};

// when a run ends before its duration (scene key `stop_when`, docs/scene-reference.md):
// a point of the chain that has stopped making progress, or that has not
// reached a mark by a time. Checked at every trace row, on the positions the
// trace writes; the run then ends as finished, and summary.json says why.
struct StopRule {
  enum class Kind { NoProgress, NotReached };
  Kind kind = Kind::NoProgress;
  bool tail = false;          // of: head (module 0's first body) or tail (the last module's last body)
  bool along_pipe = false;    // the length along the pipe's axis, else along `axis`
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();  // unit
  double by_m = 0;            // NoProgress: the furthest position must grow by this ...
  double within_s = 0;        // ... within every window of this long
  double reach_m = 0;         // NotReached: the position to reach ...
  double by_s = 0;            // ... by this time
  // `along` as written when it is a vector (axis is it normalised): what
  // write_scene writes, since normalising a normalised vector again can
  // change its last bit
  std::optional<Eigen::Vector3d> along_given;
};

// `programs: {all: {...}, <type>: {...}}` as the scene file gives them: what
// a module of a type gets unless it says otherwise (scene.cpp's
// apply_programs, set_chain in scene_edit.h)
struct SceneProgram {
  std::string firmware;  // empty: not given; a path resolved as a module's firmware is
  std::string firmware_at;
  std::optional<Target> target;
  std::string target_at;
  std::optional<bool> may_stay_silent;
  std::map<std::string, int32_t> params;
  std::map<std::string, std::string> param_at;
};

// `placement` as the scene file gives it; WorldConfig's head_position,
// heading_rad, roll_rad and head_orientation are derived from it and the
// chain (place_scene_chain in scene_edit.h)
struct ScenePlacement {
  bool at_pipe_entry = false;        // `at: pipe_entry`
  double inset_m = 0.005;            // with at_pipe_entry
  Eigen::Vector3d position_m{0, 0, 0.02};  // without it
  double heading_deg = 0;            // without it
  double roll_deg = 0;
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
  // modules: the chain model (compile_chain) is compiled from chain_types().
  std::vector<SceneModule> modules;
  SceneModule central;         // the central control program
  // by this simulated time every module has answered discovery (taken an
  // I2C address) unless it may stay silent; a run that lasts this long and
  // has a module without one stops with kExitSilentModule
  double discovery_s = 1.0;
  double trace_hz = 100.0;     // trace rows per simulated second
  // the modules whose target is pic (scene key `pic`)
  struct Pic {
    int64_t cpu_budget_us = 0;  // most busy time a step of a program may take; 0: no budget
    int64_t stall_ms = 2000;    // a program busy this long without a HAL wait is a fault
  } pic;
  std::vector<StopRule> stop_when;  // any one ends the run early

  // what the file gives that the fields above hold only merged or derived,
  // kept so that write_scene (scene_write.h) writes the scene back and the
  // edits of scene_edit.h keep it whole:
  // `module_types`: each type's name and its file, resolved against the
  // scene's directory as loading it was (world.module_types holds the
  // definitions, in the same order)
  std::vector<std::pair<std::string, std::string>> module_type_files;
  std::map<std::string, SceneProgram> programs;  // `programs`, by type or "all"
  std::optional<Target> target;                  // the scene-wide `target`
  std::string target_at;
  ScenePlacement placement;

  // the module types of the chain, head first (what compile_chain takes)
  std::vector<std::string> chain_types() const;
};

// the scene's chain compiled once (physics/chain_model.h): what the World,
// the trace's sensor columns and scene.json read the modules from. Throws
// std::invalid_argument as compile_chain does.
ChainModel compile_chain(const Scene& scene);

// every endpoint (modules and central control) runs on target t, whatever
// the scene says (`--target` of run, test and optimize); the scene-wide
// target becomes t and the programs' targets are dropped, so that a module
// added later (set_chain) and the written scene run on t too
void set_target(Scene* scene, Target t);
// whether any endpoint runs on the PIC
bool uses_pic(const Scene& scene);

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
