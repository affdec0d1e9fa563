#include "optimize/individual_scene.h"

#include <cmath>
#include <filesystem>

#include <Eigen/Core>

#include "optimize/problem.h"
#include "scene/scene.h"
#include "scene/scene_edit.h"
#include "scene/scene_write.h"
#include "physics/splitmix64.h"

namespace chainsim {

namespace {

// an angle in (-180, 180], degrees (a perturbed heading stays in the scene's range)
double wrapped_deg(double a) {
  a = std::fmod(a, 360.0);
  if (a > 180) a -= 360;
  if (a <= -180) a += 360;
  return a;
}

// the trial's start pose: the base scene's placement moved and turned by
// start_perturbation (the scene's own checks then apply to the result)
void perturb_placement(const Problem& pr, uint64_t seed, Scene* s) {
  ScenePlacement pl = s->placement;
  const StartPerturbation d = start_perturbation(pr, seed, pl.at_pipe_entry);
  if (d.roll_deg != 0) pl.roll_deg = wrapped_deg(pl.roll_deg + d.roll_deg);
  if (pl.at_pipe_entry) {
    if (d.along_m != 0) pl.inset_m += d.along_m;
  } else {
    const double h = pl.heading_deg * M_PI / 180;
    const Eigen::Vector3d dir(std::cos(h), std::sin(h), 0), side(-std::sin(h), std::cos(h), 0);
    Eigen::Vector3d pos = pl.position_m + d.along_m * dir + d.lateral_m * side;
    if (d.along_m != 0 || d.lateral_m != 0)
      for (int i = 0; i < 3; ++i) pl.position_m[i] = std::round(pos[i] * 1e6) / 1e6;
    if (d.heading_deg != 0) pl.heading_deg = wrapped_deg(pl.heading_deg + d.heading_deg);
  }
  set_placement(s, pl);
}

}  // namespace

uint64_t evaluation_seed(uint64_t search_seed, const std::string& key) {
  uint64_t h = 0xcbf29ce484222325ull;  // FNV-1a of the key
  for (unsigned char c : key) h = (h ^ c) * 0x100000001b3ull;
  return splitmix64(h ^ splitmix64(search_seed)) >> 2;
}

StartPerturbation start_perturbation(const Problem& pr, uint64_t seed, bool pipe_entry) {
  const PerturbSettings& b = pr.evaluation.perturb;
  // four uniform numbers in [-1, 1) from the seed alone
  auto u = [&](uint64_t k) {
    const uint64_t x = splitmix64(seed ^ splitmix64(0x70E7B0A7u + k));
    return static_cast<double>(x >> 11) * 0x1.0p-52 - 1.0;
  };
  auto round_to = [](double v, double grain) { return std::round(v / grain) * grain; };
  StartPerturbation s;
  s.along_m = round_to(pipe_entry ? b.along_m * 0.5 * (u(0) + 1.0) : b.along_m * u(0), 1e-6);
  s.lateral_m = round_to(b.lateral_m * u(1), 1e-6);
  s.heading_deg = round_to(b.heading_deg * u(2), 1e-3);
  s.roll_deg = round_to(b.roll_deg * u(3), 1e-3);
  return s;
}

Scene individual_scene(const Problem& pr, const Phenotype& p, uint64_t seed, const std::string& solver,
                       const std::string& target_override) {
  const std::string& target = !target_override.empty() ? target_override : pr.evaluation.target;
  Scene s = pr.scene ? *pr.scene : load_scene_text(pr.scene_text, pr.scene_file);
  s.world.seed = seed;
  if (pr.evaluation.duration_s > 0) set_duration(&s, pr.evaluation.duration_s);
  if (solver == "exact") set_exact_solver(&s);
  for (const StopRule& r : pr.evaluation.stop_when) add_stop_rule(&s, r);
  // the chain before the start pose: a pipe entry places the chain it has
  if (pr.genome.has_chain) set_chain(&s, p.chain);
  if (pr.evaluation.perturb.any()) perturb_placement(pr, seed, &s);
  // --target: every endpoint on it, whatever the scene says module by module
  if (!target.empty()) set_target(&s, target == "pic" ? Target::Pic : Target::Native);

  for (size_t k = 0; k < pr.genome.params.size() && k < p.values.size(); ++k) {
    const ParamGene& g = pr.genome.params[k];
    const int64_t v = p.values[k];
    try {
      switch (g.scope) {
        case ParamGene::Scope::Central: set_central_param(&s, g.name, v); break;
        case ParamGene::Scope::Module: set_module_param(&s, g.module, g.name, v); break;
        case ParamGene::Scope::AllModules: set_all_modules_param(&s, g.name, v); break;
        case ParamGene::Scope::Program: set_program_param(&s, g.program, g.name, v); break;
      }
    } catch (const SceneError& e) {
      throw SceneError(pr.file + ": " + g.target + ": " + e.what());
    }
  }
  return s;
}

std::string individual_scene_yaml(const Problem& pr, const Phenotype& p, uint64_t seed, const std::string& solver,
                                  const std::string& target) {
  return write_scene(individual_scene(pr, p, seed, solver, target));
}

}  // namespace chainsim
