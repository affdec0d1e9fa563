// A problem's parameters against the programs' declarations. See problem_params.h.
#include "optimize/problem_params.h"

#include <algorithm>

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
  // the individuals checked: the lowest and highest genes, and enough others
  // that every letter of every chain position is in one (the k-th letter of
  // each position in the k-th), so every program a chain can run is checked
  const std::vector<int64_t> upper = pr.genome.gene_upper();
  const size_t chain_genes = upper.size() - pr.genome.params.size();
  std::vector<std::vector<int64_t>> checked{std::vector<int64_t>(upper.size(), 0), upper};
  int64_t letters = 0;
  for (size_t i = 0; i < chain_genes; ++i) letters = std::max(letters, upper[i]);
  for (int64_t k = 1; k < letters; ++k) {
    std::vector<int64_t> genes(upper.size(), 0);
    for (size_t i = 0; i < chain_genes; ++i) genes[i] = std::min(k, upper[i]);
    checked.push_back(genes);
  }
  std::vector<int> program_targets(pr.genome.params.size(), 0);  // endpoints a program[NAME] gene reached
  std::string programs_seen;
  for (const std::vector<int64_t>& genes : checked) {
    Scene scene;
    try {
      scene = load_scene_text(individual_scene_yaml(pr, decode_genes(pr.genome, genes), 1), pr.scene_file);
    } catch (const SceneError& e) {
      throw ProblemError(pr.file + ": an individual's scene is not valid: " + e.what());
    }
    const int n = static_cast<int>(scene.modules.size());
    for (const ParamGene& g : pr.genome.params) {
      for (int i = 0; i <= n; ++i) {
        const SceneModule& e = i < n ? scene.modules[i] : scene.central;
        const bool targeted = g.scope == ParamGene::Scope::Central  ? i == n
                              : g.scope == ParamGene::Scope::Module ? i == g.module
                              : g.scope == ParamGene::Scope::Program
                                  ? !e.firmware.empty() && program_file_name(e.firmware) == g.program
                                  : i < n;
        if (!e.firmware.empty() && programs_seen.find(" " + program_file_name(e.firmware) + ",") == std::string::npos)
          programs_seen += " " + program_file_name(e.firmware) + ",";
        if (!targeted) continue;
        ++program_targets[static_cast<size_t>(&g - pr.genome.params.data())];
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
  for (size_t k = 0; k < pr.genome.params.size(); ++k) {
    const ParamGene& g = pr.genome.params[k];
    if (g.scope == ParamGene::Scope::Program && program_targets[k] == 0)
      throw ProblemError(g.where + ": '" + g.target + "': no module and no central control runs a program named " +
                         g.program + " (they run:" + programs_seen.substr(0, programs_seen.size() - 1) + ")");
  }
}

}  // namespace chainsim
