// A scene's parameters against the programs' declarations. See scene_params.h.
#include "scene/scene_params.h"

#include <algorithm>

#include "chainsim_protocol.h"

namespace chainsim {
namespace {

size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diag = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

std::string where_of(const SceneModule& e, const std::string& name, const Scene& scene) {
  const auto it = e.param_at.find(name);
  return it != e.param_at.end() ? it->second : scene.source;
}

}  // namespace

const ParamDecl* ProgramParams::find(const std::string& name) const {
  for (const ParamDecl& d : params)
    if (d.name == name) return &d;
  return nullptr;
}

std::string ProgramParams::names() const {
  std::string out;
  for (const ParamDecl& d : params) out += (out.empty() ? "" : ", ") + d.name;
  return out.empty() ? "none" : out;
}

std::string nearest_param(const ProgramParams& decls, const std::string& name) {
  std::string best;
  size_t best_d = 3;
  for (const ParamDecl& d : decls.params) {
    const bool prefix = d.name.rfind(name, 0) == 0 || name.rfind(d.name, 0) == 0;
    const size_t dist = prefix ? 1 : edit_distance(d.name, name);
    if (dist < best_d) {
      best_d = dist;
      best = d.name;
    }
  }
  return best;
}

std::string scene_endpoint_name(const Scene& scene, int index) {
  if (index >= static_cast<int>(scene.modules.size())) return "the central control";
  return "module " + std::to_string(index) + " (" + scene.modules[index].type + ")";
}

void check_scene_params(const Scene& scene, const ParamsOf& params_of) {
  const int n = static_cast<int>(scene.modules.size());
  for (int i = 0; i <= n; ++i) {
    const SceneModule& e = i < n ? scene.modules[i] : scene.central;
    if (e.params.empty()) continue;
    const std::string who = scene_endpoint_name(scene, i);
    // programs.all, programs.<type> and the module's own merge: more than a WELCOME carries
    if (e.params.size() > CS_PARAMS_MAX)
      throw SceneError(where_of(e, e.params.rbegin()->first, scene) + ": " + who + " is given " +
                       std::to_string(e.params.size()) + " parameters (programs.all, programs." + e.type +
                       " and its own together), more than the " + std::to_string(CS_PARAMS_MAX) +
                       " a program can be given");
    const ProgramParams& decls = params_of(e, who);
    for (const auto& [name, value] : e.params) {
      const ParamDecl* d = decls.find(name);
      if (!d) {
        const std::string near = nearest_param(decls, name);
        throw SceneError(where_of(e, name, scene) + ": parameter '" + name + "' of " + who + ": program " +
                         decls.program + " declares no such parameter (" +
                         (near.empty() ? "" : "did you mean '" + near + "'? ") + "its parameters: " +
                         decls.names() + "; `chainsim params " + decls.program + "` lists them)");
      }
      if (value < d->min || value > d->max)
        throw SceneError(where_of(e, name, scene) + ": parameter '" + name + "' of " + who + " is " +
                         std::to_string(value) + ", outside the range " + std::to_string(d->min) + ".." +
                         std::to_string(d->max) + " that program " + decls.program + " declares (" +
                         d->meaning + ")");
    }
  }
}

}  // namespace chainsim
