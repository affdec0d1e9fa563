// A scene checked without running it (chainsim run --check): what a run does
// before its first process starts (the World built from the scene, its mesh
// loaded, every program found), and nothing after: no process, no socket, no
// file written.
#pragma once

#include <string>

#include "scene/scene.h"

namespace chainsim {

struct SceneCheck {
  int exit_code = 0;     // kExitOk, kExitBadInput (a program missing, a body inside the environment) or kExitInternal (run_options.h)
  std::string message;   // what is wrong; on kExitOk a one-line account of what was checked
};

// the scene as loaded (load_scene_file has checked its files and keys);
// firmware_dir as RunOptions::firmware_dir
SceneCheck check_scene(const Scene& scene, const std::string& firmware_dir);

}  // namespace chainsim
