// scene.json of a run directory: what a viewer needs to draw the run (the
// environment, each module's bodies with shapes, sizes and colour) next to
// trace.csv, which has their poses over time.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "output/run_output.h"
#include "scene/scene.h"

namespace chainsim {

// display colour of a shipped module type ("#rrggbb"), the same in every
// view; nullptr for a type of the user's
const char* module_color(const std::string& type);
// the colour of each module of the scene: its type's, or for each type of the
// user's one of ten others, in the order the chain first meets the types
std::vector<std::string> module_colors(const Scene& scene);

// chain: the scene's, compiled (compile_chain(scene)): each module's bodies and servos
nlohmann::json scene_json(const Scene& scene, const ChainModel& chain);

// writes scene_json(scene, chain) as the run directory's scene.json; returns it
nlohmann::json write_scene_json(RunOutput* out, const Scene& scene, const ChainModel& chain);

}  // namespace chainsim
