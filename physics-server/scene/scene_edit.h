// Edits of a loaded Scene that keep it whole: what a design search changes
// in its base scene for each individual (the chain, program parameters, the
// solver, the start pose, stop rules). Each edit leaves the Scene as loading
// the file write_scene (scene_write.h) makes of it would: the modules of a
// new chain get their programs from the scene's `programs`, a new chain or
// start pose is placed again. Errors are SceneErrors naming the culprit.
#pragma once

#include <cstdint>
#include <string>

#include "scene/scene.h"

namespace chainsim {

// a chain has at most this many modules: one process and one socket each
inline constexpr size_t kMaxSceneModules = 64;

// a parameter name goes on the wire and into the firmware's lookups: 1 to 15
// letters, digits or '_'
bool is_param_name(const std::string& name);

// what a module of this type gets from the scene's `programs` (its type's
// entry, then all's) and the scene-wide target: its program, parameters,
// may_stay_silent and target (firmware_at, param_at and target_at name where
// the scene says them; "" when nothing does)
SceneModule scene_module_of_type(const Scene& scene, const std::string& type);

// scene->world's start pose (head_position, heading_rad, roll_rad,
// head_orientation) from scene->placement and the chain; throws SceneError
// when the chain does not fit at the pipe's entry
void place_scene_chain(Scene* scene);

// the chain as module letters (scene key `chain` as a string: T touch, R
// rotation, ...): each module as scene_module_of_type gives it, then placed
// again. Throws SceneError for an unknown letter, an empty chain or more
// than kMaxSceneModules modules.
void set_chain(Scene* scene, const std::string& letters);

// one program parameter (as `params: {name: value}`) of the module at index
// module of the chain, of every module, of the central control, or of every
// endpoint whose program has this file name (program_file: "fw-sine" of
// "../build/fw-sine"; returns how many). Throws SceneError for a bad name, a
// value outside int32 or a module index past the chain's end.
void set_module_param(Scene* scene, int64_t module, const std::string& name, int64_t value);
void set_all_modules_param(Scene* scene, const std::string& name, int64_t value);
void set_central_param(Scene* scene, const std::string& name, int64_t value);
int set_program_param(Scene* scene, const std::string& program_file, const std::string& name, int64_t value);

// the file name of a program as a scene names it: "fw-sine" of "../build/fw-sine"
std::string program_file_name(const std::string& program);

// duration_s within the scene's bounds (0.001 .. 86400 s, and at least a tick)
void set_duration(Scene* scene, double duration_s);
// ODE's exact solver; solver_iterations (QuickStep's) back to its default
void set_exact_solver(Scene* scene);
// a start pose as `placement` gives it, placed (place_scene_chain); throws
// SceneError for an angle outside -360 .. 360 degrees or an inset outside
// 0 .. 1000 m
void set_placement(Scene* scene, const ScenePlacement& placement);
// one more `stop_when` rule; throws SceneError for along: pipe without a pipe
void add_stop_rule(Scene* scene, const StopRule& rule);

}  // namespace chainsim
