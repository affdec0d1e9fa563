// libm_probe: calls use_baseline_libm as chainsim's main does, then prints
// what glibc chose for this process (for libm_restart_test.cpp)
#include <sys/platform/x86.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>

#include "determinism/libm_variants.h"

int main(int, char** argv) {
  chainsim::use_baseline_libm("libm_probe", argv);
  const char* t = std::getenv("GLIBC_TUNABLES");
  std::printf("pid=%d avx2=%d fma=%d marker=%d tunables=%s\n", static_cast<int>(getpid()),
              CPU_FEATURE_ACTIVE(AVX2) ? 1 : 0, CPU_FEATURE_ACTIVE(FMA) ? 1 : 0,
              std::getenv("CHAINSIM_LIBM_RESTARTED") ? 1 : 0, t ? t : "(unset)");
  return 0;
}
