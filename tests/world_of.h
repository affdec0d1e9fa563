// Test helpers: a World, or a pipe-entry placement, from module type names,
// head first. A run compiles its scene's chain once (compile_chain) and hands
// the ChainModel to placement and the World, which take nothing else; a test
// that builds a World by hand names its modules, and the chain is compiled
// here the same way.
#pragma once

#include <string>
#include <vector>

#include "physics/chain_model.h"
#include "physics/placement.h"
#include "physics/world.h"

namespace chainsim {

// throws std::invalid_argument naming an unknown type, as compile_chain does
inline World world_of(const WorldConfig& config, const std::vector<std::string>& types) {
  return World(config, compile_chain(config, types));
}

// sets config's head pose so that the chain of `types` lies at the pipe's
// entry (place_chain_at_pipe_entry)
inline void place_types_at_pipe_entry(WorldConfig* config, const std::vector<std::string>& types, double inset_m) {
  ChainModel chain = compile_chain(*config, types);
  place_chain_at_pipe_entry(config, &chain, inset_m);
}

}  // namespace chainsim
