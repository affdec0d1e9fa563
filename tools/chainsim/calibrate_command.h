// `chainsim calibrate --bench B.yaml --measured M.csv --out DIR`: servo
// calibration (physics-server/analysis/calibration): refits the servo's base
// parameters to a bench measurement, finds the catalogue effects it misses,
// writes DIR/report.json, report.md and SVG plots. With --robot: robot-level
// calibration (physics-server/analysis/robot_calibration). docs/calibration.md.
#pragma once

#include "chainsim/command.h"

namespace CLI {
class App;
}

namespace chainsim {

// registers the subcommand on app: what runs it, returning its exit code
Command add_calibrate_command(CLI::App& app);

}  // namespace chainsim
