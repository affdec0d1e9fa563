// chainsim: the command line of the co-simulator.
//   chainsim run [SCENE.yaml]        run a scene (default: the built-in one)
//   chainsim view RUN_DIR            replay.html of a run (--png: a picture); run --live: live view
//   chainsim bench                   one servo on a test stand (set-points in, angle and current out)
//   chainsim calibrate               find what the servo model misses against a measurement
//   chainsim test PATH...            run test files (scene + expectations); JUnit XML for CI
//   chainsim bench-lockstep          price of processes and sockets vs physics only
//   chainsim optimize PROBLEM.yaml   design search: GA over chains and parameters (local workers or MPI)
//   chainsim params PROGRAM          the parameters a module program declares
// Each subcommand is a file of its own (tools/chainsim/<name>_command.cpp,
// chainsim/command.h); this file only registers them and runs the one given.
#include <CLI/CLI.hpp>

#include <vector>

#include "chainsim/bench_command.h"
#include "chainsim/bench_lockstep_command.h"
#include "chainsim/bench_search_command.h"
#include "chainsim/calibrate_command.h"
#include "chainsim/command.h"
#include "chainsim/optimize_command.h"
#include "chainsim/params_command.h"
#include "chainsim/run_command.h"
#include "chainsim/test_command.h"
#include "chainsim/view_command.h"
#include "cosim/run_options.h"
#include "determinism/libm_variants.h"
#include "testing/test_runner.h"

using namespace chainsim;

int main(int argc, char** argv) {
  use_baseline_libm("chainsim", argv);  // the same bytes on every CPU (may start this program again)
  CLI::App app{"chainsim: firmware-in-the-loop co-simulator for chained modular robots"};
  app.require_subcommand(1);
  const std::vector<Command> commands = {
      add_run_command(app),      add_view_command(app),      add_bench_lockstep_command(app),
      add_bench_command(app),    add_calibrate_command(app), add_test_command(app),
      add_optimize_command(app), add_bench_search_command(app), add_params_command(app),
  };
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);  // prints help, or the error and a hint
    return rc == 0 ? 0 : test_command_selected() ? kTestExitMalformed : kExitBadInput;
  }
  for (const Command& c : commands)
    if (c.app->parsed()) return c.run();
  return kExitBadInput;
}
