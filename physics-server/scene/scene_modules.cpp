// Scene keys of module types. See scene_modules.h.
#include "scene/scene_modules.h"

#include <algorithm>
#include <filesystem>
#include <sstream>

#include "model/module_file.h"
#include "model/module_def.h"
#include "scene/scene_yaml.h"

namespace chainsim {
namespace {



}  // namespace

void load_scene_module_types(const std::string& file, const std::string& base_dir,
                             const YAML::Node& node, Scene* scene) {
  if (!node) return;
  if (!node.IsMap())
    throw SceneError(SceneYaml{file}.where(node) +
                     ": 'module_types' must be a mapping of type name: module definition file");
  for (const auto& kv : node) {
    const std::string name = kv.first.as<std::string>();
    if (!kv.second.IsScalar())
      throw SceneError(SceneYaml{file}.where(kv.second) + ": 'module_types." + name +
                       "' must be a file name (a module definition, docs/module-format.md)");
    std::filesystem::path path = kv.second.as<std::string>();
    if (path.is_relative() && !base_dir.empty()) path = std::filesystem::path(base_dir) / path;
    ModuleDef def;
    try {
      def = load_module_file(path.string());
    } catch (const ModuleFileError& e) {
      throw SceneError(SceneYaml{file}.where(kv.second) + ": module type '" + name + "': " + e.what());
    }
    if (def.type != name)
      throw SceneError(SceneYaml{file}.where(kv.first) + ": 'module_types." + name + "': " + path.string() +
                       " defines type '" + def.type + "', not '" + name + "'");
    scene->world.module_types.push_back(std::move(def));
    scene->module_type_files.emplace_back(name, path.string());
  }
}

bool is_module_type(const WorldConfig& w, const std::string& type) {
  const auto builtin = builtin_module_names();
  return std::find(builtin.begin(), builtin.end(), type) != builtin.end() ||
         std::any_of(w.module_types.begin(), w.module_types.end(),
                     [&](const ModuleDef& d) { return d.type == type; });
}

void check_scene_chain_types(const std::string& file, const YAML::Node& chain, const Scene& scene) {
  for (size_t i = 0; i < scene.modules.size(); ++i) {
    const std::string& type = scene.modules[i].type;
    if (is_module_type(scene.world, type)) continue;
    const YAML::Node at =
        chain.IsSequence() && i < chain.size() && chain[i]["type"] ? chain[i]["type"] : chain;
    std::string names;
    for (const auto& n : builtin_module_names()) names += " " + n;
    for (const auto& d : scene.world.module_types) names += " " + d.type;
    throw SceneError(SceneYaml{file}.where(at) + ": module type '" + type + "' is not known (known:" + names +
                     "; a scene adds its own with module_types: {name: file.yaml})");
  }
}

}  // namespace chainsim
