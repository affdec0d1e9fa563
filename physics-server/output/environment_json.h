// The `environment` block of scene.json (scene_json.h): what a viewer needs
// to draw the environment. Format documented in environment_json.cpp.
#pragma once

#include <nlohmann/json.hpp>

#include "physics/world_config.h"

namespace chainsim {

nlohmann::json environment_json(const WorldConfig& world);

}  // namespace chainsim
