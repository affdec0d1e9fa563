// `chainsim bench-lockstep`: the co-simulation's price against physics only (docs/benchmarks.md).
#pragma once

#include "chainsim/command.h"

namespace CLI {
class App;
}

namespace chainsim {

// registers the subcommand on app: what runs it, returning its exit code
Command add_bench_lockstep_command(CLI::App& app);

}  // namespace chainsim
