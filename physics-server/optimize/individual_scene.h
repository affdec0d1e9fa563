// An individual as a scene: the problem's base scene with the genome applied
// (the chain string, program parameters), its own seed and duration, and
// every file it names made absolute so that the text runs from anywhere.
// This text is what `chainsim run` simulates for the individual, and what
// best.yaml holds.
#pragma once

#include <cstdint>
#include <string>

#include "optimize/genome.h"

namespace chainsim {

struct Problem;

// the seed of an individual's run: from the search seed and the individual's
// key only (never from the worker that runs it), in 0 .. 2^62 - 1
uint64_t evaluation_seed(uint64_t search_seed, const std::string& key);

// the scene text; throws SceneError if the base scene cannot take the genome
std::string individual_scene_yaml(const Problem& problem, const Phenotype& p, uint64_t seed);

}  // namespace chainsim
