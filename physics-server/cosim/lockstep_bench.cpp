// The lockstep's price for one scene. See lockstep_bench.h.
#include "cosim/lockstep_bench.h"

#include <algorithm>
#include <vector>

#include "cosim/lockstep_server.h"
#include "cosim/replay.h"

namespace chainsim {

LockstepFigures measure_lockstep(const Scene& scene, const RunOptions& opt, int repeat) {
  LockstepFigures f;
  f.sim_s = scene.duration_s;
  f.ticks = scene.duration_s * 1e6 / scene.tick_us;
  f.cosim_wall_s = f.physics_wall_s = 1e300;
  // the best of `repeat` for each side: wall-clock figures on a shared machine are noisy
  for (int rep = 0; rep < std::max(1, repeat); ++rep) {
    std::vector<ServoCommand> commands;
    const RunResult r = run_scene(scene, opt, &commands);
    if (r.exit_code != kExitOk) {
      f.exit_code = r.exit_code;
      f.message = r.message;
      return f;
    }
    f.exchanges = r.exchanges;
    f.cosim_wall_s = std::min(f.cosim_wall_s, r.wall_time_s);
    std::string sha;
    f.physics_wall_s = std::min(f.physics_wall_s, replay_physics(scene, commands, &sha));
    f.same_trace &= sha == r.summary["trace_sha256"].get<std::string>();
  }
  return f;
}

}  // namespace chainsim
