// scene.json of a run directory: what a viewer needs to draw the run (the
// environment, each module's bodies with shapes, sizes and colour) next to
// trace.csv, which has their poses over time.
#pragma once

#include <nlohmann/json.hpp>

#include "output/run_output.h"
#include "scene/scene.h"

namespace chainsim {

// display colour of a module type ("#rrggbb"), the same in every view
const char* module_color(const std::string& type);

nlohmann::json scene_json(const Scene& scene);

// writes scene_json(scene) as the run directory's scene.json; returns it
nlohmann::json write_scene_json(RunOutput* out, const Scene& scene);

}  // namespace chainsim
