// `chainsim params PROGRAM [--firmware-dir DIR] [--markdown]`: the parameters
// a module program declares (name, type, range, default, meaning), read from
// the program itself (cosim/program_params.h).
#pragma once

#include "chainsim/command.h"

namespace CLI {
class App;
}

namespace chainsim {

// registers the subcommand on app: what runs it, returning its exit code
Command add_params_command(CLI::App& app);

}  // namespace chainsim
