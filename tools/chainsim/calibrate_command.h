// `chainsim calibrate --bench B.yaml --measured M.csv --out DIR`: servo
// calibration (physics-server/analysis/calibration): refits the servo's base
// parameters to a bench measurement, finds the catalogue effects it misses,
// writes DIR/report.json, report.md and SVG plots. With --robot: robot-level
// calibration (physics-server/analysis/robot_calibration). docs/calibration.md.
#pragma once

namespace CLI {
class App;
}

namespace chainsim {

// registers the `calibrate` subcommand on `app`
void add_calibrate_command(CLI::App& app);

// after app.parse(): 0 ok, 1 bad input or output, 3 internal error, -1 when
// the calibrate subcommand was not given
int calibrate_command_exit_code();

}  // namespace chainsim
