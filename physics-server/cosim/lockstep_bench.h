// The lockstep's price for one scene: the co-simulation (one process per
// module, sockets, firmware) against the same servo commands replayed into a
// fresh world with no processes (replay.h), each the fastest of `repeat`
// runs. `chainsim bench-lockstep` (docs/benchmarks.md).
#pragma once

#include <cstdint>
#include <string>

#include "cosim/run_options.h"
#include "scene/scene.h"

namespace chainsim {

struct LockstepFigures {
  int exit_code = kExitOk;     // of the first co-simulation that did not finish cleanly
  std::string message;         // what stopped it
  double cosim_wall_s = 0;     // fastest co-simulation, wall seconds
  double physics_wall_s = 0;   // fastest physics-only replay, wall seconds
  double sim_s = 0;            // simulated seconds per run
  uint64_t exchanges = 0;      // TickBegin/TickEnd round trips of a co-simulation
  double ticks = 0;            // HAL ticks per run
  bool same_trace = true;      // every replay gave its co-simulation's trace byte for byte
  // CPU seconds (the least of the runs): the server process in a
  // co-simulation, its module processes, and the replay. Less disturbed by
  // other work on the machine than the wall clock.
  double cosim_cpu_s = 0, modules_cpu_s = 0, physics_cpu_s = 0;
  double cosim_rtf() const { return sim_s / cosim_wall_s; }
  double physics_rtf() const { return sim_s / physics_wall_s; }
  double ratio() const { return cosim_wall_s / physics_wall_s; }
  double cpu_ratio() const { return cosim_cpu_s / physics_cpu_s; }  // the server's CPU against the replay's
};

// runs the scene `repeat` times (opt.out_dir holds the last run) and replays
// each run's commands; stops at the first run that does not finish cleanly
LockstepFigures measure_lockstep(const Scene& scene, const RunOptions& opt, int repeat);

}  // namespace chainsim
