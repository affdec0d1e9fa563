// `chainsim bench --bench B.yaml --setpoints S.csv --out OUT.csv`: the servo
// test stand (physics-server/analysis/servo_bench) on a set-point CSV; writes
// the output-shaft angle and the filtered current at the CSV's times.
// docs/servo-bench.md describes the model, the files and the agreement with
// the continuous equations.
#pragma once

#include "chainsim/command.h"

namespace CLI {
class App;
}

namespace chainsim {

// registers the subcommand on app: what runs it, returning its exit code
Command add_bench_command(CLI::App& app);

}  // namespace chainsim
