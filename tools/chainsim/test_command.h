// `chainsim test PATH... [--junit OUT.xml] [-j N] [--seeds A..B] [--keep DIR]`:
// runs test files (a scene, edits, expectations) and reports one line per
// test and seed, and JUnit XML for CI. docs/testing.md; the work is done by
// physics-server/testing.
#pragma once

#include "chainsim/command.h"

namespace CLI {
class App;
}

namespace chainsim {

// registers the subcommand on app: what runs it, returning its exit code
Command add_test_command(CLI::App& app);

// after a command-line error: true when it was in the test subcommand (whose
// bad input is exit code 2, not 1)
bool test_command_selected();

}  // namespace chainsim
