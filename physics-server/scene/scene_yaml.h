// The strict YAML reader (readers/strict_yaml.h) as the scene loaders use it
// (scene.cpp, scene_environment.cpp, scene_modules.cpp): errors are
// SceneErrors; plus the one scene-only shape, a contact material.
#pragma once

#include <string>

#include "environment/material.h"
#include "readers/strict_yaml.h"
#include "scene/scene.h"

namespace chainsim {

struct SceneYaml : StrictYaml {
  explicit SceneYaml(const std::string& file)
      : StrictYaml(file, [](const std::string& message) { throw SceneError(message); }) {}

  // {mu, bounce, soft_erp, soft_cfm} (and `between` in a contacts entry)
  Material material(const YAML::Node& n, const std::string& path, const Material& dflt,
                    bool allow_between = false) const {
    if (allow_between)
      keys(n, path, {"between", "mu", "bounce", "soft_erp", "soft_cfm"});
    else
      keys(n, path, {"mu", "bounce", "soft_erp", "soft_cfm"});
    Material m = dflt;
    m.mu = number(n, "mu", m.mu, 0.0, 100.0, path);
    m.bounce = number(n, "bounce", m.bounce, 0.0, 1.0, path);
    m.soft_erp = number(n, "soft_erp", m.soft_erp, 0.0, 1.0, path);
    m.soft_cfm = number(n, "soft_cfm", m.soft_cfm, 0.0, 1.0, path);
    return m;
  }
};

}  // namespace chainsim
