// The scenes of a robot calibration, one per table row, and their variants
// with the knobs set: each scene is loaded with the scene loader (nominal
// values come from the loaded Scene and ModuleDefs), and a variant is the
// scene's YAML with the changed values edited in as yaml-cpp nodes (module
// types it changes are written next to it as module files).
#pragma once

#include <string>
#include <vector>

#include "analysis/robot_calibration/robot_knobs.h"
#include "scene/scene.h"

namespace chainsim {

class SceneVariants {
 public:
  // loads scene_template with {slope} replaced by each key; throws RobotError
  SceneVariants(const std::string& scene_template, const std::vector<std::string>& keys);

  size_t size() const { return scenes_.size(); }
  const Scene& scene(size_t i) const { return scenes_[i]; }
  // a knob's nominal value in the first row's scene (0: nothing to act on)
  double nominal(int knob) const;
  // the knobs that act on these scenes, in catalogue order
  const std::vector<int>& usable() const { return usable_; }

  // the YAML text of row i's scene with the setting applied; the module
  // types it changes are written to dir. Relative paths in the scene are
  // made absolute: the text is written elsewhere.
  std::string scene_text(size_t i, const KnobSetting& st, const std::string& dir) const;

 private:
  std::vector<std::string> texts_, dirs_;
  std::vector<Scene> scenes_;
  ChainModel chain0_;   // the first row's chain, compiled: the nominal values are its modules'
  std::map<std::string, std::string> type_text_;   // edited module types: their file's text (first row)
  std::map<int, double> nominal_;
  std::vector<int> usable_;
};

}  // namespace chainsim
