// An individual as a scene: the problem's base scene (as loaded) with the
// genome applied through scene/'s edits (scene_edit.h: the chain string,
// program parameters), its own seed and duration, and written by
// write_scene (scene_write.h), which makes every file it names absolute so
// that the text runs from anywhere. This text is what `chainsim run`
// simulates for the individual, and what best.yaml holds.
#pragma once

#include <cstdint>
#include <string>

#include "optimize/genome.h"
#include "scene/scene.h"
#include "scene/scene_edit.h"  // program_file_name: what a program[NAME] target matches

namespace chainsim {

struct Problem;

// the seed of an individual's run: from the search seed and the individual's
// key only (never from the worker that runs it), in 0 .. 2^62 - 1
uint64_t evaluation_seed(uint64_t search_seed, const std::string& key);

// the scene; throws SceneError if the base scene cannot take the genome.
// seed is the trial's: the run's seed, and (with evaluation.perturb) where
// the start pose's perturbation is drawn from. solver "exact" runs it with
// the converged solver (verification); "" as the base scene says. target
// "native" or "pic" puts every endpoint on it ("": the problem's --target).
Scene individual_scene(const Problem& problem, const Phenotype& p, uint64_t seed, const std::string& solver = "",
                       const std::string& target = "");
// the same as the text of a scene file (write_scene)
std::string individual_scene_yaml(const Problem& problem, const Phenotype& p, uint64_t seed,
                                  const std::string& solver = "", const std::string& target = "");

// the start pose's perturbation of a trial seeded so: offsets along the
// chain's axis and sideways (m), of heading and roll (degrees), each uniform
// within the problem's bounds (along in a pipe: 0 .. along_m)
struct StartPerturbation {
  double along_m = 0, lateral_m = 0, heading_deg = 0, roll_deg = 0;
};
StartPerturbation start_perturbation(const Problem& problem, uint64_t seed, bool pipe_entry);

}  // namespace chainsim
