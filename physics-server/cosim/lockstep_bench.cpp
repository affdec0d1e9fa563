// The lockstep's price for one scene. See lockstep_bench.h.
#include "cosim/lockstep_bench.h"

#include <sys/resource.h>

#include <algorithm>
#include <ctime>
#include <vector>

#include "cosim/lockstep_server.h"
#include "cosim/replay.h"

namespace chainsim {
namespace {

// CPU seconds of this process (every thread)
double process_cpu_s() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + t.tv_nsec * 1e-9;
}

// CPU seconds of this process's children that have ended and been waited for
double children_cpu_s() {
  rusage u{};
  getrusage(RUSAGE_CHILDREN, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + (u.ru_utime.tv_usec + u.ru_stime.tv_usec) * 1e-6;
}

}  // namespace

LockstepFigures measure_lockstep(const Scene& scene, const RunOptions& opt, int repeat) {
  LockstepFigures f;
  f.sim_s = scene.duration_s;
  f.ticks = scene.duration_s * 1e6 / scene.tick_us;
  f.cosim_wall_s = f.physics_wall_s = 1e300;
  f.cosim_cpu_s = f.modules_cpu_s = f.physics_cpu_s = 1e300;
  // the best of `repeat` for each side: wall-clock figures on a shared machine are noisy
  for (int rep = 0; rep < std::max(1, repeat); ++rep) {
    std::vector<ServoCommand> commands;
    const double cpu0 = process_cpu_s(), children0 = children_cpu_s();
    const RunResult r = run_scene(scene, opt, &commands);
    const double cpu1 = process_cpu_s(), children1 = children_cpu_s();
    if (r.exit_code != kExitOk) {
      f.exit_code = r.exit_code;
      f.message = r.message;
      return f;
    }
    f.exchanges = r.exchanges;
    f.cosim_wall_s = std::min(f.cosim_wall_s, r.wall_time_s);
    f.cosim_cpu_s = std::min(f.cosim_cpu_s, cpu1 - cpu0);
    f.modules_cpu_s = std::min(f.modules_cpu_s, children1 - children0);
    std::string sha;
    f.physics_wall_s = std::min(f.physics_wall_s, replay_physics(scene, commands, &sha));
    f.physics_cpu_s = std::min(f.physics_cpu_s, process_cpu_s() - cpu1);
    f.same_trace &= sha == r.summary["trace_sha256"].get<std::string>();
  }
  return f;
}

}  // namespace chainsim
