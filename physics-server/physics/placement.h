// Where the chain starts: helpers that fill WorldConfig's head pose
// (head_position, head_orientation) from the environment.
#pragma once

#include "physics/chain_model.h"
#include "physics/world_config.h"

namespace chainsim {

// Lays `chain` on the axis of the pipe's first straight segment, head first
// into the pipe: the tail's back face inset_m inside the entry, module z
// along the pipe's "up" (pipe_path.h); sets cfg's head pose and lays chain's
// frames from it. Throws std::invalid_argument if the environment is not a
// pipe or the straight is shorter than inset + chain.
void place_chain_at_pipe_entry(WorldConfig* cfg, ChainModel* chain, double inset_m);

}  // namespace chainsim
