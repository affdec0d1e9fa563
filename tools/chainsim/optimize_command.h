// `chainsim optimize PROBLEM.yaml --out DIR`: the design search (docs/optimize.md).
// The command only wires the library in physics-server/optimize/: the pool
// (local workers, or MPI ranks under mpirun), the search, the best's replay
// and the report.
#pragma once

#include "chainsim/command.h"

namespace CLI {
class App;
}

namespace chainsim {

// registers the subcommand on app: what runs it, returning its exit code
Command add_optimize_command(CLI::App& app);

}  // namespace chainsim
