// Scene keys of module types: `module_types: {<name>: <file>}` adds a scene's
// own types (module definition files, docs/module-format.md; a name may also
// replace a built-in type for this scene), and the check that every type the
// chain names exists. Errors are SceneErrors naming file:line:column.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>

#include "scene/scene.h"

namespace chainsim {

// appends the types of `module_types` (may be absent) to
// scene->world.module_types and their files to scene->module_type_files;
// relative paths are resolved against base_dir (the scene file's directory;
// empty = the working directory)
void load_scene_module_types(const std::string& file, const std::string& base_dir,
                             const YAML::Node& module_types, Scene* scene);

// whether type is a built-in module type or one of world's module_types
bool is_module_type(const WorldConfig& world, const std::string& type);

// every type of `chain` (the scene's chain node) is a scene type or a built-in
void check_scene_chain_types(const std::string& file, const YAML::Node& chain, const Scene& scene);

}  // namespace chainsim
