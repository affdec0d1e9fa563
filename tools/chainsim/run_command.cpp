// `chainsim run [SCENE.yaml]`: a scene run in lockstep, one process per
// module (cosim/lockstep_server.h); --compare on two targets, --live, --watch.
#include "chainsim/run_command.h"

#include <CLI/CLI.hpp>

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "chainsim/source_watch.h"
#include "viewer/live_view.h"
#include "cosim/child_process.h"
#include "cosim/lockstep_bench.h"
#include "cosim/lockstep_server.h"
#include "cosim/program_params.h"
#include "cosim/scene_check.h"
#include "text/number_text.h"
#include "output/run_dir.h"
#include "physics/world.h"  // WorldSetupError
#include "scene/scene.h"
#include "testing/run_compare.h"
#include "output/run_reader.h"
#include "testing/test_runner.h"


extern char** environ;

namespace chainsim {
namespace {

std::string default_out_dir(const Scene& s) {
  char stamp[32];
  const std::time_t now = std::time(nullptr);
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", std::localtime(&now));
  return "runs/" + s.name + "-" + stamp;
}

struct RunArgs {
  std::string scene;
  std::string out;
  double duration = -1;
  int64_t seed = -1;
  std::string fault = "stop";
  std::string divergence = "stop";
  double timeout = 10.0;
  std::vector<int> attach;
  std::string firmware_dir;
  std::string target;      // --target: every endpoint on native or pic
  std::string compare;     // --compare A,B: the scene on both targets, compared
  std::string overrun = "stop";
  bool quiet = false;
  bool check = false;      // --check: load and check, run nothing
  bool live = false;       // --live: serve the live view while running
  bool watch = false;      // --watch: rebuild the programs and rerun when a source changes
  int live_port = 0;
  double live_wait = 0;
  double progress_every = 0;  // 0: 1 s on a terminal, 10 s otherwise
};


// the scene on both targets into OUT/<target>, then the comparison into
// OUT/compare.txt and OUT/compare.json (testing/run_compare.h)
int run_compare(const Scene& scene, RunOptions opt, const std::vector<Target>& targets) {
  const std::string base = opt.out_dir;
  int code = kExitOk;
  std::vector<std::string> dirs;
  for (Target t : targets) {
    Scene s = scene;
    set_target(&s, t);
    opt.out_dir = base + "/" + target_name(t);
    dirs.push_back(opt.out_dir);
    const RunDirCheck dir = prepare_run_dir(opt.out_dir);
    if (!dir.error.empty()) {
      std::fprintf(stderr, "chainsim: %s\n", dir.error.c_str());
      return kExitBadInput;
    }
    say(opt, std::string("running ") + s.name + " with every program " +
                 (t == Target::Pic ? "on the PIC (gpsim)" : "native") + " into " + opt.out_dir);
    RunResult r;
    try {
      r = run_scene(s, opt);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "chainsim: %s\n", e.what());
      return kExitInternal;
    }
    if (r.exit_code != kExitOk) {
      std::fprintf(stderr, "chainsim: the %s run stopped: %s\n", target_name(t), r.message.c_str());
      if (code == kExitOk) code = r.exit_code;
    }
  }
  try {
    RunReader a(dirs[0]), b(dirs[1]);
    const CompareReport report = compare_runs(a, b, target_name(targets[0]), target_name(targets[1]));
    const std::string text = compare_text(report);
    std::ofstream(base + "/compare.txt") << text;
    std::ofstream(base + "/compare.json") << compare_json(report).dump(1) << "\n";
    std::printf("%s", text.c_str());
    say(opt, "comparison: " + base + "/compare.txt, compare.json");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "chainsim: cannot compare the runs: %s\n", e.what());
    return code != kExitOk ? code : kExitInternal;
  }
  return code;
}

// one run of `chainsim run`; shared_live: the watch loop's live view (else
// --live starts one for this run)
int run_once(const RunArgs& a, LiveView* shared_live) {
  Scene scene;
  try {
    scene = a.scene.empty() ? default_scene() : load_scene_file(a.scene);
  } catch (const SceneError& e) {
    std::fprintf(stderr, "chainsim: %s\n", e.what());
    return kExitBadInput;
  }
  if (a.duration > 0) scene.duration_s = a.duration;
  if (a.seed >= 0) scene.world.seed = static_cast<uint64_t>(a.seed);
  if (!a.target.empty()) set_target(&scene, a.target == "pic" ? Target::Pic : Target::Native);
  std::vector<Target> compare;
  if (!a.compare.empty()) {
    std::string error;
    compare = parse_compare_targets(a.compare, &error);
    if (compare.empty() || !a.target.empty() || a.live || !a.attach.empty()) {
      std::fprintf(stderr, "chainsim: %s\n",
                   !error.empty() ? error.c_str() : "--compare runs the scene twice: not with --target, --live or --attach");
      return kExitBadInput;
    }
  }
  if (const std::string e = duration_error(a.duration, scene); !e.empty()) {
    std::fprintf(stderr, "chainsim: %s\n", e.c_str());
    return kExitBadInput;
  }
  for (int i : a.attach) {
    if (i < 0 || i > static_cast<int>(scene.modules.size())) {
      std::fprintf(stderr, "chainsim: --attach %d: the scene has modules 0..%zu and the central control %zu\n", i,
                   scene.modules.size() - 1, scene.modules.size());
      return kExitBadInput;
    }
  }
  try {
    // programs found, the parameters each is given declared and in range
    // (a program given parameters is run once, with --chainsim-params, for its list)
    if (compare.empty()) check_scene_programs(scene, a.firmware_dir);
    for (Target t : compare) {
      Scene s = scene;
      set_target(&s, t);
      check_scene_programs(s, a.firmware_dir);
    }
  } catch (const SceneError& e) {
    std::fprintf(stderr, "chainsim: %s\n", e.what());
    return kExitBadInput;
  }
  if (a.check) {
    const SceneCheck c = check_scene(scene, a.firmware_dir);
    if (c.exit_code != kExitOk) {
      std::fprintf(stderr, "chainsim: %s\n", c.message.c_str());
      return c.exit_code;
    }
    if (!a.quiet) std::printf("%s\n", c.message.c_str());
    return kExitOk;
  }
  RunOptions opt;
  opt.out_dir = a.out.empty() ? default_out_dir(scene) : a.out;
  opt.on_fault = a.fault == "limp" ? FaultMode::Limp : FaultMode::Stop;
  opt.on_divergence = a.divergence == "warn" ? DivergenceMode::Warn : DivergenceMode::Stop;
  opt.module_timeout_s = a.timeout;
  opt.firmware_dir = a.firmware_dir;
  opt.overrun_warn = a.overrun == "warn";
  opt.quiet = a.quiet;
  opt.progress = !a.quiet;
  opt.progress_terminal = isatty(2);
  opt.progress_every_s = a.progress_every > 0 ? a.progress_every : opt.progress_terminal ? 1.0 : 10.0;
  if (!compare.empty()) return run_compare(scene, opt, compare);
  // checked before any module starts: a bad --out is a bad option, not an internal error
  const RunDirCheck dir = prepare_run_dir(opt.out_dir);
  if (!dir.error.empty()) {
    std::fprintf(stderr, "chainsim: %s\n", dir.error.c_str());
    return kExitBadInput;
  }
  if (dir.had_run) say(opt, "--out '" + opt.out_dir + "' already holds a run: its files are replaced");
  opt.attach.insert(a.attach.begin(), a.attach.end());
  std::unique_ptr<LiveView> own_live;
  if (!shared_live && a.live && !(own_live = start_live_view(scene.name, a.live_port, a.live_wait)))
    return kExitBadInput;
  LiveView* live = shared_live ? shared_live : own_live.get();
  opt.observer = live;
  RunResult r;
  try {
    r = run_scene(scene, opt);
  } catch (const WorldSetupError& e) {  // the scene asks for a world that cannot be built
    std::fprintf(stderr, "chainsim: %s: %s\n", scene.source.c_str(), e.what());
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "chainsim: %s\n", e.what());
    return kExitInternal;
  }
  if (r.exit_code != kExitOk) std::fprintf(stderr, "chainsim: run stopped: %s\n", r.message.c_str());
  if (!a.quiet) {
    const auto& s = r.summary;
    std::fprintf(stderr,
                 "chainsim: %s: %.3f s simulated in %.3f s (%.2fx real time); chain moved %.4f m (%.4f m/s)\n"
                 "chainsim: run directory: %s\n",
                 scene.name.c_str(), s["sim_time_s"].get<double>(), s["wall_time_s"].get<double>(),
                 s["real_time_factor"].get<double>(), s["chain"]["distance_m"].get<double>(),
                 s["chain"]["speed_m_s"].get<double>(), opt.out_dir.c_str());
  }
  if (own_live) own_live->wait_until_seen(3.0);
  return r.exit_code;
}

// builds one of --watch's builds, its output on the terminal; true when it built
bool build_programs(const WatchedBuild& b) {
  const std::vector<std::string> argv = build_command(b);
  std::string line = "chainsim: --watch: building:";
  for (const std::string& x : argv) line += " " + x;
  std::fprintf(stderr, "%s\n", line.c_str());
  std::vector<char*> args;
  for (const std::string& x : argv) args.push_back(const_cast<char*>(x.c_str()));
  args.push_back(nullptr);
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  sigset_t none;
  sigemptyset(&none);
  posix_spawnattr_setsigmask(&attr, &none);  // Ctrl-C reaches the build too
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addclosefrom_np(&fa, 3);  // not the live view's sockets
  pid_t pid = 0;
  const int e = posix_spawnp(&pid, "cmake", &fa, &attr, args.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  posix_spawnattr_destroy(&attr);
  if (e != 0) {
    std::fprintf(stderr, "chainsim: --watch: cannot start cmake: %s\n", std::strerror(e));
    return false;
  }
  int st = 0;
  pid_t w;
  while ((w = waitpid(pid, &st, 0)) < 0 && errno == EINTR) {
  }
  return w == pid && WIFEXITED(st) && WEXITSTATUS(st) == 0;
}

// `chainsim run --watch`: run, then on every change of a program's sources
// rebuild it and run again, the open live page reloading for each run; on a
// change of the scene file, run again. Ends with 130 on Ctrl-C or SIGTERM.
int run_watch(const RunArgs& a) {
  if (!a.compare.empty() || !a.attach.empty() || a.check) {
    std::fprintf(stderr, "chainsim: --watch reruns one scene: not with --compare, --attach or --check\n");
    return kExitBadInput;
  }
  std::vector<WatchedBuild> builds;
  try {
    builds = watched_builds(a.firmware_dir, executable_dir());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "chainsim: %s\n", e.what());
    return kExitBadInput;
  }
  // SIGINT and SIGTERM blocked in every thread but while a run goes (the live
  // view's thread among them): while waiting they are read by the watcher
  const sigset_t stop_signals = stop_signal_set();
  sigset_t old;
  sigprocmask(SIG_BLOCK, &stop_signals, &old);
  std::unique_ptr<SourceWatch> watch;
  std::unique_ptr<LiveView> live;
  try {
    watch = std::make_unique<SourceWatch>(builds, a.scene);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "chainsim: %s\n", e.what());
    return kExitBadInput;
  }
  if (!(live = start_live_view(a.scene.empty() ? "default" : a.scene, a.live_port, a.live_wait))) return kExitBadInput;
  std::string what;
  for (const WatchedBuild& b : builds) what += (what.empty() ? "" : ", ") + b.source_dir;
  std::fprintf(stderr, "chainsim: --watch: %zu folders of %s%s%s; Ctrl-C ends\n", watch->folders(),
               what.empty() ? "" : what.c_str(), what.empty() ? "" : " and ",
               a.scene.empty() ? "no scene file" : a.scene.c_str());
  bool built = true;
  for (int round = 1;; ++round) {
    if (built) {
      sigprocmask(SIG_SETMASK, &old, nullptr);
      const int code = run_once(a, live.get());
      sigprocmask(SIG_BLOCK, &stop_signals, nullptr);
      if (code == kExitInterrupted) return code;
      std::fprintf(stderr, "chainsim: --watch: run %d ended (exit %d); waiting for a change\n", round, code);
    }
    const SourceWatch::Change c = watch->wait();
    if (c.interrupted) {
      std::fprintf(stderr, "chainsim: --watch: interrupted\n");
      return kExitInterrupted;
    }
    std::fprintf(stderr, "chainsim: --watch: %s changed\n", c.first.c_str());
    built = true;
    if (c.sources)
      for (const WatchedBuild& b : builds)
        if (!build_programs(b)) {
          built = false;
          break;
        }
    // Ctrl-C during the build reached cmake (its own process group member) and
    // is pending here: end, rather than have it delivered once unblocked
    if (watch->take_signal()) {
      std::fprintf(stderr, "chainsim: --watch: interrupted\n");
      return kExitInterrupted;
    }
    if (!built)
      std::fprintf(stderr, "chainsim: --watch: the build failed; the last programs stay, waiting for a change\n");
    if (built) live->restart(c.sources ? "rebuilt: " + c.first : "changed: " + c.first);
  }
}

int cmd_run(const RunArgs& a) { return a.watch ? run_watch(a) : run_once(a, nullptr); }

RunArgs g_run_args;

}  // namespace

// a run is whole ticks: a --duration shorter than one tick of the scene
// would silently become one tick. The error, or "" when it is not shorter
// or not given (duration <= 0)
std::string duration_error(double duration, const Scene& scene) {
  if (duration <= 0 || std::llround(duration * 1e6) >= scene.tick_us) return "";
  return "--duration " + fixed_text(duration, 6) + " s is shorter than one tick of the scene (physics.tick_us = " +
         std::to_string(scene.tick_us) + " us)";
}

Command add_run_command(CLI::App& app) {
  auto* run = app.add_subcommand("run", "run a scene: one process per module, lockstep with the ODE world");
  run->add_option("scene", g_run_args.scene, "scene file (YAML); default: the built-in snake in open air")
      ->check(CLI::ExistingFile);
  run->add_option("--out,-o", g_run_args.out, "run directory to write (default: runs/<scene>-<date>-<time>)");
  run->add_option("--duration", g_run_args.duration, "simulated seconds (default: the scene's)")->check(CLI::PositiveNumber);
  run->add_option("--seed", g_run_args.seed, "random seed (default: the scene's)")->check(CLI::NonNegativeNumber);
  run->add_option("--on-module-fault", g_run_args.fault, "stop the run, or go on with the module powered off")
      ->check(CLI::IsMember({"stop", "limp"}))
      ->capture_default_str();
  run->add_option("--on-divergence", g_run_args.divergence,
                  "physics diverged (a body faster than 10 m/s or 1000 rad/s, farther than 10 km, or not "
                  "finite): stop the run (exit 4), or warn once and go on (not finite: always stops)")
      ->check(CLI::IsMember({"stop", "warn"}))
      ->capture_default_str();
  run->add_option("--module-timeout", g_run_args.timeout, "wall-clock seconds a module may take to answer")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  run->add_option("--attach", g_run_args.attach,
                  "do not spawn this module (index; the central control is the last index): wait for it "
                  "to be started by hand, e.g. under gdb")
      ->expected(0, -1);
  run->add_option("--firmware-dir", g_run_args.firmware_dir,
                  "where to look for programs first (DIR[:DIR...], e.g. your own build), then next to chainsim");
  run->add_option("--target", g_run_args.target,
                  "run every module and the central control as native programs, or as the board's own .hex "
                  "in gpsim (pic; docs/pic-in-the-loop.md), whatever the scene's target says")
      ->check(CLI::IsMember({"native", "pic"}));
  run->add_option("--compare", g_run_args.compare,
                  "run the scene on two targets (native,pic) into OUT/native and OUT/pic, and report where "
                  "each endpoint's log lines, I2C frames, Sout edges, set-points, faults first differ, and how "
                  "far the runs drift apart (OUT/compare.txt, compare.json)");
  run->add_option("--on-overrun", g_run_args.overrun,
                  "a PIC program's step over the scene's pic.cpu_budget_us: a fault (stop), or a warning in "
                  "the module's .out and summary.json (warn)")
      ->check(CLI::IsMember({"stop", "warn"}))
      ->capture_default_str();
  run->add_flag("--quiet,-q", g_run_args.quiet, "print only errors");
  run->add_flag("--check", g_run_args.check,
                "check the scene and run nothing: load it and its module and mesh files, build the world, find "
                "every program and check the parameters the scene gives it against what it declares (a program "
                "given parameters is run once to list them); start no module and write no file (exit 0, or 1 "
                "naming file:line:column or the program)");
  run->footer("Exit codes: 0 finished; 1 bad scene, module file or options (file:line:column, or the --out path; "
              "a parameter the program does not declare or out of its range); "
              "2 a module or the central control faulted (crash, exit, hang, bad frame); 3 internal error; 4 the physics diverged "
              "(--on-divergence); 5 an output file could not be written (disk full); 6 a module never answered "
              "discovery (no I2C address at the scene's central.discovery_s, default 1 s, unless it may_stay_silent); "
              "130 interrupted. See docs/reliability.md.");
  run->add_flag("--live", g_run_args.live, "show the run as it happens: serve the viewer on 127.0.0.1 (URL printed)");
  run->add_flag("--watch", g_run_args.watch,
                "run, then rebuild the programs (--firmware-dir's CMake build folders, or chainsim's own) and run "
                "again whenever a source or the scene changes; the live page reloads for each run (docs/firmware.md)");
  run->add_option("--live-port", g_run_args.live_port, "port of the live view (default 0: any free port)")
      ->check(CLI::Range(0, 65535));
  run->add_option("--live-wait", g_run_args.live_wait, "seconds to wait for a page to connect before the run starts")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  run->add_option("--progress-every", g_run_args.progress_every,
                  "wall-clock seconds between progress reports on stderr (default: 1 on a terminal, where one "
                  "line is rewritten; 10 otherwise, a new line each time, e.g. in a CI log)")
      ->check(CLI::PositiveNumber);
  return {run, [] { return cmd_run(g_run_args); }};
}

}  // namespace chainsim
