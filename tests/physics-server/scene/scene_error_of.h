// The message a scene text is refused with, for the scene tests.
#pragma once

#include <string>

#include "scene/scene.h"

namespace chainsim::testing {

// load_scene_text(yaml, "s.yaml")'s SceneError message, or "(no error)"
inline std::string scene_error_of(const std::string& yaml) {
  try {
    load_scene_text(yaml, "s.yaml");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace chainsim::testing
