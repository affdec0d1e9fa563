// `chainsim bench-search PROBLEM --history H.csv`: the design search's
// scheduler at core counts this machine does not have. The search runs as
// it would (its islands, cache, checkpoints), on a SimulatedPool whose
// evaluations sleep the wall times a real search recorded (scaled) and
// return its results; the table gives the cores' busy fraction per core
// count and number of islands (docs/benchmarks.md).
#pragma once

namespace CLI {
class App;
}

namespace chainsim {

void add_bench_search_command(CLI::App& app);
int bench_search_command_exit_code();

}  // namespace chainsim
