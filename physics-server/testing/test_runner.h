// `chainsim test`: runs test files (docs/testing.md). Every test and seed is
// a normal run (run_scene, in a process of its own forked from this one, so
// that several run at once and none shares ODE's global state), measured
// afterwards from its run directory.
#pragma once

#include <cstdint>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "scene/scene.h"
#include "testing/test_result.h"

namespace chainsim {

// exit codes of `chainsim test`
constexpr int kTestExitPassed = 0;
constexpr int kTestExitFailed = 1;     // an expectation failed
constexpr int kTestExitMalformed = 2;  // a malformed test file, or a run that could not start

struct TestRunOptions {
  std::vector<std::string> paths;   // test files, or folders searched for *.test.yaml
  std::string junit;                // JUnit XML to write ("" = none)
  int jobs = 1;                     // runs at once
  std::optional<std::vector<uint64_t>> seeds;  // replaces every test's seeds
  std::string keep_dir;             // keep every run here; "" = runs/test-<date>-<time>, failed runs only
  std::string firmware_dir;         // as chainsim run --firmware-dir
  double module_timeout_s = 10.0;
  bool overrun_warn = false;        // as chainsim run --on-overrun=warn
  std::optional<Target> target;     // every endpoint of every run on this target (--target)
  // every test and seed on both targets (--compare native,pic): two results,
  // the expectations held by each, and the comparison of the two runs
  // (testing/run_compare.h) in <root>/<name>-seed<S>-compare.txt
  std::vector<Target> compare;
};

// writes a failed run's replay.html and a picture at t_s into run_dir;
// returns the files written (an error goes to *error)
using FailureViewer =
    std::function<std::vector<std::string>(const std::string& run_dir, double t_s, std::string* error)>;

// runs the tests, printing one line per test and seed to out; returns a
// kTestExit* code (or 130 when interrupted)
int run_tests(const TestRunOptions& options, const FailureViewer& viewer, FILE* out);

// the console line of one result (no newline)
std::string result_line(const TestCaseResult& r);

}  // namespace chainsim
