#include "chainsim/test_command.h"

#include <CLI/CLI.hpp>

#include <csignal>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "chainsim/view_command.h"
#include "cosim/run_options.h"
#include "testing/run_compare.h"
#include "testing/test_file.h"
#include "testing/test_runner.h"

namespace chainsim {
namespace {

struct TestArgs {
  TestRunOptions run;
  std::string seeds;
  std::string target, compare, overrun = "stop";
};

TestArgs g_test_args;
const CLI::App* g_sub = nullptr;

// a failed run: replay.html and a picture at the failure time (chainsim view)
std::vector<std::string> view_failure(const std::string& dir, double t_s, std::string* error) {
  std::vector<std::string> files;
  ViewArgs page;
  page.run_dir = dir;
  if (cmd_view(page) == 0) files.push_back(dir + "/replay.html");
  else *error = "no replay.html (see the message above)";
  if (find_chromium().empty()) {
    *error = "no picture of the failure: Chromium is not installed (apt-get install chromium; tools/setup.sh does)";
    return files;
  }
  char name[48];
  std::snprintf(name, sizeof name, "/failure-t%.3f.png", t_s);
  ViewArgs png = page;
  png.png_time = t_s;
  png.out = dir + name;
  const int rc = cmd_view(png);
  if (rc == 0) files.push_back(png.out);
  else *error = "no picture of the failure (see the message above)";
  // Ctrl-C or SIGTERM while Chromium drew: cmd_view took it (and ended
  // Chromium); chainsim test's own handler, in place again, is told too
  if (rc == kExitInterrupted) raise(SIGINT);
  return files;
}

int run_test_command() {
  if (!g_test_args.seeds.empty()) {
    try {
      g_test_args.run.seeds = parse_seed_range(g_test_args.seeds);
    } catch (const std::invalid_argument& e) {
      std::fprintf(stderr, "chainsim: --seeds %s\n", e.what());
      return kTestExitMalformed;
    }
  }
  if (!g_test_args.target.empty()) g_test_args.run.target = g_test_args.target == "pic" ? Target::Pic : Target::Native;
  if (!g_test_args.compare.empty()) {
    std::string error;
    g_test_args.run.compare = parse_compare_targets(g_test_args.compare, &error);
    if (g_test_args.run.compare.empty() || !g_test_args.target.empty()) {
      std::fprintf(stderr, "chainsim: %s\n", error.empty() ? "--compare runs every test on both targets: not with --target" : error.c_str());
      return kTestExitMalformed;
    }
  }
  g_test_args.run.overrun_warn = g_test_args.overrun == "warn";
  return run_tests(g_test_args.run, view_failure, stdout);
}

}  // namespace

Command add_test_command(CLI::App& app) {
  auto* sub = app.add_subcommand("test", "run test files (a scene, edits, expectations); one line per test, JUnit XML "
                                         "for CI (docs/testing.md)");
  sub->add_option("paths", g_test_args.run.paths, "test files, or folders searched for *.test.yaml")->required();
  sub->add_option("--junit", g_test_args.run.junit, "write a JUnit XML report here");
  sub->add_option("-j,--jobs", g_test_args.run.jobs, "runs at once (default 1)")->check(CLI::Range(1, 256));
  sub->add_option("--seeds", g_test_args.seeds, "run every test with these seeds instead of its own: A..B or one seed");
  sub->add_option("--keep", g_test_args.run.keep_dir,
                  "keep every run directory under DIR (default: failed runs only, under runs/test-<date>-<time>)");
  sub->add_option("--firmware-dir", g_test_args.run.firmware_dir,
                  "where to look for programs first (DIR[:DIR...]), before next to chainsim");
  sub->add_option("--module-timeout", g_test_args.run.module_timeout_s, "wall-clock seconds a module may take to answer")
      ->check(CLI::PositiveNumber);
  sub->add_option("--target", g_test_args.target,
                  "every run's programs native, or the board's own .hex in gpsim (pic), whatever the scenes say")
      ->check(CLI::IsMember({"native", "pic"}));
  sub->add_option("--compare", g_test_args.compare,
                  "every test and seed on both targets (native,pic): each run's expectations, then where the two "
                  "runs first differ (a COMPARE line, <runs>/<name>-seed<S>-compare.txt)");
  sub->add_option("--on-overrun", g_test_args.overrun, "a PIC program's step over its CPU budget: stop (a fault) or warn")
      ->check(CLI::IsMember({"stop", "warn"}))
      ->capture_default_str();
  g_sub = sub;
  return {sub, [] { return run_test_command(); }};
}

bool test_command_selected() { return g_sub && g_sub->count() > 0; }

}  // namespace chainsim
