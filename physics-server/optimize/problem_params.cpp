// A problem's parameters against the programs' declarations. See problem_params.h.
#include "optimize/problem_params.h"

#include "cosim/program_params.h"
#include "optimize/individual_scene.h"
#include "scene/scene_params.h"

namespace chainsim {

void check_problem_params(const Problem& pr, const std::string& firmware_dir) {
  try {
    check_scene_programs(load_scene_text(pr.scene_text, pr.scene_file), firmware_dir);
  } catch (const SceneError& e) {
    throw ProblemError(std::string(e.what()) + " (the base scene of " + pr.file + ")");
  }
  ProgramParamsCache known;
  auto decls_of = [&](const ParamGene& g, const SceneModule& e) -> const ProgramParams& {
    const std::string path = program_path(e.firmware, firmware_dir);
    return known.get(path, e.firmware, [&](const std::string& why) {
      throw ProblemError(g.where + ": '" + g.target + "': program " + path + " did not list its parameters: " + why);
    });
  };
  const std::vector<int64_t> lowest(pr.genome.gene_count(), 0);
  for (const std::vector<int64_t>& genes : {lowest, pr.genome.gene_upper()}) {
    Scene scene;
    try {
      scene = load_scene_text(individual_scene_yaml(pr, decode_genes(pr.genome, genes), 1), pr.scene_file);
    } catch (const SceneError& e) {
      throw ProblemError(pr.file + ": an individual's scene is not valid: " + e.what());
    }
    const int n = static_cast<int>(scene.modules.size());
    for (const ParamGene& g : pr.genome.params) {
      for (int i = 0; i <= n; ++i) {
        const bool targeted = g.scope == ParamGene::Scope::Central ? i == n
                              : g.scope == ParamGene::Scope::Module ? i == g.module
                                                                     : i < n;
        if (!targeted) continue;
        const SceneModule& e = i < n ? scene.modules[i] : scene.central;
        const ProgramParams& decls = decls_of(g, e);
        const ParamDecl* d = decls.find(g.name);
        const std::string who = scene_endpoint_name(scene, i);
        if (!d) {
          const std::string near = nearest_param(decls, g.name);
          throw ProblemError(g.where + ": '" + g.target + "': program " + e.firmware + " of " + who +
                             " declares no parameter '" + g.name + "' (" +
                             (near.empty() ? "" : "did you mean '" + near + "'? ") + "its parameters: " +
                             decls.names() + ")");
        }
        if (g.min < d->min || g.max > d->max)
          throw ProblemError(g.where + ": '" + g.target + "' ranges over " + std::to_string(g.min) + ".." +
                             std::to_string(g.max) + ", beyond the range " + std::to_string(d->min) + ".." +
                             std::to_string(d->max) + " that program " + e.firmware + " of " + who +
                             " declares (" + d->meaning + ")");
      }
    }
  }
}

}  // namespace chainsim
