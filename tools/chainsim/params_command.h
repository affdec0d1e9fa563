// `chainsim params PROGRAM [--firmware-dir DIR] [--markdown]`: the parameters
// a module program declares (name, type, range, default, meaning), read from
// the program itself (cosim/program_params.h).
#pragma once

namespace CLI {
class App;
}

namespace chainsim {

// registers the `params` subcommand on `app`
void add_params_command(CLI::App& app);

// after app.parse(): 0 listed, 1 the program is missing or lists no
// parameters; -1 when the subcommand was not given
int params_command_exit_code();

}  // namespace chainsim
