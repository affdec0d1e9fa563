// `chainsim run [SCENE.yaml]`: a scene run in lockstep (docs/README); --live, --watch, --compare.
#pragma once

#include <string>

#include "chainsim/command.h"
#include "scene/scene.h"

namespace CLI {
class App;
}

namespace chainsim {

// registers the subcommand on app: what runs it, returning its exit code
Command add_run_command(CLI::App& app);

// a run is whole ticks: a --duration shorter than one tick of the scene would
// silently become one tick. The error, or "" when it is not shorter or not
// given (duration <= 0); bench-lockstep's --duration too
std::string duration_error(double duration, const Scene& scene);

}  // namespace chainsim
