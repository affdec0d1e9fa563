// `chainsim optimize PROBLEM.yaml --out DIR`: the design search (docs/optimize.md).
// The command only wires the library in physics-server/optimize/: the pool
// (local workers, or MPI ranks under mpirun), the search, the best's replay
// and the report.
#pragma once

namespace CLI {
class App;
}

namespace chainsim {

// registers the `optimize` subcommand on app
void add_optimize_command(CLI::App& app);

// after app.parse(): the command's exit code, or -1 when it was not given
int optimize_command_exit_code();

}  // namespace chainsim
