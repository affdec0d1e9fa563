// This build tree's programs for the PIC (build/pic/, made by
// tools/pic-build.sh) and the gpsim host that runs them: what the PIC tests
// of pic_test.cpp and pic_planted_test.cpp need (CHAINSIM_EXE and
// CHAINSIM_PIC_EXE come from tests/scenario/CMakeLists.txt).
#pragma once

#include <sys/stat.h>

#include <string>

namespace scenario {

inline std::string tree_pic_dir() {
  const std::string exe = CHAINSIM_EXE;
  return exe.substr(0, exe.rfind("/bin/")) + "/pic";
}

// the central control's and a rotation module's .hex (pic-build.sh builds
// every program at once) and chainsim-pic
inline bool tree_pic_built() {
  struct stat st {};
  return stat((tree_pic_dir() + "/fw-rotation.hex").c_str(), &st) == 0 &&
         stat((tree_pic_dir() + "/fw-central.hex").c_str(), &st) == 0 && stat(CHAINSIM_PIC_EXE, &st) == 0;
}

}  // namespace scenario
