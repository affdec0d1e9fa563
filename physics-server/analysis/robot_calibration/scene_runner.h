// Runs a robot calibration's scenes: for a knob setting, one `chainsim run`
// process per table row (the same lockstep machinery and module programs as
// any run; ChildProcess, at most `jobs` at once), and the head's speed of
// each run. Settings already run come from a cache.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "analysis/robot_calibration/scene_variants.h"

namespace chainsim {

struct SceneRunOptions {
  std::string chainsim_exe;   // the chainsim executable
  std::string firmware_dir;   // --firmware-dir of the runs ("" = next to chainsim)
  std::string work_dir;       // where scenes and run directories go (emptied first)
  double duration_s = 6;      // simulated seconds per run
  double window_start_s = 1;  // the speed is measured from here to the end of the run
  int jobs = 2;               // runs at once
};

class SceneRunner {
 public:
  // keys: each row's key (names its run directory); throws RobotError when
  // the work directory cannot be made
  SceneRunner(const SceneVariants& scenes, std::vector<std::string> keys, SceneRunOptions options);

  // the head's speed per row, cm/s, with the knobs set; throws RobotError
  // when a run fails (its log in the message)
  std::vector<double> speeds(const KnobSetting& st);

  int runs() const { return runs_; }                    // processes run
  size_t settings() const { return cache_.size(); }     // settings evaluated
  double run_wall_s() const { return run_wall_s_; }     // wall time spent in runs

 private:
  const SceneVariants& scenes_;
  std::vector<std::string> keys_;
  SceneRunOptions opt_;
  std::map<std::string, std::vector<double>> cache_;   // setting_key -> speeds
  int runs_ = 0;
  double run_wall_s_ = 0;
};

}  // namespace chainsim
