// A Scene as a scene file: write_scene's text is what `chainsim run` reads
// back to the same Scene (scene_differences is empty), from any directory:
// every file the scene names (module_types, environment.mesh.file, a
// program given as a path: programs.*.firmware, chain[].firmware,
// central.program) is written absolute, resolved as loading the scene
// resolved it. Numbers are written in their shortest exact form. The design
// search writes each individual's scene so (optimize/individual_scene.h).
#pragma once

#include <string>
#include <vector>

#include "scene/scene.h"

namespace chainsim {

// the scene as YAML (keys in docs/scene-reference.md)
std::string write_scene(const Scene& scene);

// the fields in which a and b differ ("world.environment.pipe.segments[1].angle_deg",
// "modules[2].params"), empty when they are the same scene. Not compared:
// `source` and the *_at fields (where a file says something), and the mesh's
// file_as_given; file paths compare as the files they name (absolute,
// normalised); module types by their files; doubles bit for bit (NaN equal
// to NaN).
std::vector<std::string> scene_differences(const Scene& a, const Scene& b);

}  // namespace chainsim
