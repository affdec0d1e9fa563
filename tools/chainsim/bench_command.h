// `chainsim bench --bench B.yaml --setpoints S.csv --out OUT.csv`: the servo
// test stand (physics-server/analysis/servo_bench) on a set-point CSV; writes
// the output-shaft angle and the filtered current at the CSV's times.
// docs/servo-bench.md describes the model, the files and the agreement with
// the continuous equations.
#pragma once

namespace CLI {
class App;
}

namespace chainsim {

// registers the `bench` subcommand on `app`; its callback runs the bench
void add_bench_command(CLI::App& app);

// after app.parse(): the bench's exit code (0 ok, 1 bad input or output
// file, 3 internal error), or -1 when the bench subcommand was not given
int bench_command_exit_code();

}  // namespace chainsim
