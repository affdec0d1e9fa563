// `chainsim calibrate --bench B.yaml --measured M.csv --out DIR`: refits the
// servo's base parameters to a bench measurement, localises where the model
// disagrees, and adds effects from the servo model's catalogue (servo_model.h)
// while held-out data agree. Writes DIR/report.json, DIR/report.md and SVG
// plots. docs/calibration.md describes the method and the figures.
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
