// A run: the physics server that spawns one process per module plus the
// central control, advances them and the ODE world in lockstep, and writes
// the run directory. The tick loop is lockstep_server.cpp; the processes and
// their links endpoints.cpp; the barrier and bus barrier.cpp, bus.cpp; the
// files output/.
#pragma once

#include <vector>

#include "cosim/replay.h"
#include "cosim/run_options.h"
#include "scene/scene.h"

namespace chainsim {

// run scene; record, if given, collects every applied servo command
RunResult run_scene(const Scene& scene, const RunOptions& options,
                    std::vector<ServoCommand>* record = nullptr);

}  // namespace chainsim
