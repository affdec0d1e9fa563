// The outcome of one test run (one test file, one seed): what each
// expectation measured, for the console line and the JUnit report.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "testing/evaluate.h"

namespace chainsim {

struct CheckOutcome {
  std::string expectation;  // as written
  std::string where;        // file:line:column
  CheckResult result;
};

struct TestCaseResult {
  enum class Status { passed, failed, error, interrupted };
  std::string file;          // the test file
  std::string name;          // the test's name
  uint64_t seed = 0;
  Status status = Status::error;
  std::string error;         // Status::error: a malformed file or a run that could not start
  std::vector<CheckOutcome> checks;
  double wall_s = 0;         // the run's wall-clock time
  double sim_s = 0;          // simulated time reached
  std::string trace_sha256;
  std::string run_dir;       // empty once removed (a passed run without --keep)
  std::vector<std::string> artefacts;  // replay.html and the failure picture of a failed run
  double failure_t_s = -1;   // the time the picture shows
};

}  // namespace chainsim
