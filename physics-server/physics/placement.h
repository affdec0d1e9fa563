// Where the chain starts: helpers that fill WorldConfig's head pose
// (head_position, head_orientation) from the environment.
#pragma once

#include <string>
#include <vector>

#include "physics/chain_model.h"
#include "physics/world_config.h"

namespace chainsim {

// distance from the head's front face to the tail's back face of the chain
// as assembled (straight), m; compiles chain (module type names) as
// compile_chain does: module_types, then the built-ins
double chain_length_m(const std::vector<std::string>& chain,
                      const std::vector<ModuleDef>& module_types = {});

// Lays `chain` on the axis of the pipe's first straight segment, head first
// into the pipe: the tail's back face inset_m inside the entry, module z
// along the pipe's "up" (pipe_path.h); sets cfg's head pose and lays chain's
// frames from it. Throws std::invalid_argument if the environment is not a
// pipe or the straight is shorter than inset + chain.
void place_chain_at_pipe_entry(WorldConfig* cfg, ChainModel* chain, double inset_m);
// the same for module type names, head first (compiled from cfg, then dropped)
void place_chain_at_pipe_entry(WorldConfig* cfg, const std::vector<std::string>& chain,
                               double inset_m);

}  // namespace chainsim
