// Scene keys of the environment (`environment:`, `contacts:`) and the
// environment-dependent placement (`placement: {at: pipe_entry}`). Keys and
// defaults: docs/scene-reference.md. Errors are SceneErrors naming
// file:line:column and the key; a mesh file that cannot be read names the
// file and assimp's reason.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "scene/scene.h"

namespace chainsim {

// fills world->environment and world->ground from `environment` and
// `contacts` (either may be absent); relative mesh paths are resolved against
// base_dir (the scene file's directory; empty = the working directory)
void load_scene_environment(const std::string& file, const std::string& base_dir,
                            const YAML::Node& environment, const YAML::Node& contacts,
                            WorldConfig* world);

// `placement.at` and `placement.inset_m` for `chain` (module type names,
// head first), into *world and as given into *given
void load_scene_placement_at(const std::string& file, const YAML::Node& placement,
                             const std::vector<std::string>& chain, WorldConfig* world, ScenePlacement* given);

}  // namespace chainsim
