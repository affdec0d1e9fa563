// The benchmarks' clock (env_bench, pipe_drive_bench, servo_stand_bench):
// CPU time of the calling thread, so that their figures hold on a loaded
// machine.
#pragma once

#include <time.h>

namespace chainsim::bench {

// CPU time of this thread, us
inline double cpu_us() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec * 1e6 + t.tv_nsec * 1e-3;
}

}  // namespace chainsim::bench
