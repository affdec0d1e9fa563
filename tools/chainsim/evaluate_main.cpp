// chainsim-evaluate SCENE.yaml OUT_DIR MODULE_TIMEOUT_S [FIRMWARE_DIR]: one run
// of a scene for `chainsim optimize`, through the same run_scene as `chainsim
// run SCENE --out OUT_DIR --quiet --module-timeout T [--firmware-dir DIR]`,
// with the same exit codes. A program of
// its own because the search starts hundreds of these: `chainsim` itself
// links pagmo and OpenMPI, whose start-up (pagmo's static registrations
// above all) cost about 0.2 s per process here, this one does not.
#include <cstdio>
#include <cstdlib>
#include <exception>

#include "cosim/lockstep_server.h"
#include "cosim/program_params.h"
#include "determinism/libm_variants.h"
#include "scene/scene.h"

using namespace chainsim;

int main(int argc, char** argv) {
  use_baseline_libm("chainsim-evaluate", argv);  // the same bytes on every CPU
  if (argc != 4 && argc != 5) {
    std::fprintf(stderr, "usage: chainsim-evaluate SCENE.yaml OUT_DIR MODULE_TIMEOUT_S [FIRMWARE_DIR[:DIR...]]\n");
    return kExitBadInput;
  }
  const std::string firmware_dir = argc == 5 ? argv[4] : "";
  Scene scene;
  try {
    scene = load_scene_file(argv[1]);
    check_scene_programs(scene, firmware_dir);
  } catch (const SceneError& e) {
    std::fprintf(stderr, "chainsim-evaluate: %s\n", e.what());
    return kExitBadInput;
  }
  RunOptions opt;
  opt.out_dir = argv[2];
  opt.firmware_dir = firmware_dir;
  opt.quiet = true;
  opt.module_timeout_s = std::atof(argv[3]);
  if (!(opt.module_timeout_s > 0)) {
    std::fprintf(stderr, "chainsim-evaluate: MODULE_TIMEOUT_S must be a positive number of seconds\n");
    return kExitBadInput;
  }
  try {
    const RunResult r = run_scene(scene, opt);
    if (r.exit_code != kExitOk) std::fprintf(stderr, "chainsim-evaluate: run stopped: %s\n", r.message.c_str());
    return r.exit_code;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "chainsim-evaluate: %s\n", e.what());
    return kExitInternal;
  }
}
