// A subcommand of chainsim: its options, registered on the command line, and
// what runs it once the command line is parsed, returning the exit code.
// Each subcommand lives in its own file (tools/chainsim/<name>_command.cpp)
// with an add_<name>_command(app) that returns its Command; chainsim.cpp only
// registers them and runs the one given.
#pragma once

#include <functional>

namespace CLI {
class App;
}

namespace chainsim {

struct Command {
  CLI::App* app = nullptr;   // the subcommand's parser (app->parsed() when it was given)
  std::function<int()> run;  // runs it; the process's exit code
};

}  // namespace chainsim
