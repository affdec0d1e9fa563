// `chainsim test PATH... [--junit OUT.xml] [-j N] [--seeds A..B] [--keep DIR]`:
// runs test files (a scene, edits, expectations) and reports one line per
// test and seed, and JUnit XML for CI. docs/testing.md; the work is done by
// physics-server/testing.
#pragma once

namespace CLI {
class App;
}

namespace chainsim {

// registers the `test` subcommand on `app`; its callback runs the tests
void add_test_command(CLI::App& app);

// after app.parse(): the tests' exit code (0 all passed, 1 an expectation
// failed, 2 a malformed test file or a run that could not start, 130
// interrupted), or -1 when the test subcommand was not given
int test_command_exit_code();

// after a command-line error: true when it was in the test subcommand (whose
// bad input is exit code 2, not 1)
bool test_command_selected();

}  // namespace chainsim
