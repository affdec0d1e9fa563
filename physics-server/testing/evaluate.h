// Measures one expectation in a finished run directory (docs/testing.md).
#pragma once

#include <limits>
#include <stdexcept>
#include <string>

#include "testing/expectation.h"

namespace chainsim {

class RunReader;

// the expectation names something no run of this scene has: an unknown
// summary path, trace column, motion metric or module; a mistake in the test
// file, not a failed expectation
struct EvaluationError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct CheckResult {
  bool pass = false;
  std::string measured;  // what was measured, e.g. "0.2513", "at 5.812 s", "never"
  double value = std::numeric_limits<double>::quiet_NaN();  // the measured number, when there is one
  double t_s = -1;       // the simulated time that shows the outcome (for a picture of a failure)
};

// measures e in run; throws EvaluationError, or RunReadError when a file
// of the run directory is missing or broken, or RunReadStopped when the
// run record's stop check says so
CheckResult evaluate(const Expectation& e, RunReader& run);

}  // namespace chainsim
