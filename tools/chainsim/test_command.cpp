#include "chainsim/test_command.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "chainsim/view_command.h"
#include "testing/test_file.h"
#include "testing/test_runner.h"

namespace chainsim {
namespace {

struct TestArgs {
  TestRunOptions run;
  std::string seeds;
};

TestArgs g_args;
int g_exit = -1;
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
  if (cmd_view(png) == 0) files.push_back(png.out);
  else *error = "no picture of the failure (see the message above)";
  return files;
}

int run() {
  if (!g_args.seeds.empty()) {
    try {
      g_args.run.seeds = parse_seed_range(g_args.seeds);
    } catch (const std::invalid_argument& e) {
      std::fprintf(stderr, "chainsim: --seeds %s\n", e.what());
      return kTestExitMalformed;
    }
  }
  return run_tests(g_args.run, view_failure, stdout);
}

}  // namespace

void add_test_command(CLI::App& app) {
  auto* sub = app.add_subcommand("test", "run test files (a scene, edits, expectations); one line per test, JUnit XML "
                                         "for CI (docs/testing.md)");
  sub->add_option("paths", g_args.run.paths, "test files, or folders searched for *.test.yaml")->required();
  sub->add_option("--junit", g_args.run.junit, "write a JUnit XML report here");
  sub->add_option("-j,--jobs", g_args.run.jobs, "runs at once (default 1)")->check(CLI::Range(1, 256));
  sub->add_option("--seeds", g_args.seeds, "run every test with these seeds instead of its own: A..B or one seed");
  sub->add_option("--keep", g_args.run.keep_dir,
                  "keep every run directory under DIR (default: failed runs only, under runs/test-<date>-<time>)");
  sub->add_option("--firmware-dir", g_args.run.firmware_dir,
                  "where to look for programs first (DIR[:DIR...]), before next to chainsim");
  sub->add_option("--module-timeout", g_args.run.module_timeout_s, "wall-clock seconds a module may take to answer")
      ->check(CLI::PositiveNumber);
  sub->callback([] { g_exit = run(); });
  g_sub = sub;
}

int test_command_exit_code() { return g_exit; }

bool test_command_selected() { return g_sub && g_sub->count() > 0; }

}  // namespace chainsim
