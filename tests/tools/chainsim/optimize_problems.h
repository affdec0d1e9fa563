// The reduced problems of the `chainsim optimize` tests, written to a test's
// directory: a snake of three rotation modules in open air for 0.4 s.
#pragma once

#include <string>

namespace optimize_test {

// writes base.yaml and the problem into dir; returns the problem's path.
//  "gait":  amplitude x omega x phase, 27 individuals; maximize the chain's x distance
//  "gait-auto": the same with trials: auto; "gait-exact": and the exact solver (no seed changes a run)
//  "stop", "stop-off": gait with a constraint that the tail gets 1 cm on by 0.3 s, with and
//           without the early stop the constraint brings
//  "fault": module 1 runs fw-test-misbehave; mode 0 (quiet) or 2 (SIGSEGV at 150 ms) x amplitude
std::string write_problem(const std::string& dir, const std::string& which);

// history.csv without its last column (wall_s, the only one that may differ)
std::string history_without_wall(const std::string& path);

}  // namespace optimize_test
