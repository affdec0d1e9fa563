// `chainsim bench-search PROBLEM --history H.csv`: the design search's
// scheduler at core counts this machine does not have. The search runs as
// it would (its islands, cache, checkpoints), on a SimulatedPool whose
// evaluations sleep the wall times a real search recorded (scaled) and
// return its results; the table gives the cores' busy fraction per core
// count and number of islands (docs/benchmarks.md).
#pragma once

#include "chainsim/command.h"

namespace CLI {
class App;
}

namespace chainsim {

// registers the subcommand on app: what runs it, returning its exit code
Command add_bench_search_command(CLI::App& app);

}  // namespace chainsim
