// A scene checked without running it. See scene_check.h.
#include "cosim/scene_check.h"

#include <unistd.h>

#include <exception>

#include "cosim/endpoints.h"
#include "cosim/run_options.h"
#include "physics/world.h"

namespace chainsim {

SceneCheck check_scene(const Scene& scene, const std::string& firmware_dir) {
  SceneCheck r;
  int bodies = 0;
  try {
    const World world(scene.world, compile_chain(scene));  // as the run builds it: the same errors
    for (int m = 0; m < world.module_count(); ++m) bodies += world.body_count(m);
  } catch (const WorldSetupError& e) {  // as a run says it: the scene asks for a world that cannot be built
    r.exit_code = kExitBadInput;
    r.message = scene.source + ": " + e.what();
    return r;
  } catch (const std::exception& e) {
    r.exit_code = kExitInternal;  // what a run would say: the loader let through what the World refused
    r.message = e.what();
    return r;
  }
  const std::vector<std::string> types = endpoint_types(scene);
  int on_pic = 0;
  for (size_t i = 0; i < types.size(); ++i) {
    const bool central = i + 1 == types.size();
    const SceneModule& e = central ? scene.central : scene.modules[i];
    const bool pic = e.target == Target::Pic;
    on_pic += pic;
    const std::string path = pic ? pic_hex_path(e.firmware, firmware_dir) : program_path(e.firmware, firmware_dir);
    if (pic ? !path.empty() : access(path.c_str(), X_OK) == 0) continue;
    r.exit_code = kExitBadInput;
    r.message = "program for " + (central ? std::string("central control") : "module " + std::to_string(i)) +
                " (" + types[i] + ") " +
                (pic ? "on the PIC: " + pic_hex_missing(e.firmware, firmware_dir) : "not found or not executable: " + path);
    return r;
  }
  r.message = scene.source + ": ok: " + std::to_string(scene.modules.size()) + " modules, " +
              std::to_string(bodies) + " bodies, " + std::to_string(types.size()) + " programs found" +
              (on_pic ? " (" + std::to_string(on_pic) + " as .hex for the PIC, their modules' sensors on the board's pins)" : "") +
              "; no run was started (a native program the scene gives parameters ran once with "
              "--chainsim-params, to list the ones it declares)";
  return r;
}

}  // namespace chainsim
