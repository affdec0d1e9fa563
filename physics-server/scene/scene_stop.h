// The scene key `stop_when`: rules that end a run before its duration
// (scene.h, StopRule; docs/scene-reference.md). Errors are SceneErrors
// naming file:line:column and the key.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>

#include "scene/scene.h"

namespace chainsim {

// fills scene->stop_when from `stop_when` (a list); the environment must be
// loaded already (`along: pipe` needs a pipe). path names the key in errors
// (a problem file's `evaluation.stop_when` has the same form)
void load_scene_stop_when(const std::string& file, const YAML::Node& stop_when, Scene* scene,
                          const std::string& path = "stop_when");

// the rule as a `stop_when` entry, as load_scene_stop_when reads it
YAML::Node stop_rule_yaml(const StopRule& r);

// the rule in the scene's words, for messages and summary.json:
// "no_progress of head along pipe by 0.005 m within 10 s"
std::string stop_rule_text(const StopRule& r);

}  // namespace chainsim
