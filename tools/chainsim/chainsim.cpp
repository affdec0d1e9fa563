// chainsim: the command line of the co-simulator.
//   chainsim run [SCENE.yaml]        run a scene (default: the built-in one)
//   chainsim view RUN_DIR            replay.html of a run (--png: a picture); run --live: live view
//   chainsim bench                   one servo on a test stand (set-points in, angle and current out)
//   chainsim calibrate               find what the servo model misses against a measurement
//   chainsim test PATH...            run test files (scene + expectations); JUnit XML for CI
//   chainsim bench-lockstep          price of processes and sockets vs physics only
//   chainsim optimize PROBLEM.yaml   design search: GA over chains and parameters (local workers or MPI)
//   chainsim params PROGRAM          the parameters a module program declares
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

#include "chainsim/bench_command.h"
#include "chainsim/calibrate_command.h"
#include "chainsim/test_command.h"
#include "chainsim/bench_search_command.h"
#include "chainsim/optimize_command.h"
#include "chainsim/params_command.h"
#include "chainsim/source_watch.h"
#include "viewer/live_view.h"
#include "cosim/child_process.h"
#include "cosim/lockstep_bench.h"
#include "cosim/lockstep_server.h"
#include "cosim/program_params.h"
#include "cosim/scene_check.h"
#include "output/decimal.h"
#include "output/run_dir.h"
#include "scene/scene.h"
#include "testing/run_compare.h"
#include "testing/run_record.h"
#include "testing/test_runner.h"
#include "chainsim/view_command.h"

extern char** environ;

using namespace chainsim;

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

// a run is whole ticks: a --duration shorter than one tick of the scene
// would silently become one tick. The error, or "" when it is not shorter
// or not given (duration <= 0)
std::string duration_error(double duration, const Scene& scene) {
  if (duration <= 0 || std::llround(duration * 1e6) >= scene.tick_us) return "";
  return "--duration " + fixed_text(duration, 6) + " s is shorter than one tick of the scene (physics.tick_us = " +
         std::to_string(scene.tick_us) + " us)";
}

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
    RunRecord a(dirs[0]), b(dirs[1]);
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
  sigset_t stop_signals, old;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
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

struct BenchArgs {
  std::vector<int> sizes{2, 8, 32};
  std::vector<std::string> scenes;  // --scene: these scenes instead of the chains
  double duration = -1;             // -1: 5 s for the chains, a scene's own for --scene
  int64_t control_ms = -1;
  int repeat = 3;
  std::string out = "runs/bench-lockstep";
  std::string targets = "native";   // --target: native, pic, or native,pic (both, side by side)
};

// the chain of n rotation modules of the built-in snake scene
Scene bench_chain(int n, const BenchArgs& a) {
  Scene scene = default_scene();
  scene.name = "bench-" + std::to_string(n);
  scene.source = "bench-lockstep --modules " + std::to_string(n);
  scene.duration_s = a.duration > 0 ? a.duration : 5.0;
  scene.modules.clear();
  for (int i = 0; i < n; ++i) {
    SceneModule m;
    m.type = "rotation";
    m.firmware = default_firmware("rotation");
    if (a.control_ms > 0) m.params["control_ms"] = static_cast<int32_t>(a.control_ms);
    scene.modules.push_back(m);
  }
  return scene;
}

// the PIC module processes' own figures of a run (summary.json, pic.host):
// gpsim's instruction loop, the pin bridge and the wait for the server, summed
struct PicHost {
  double gpsim_cpu_s = 0, bridge_cpu_s = 0, wait_s = 0, cycles_per_s = 0;
  int chips = 0;
};
PicHost pic_host(const std::string& run_dir) {
  PicHost h;
  std::ifstream f(run_dir + "/summary.json");
  nlohmann::json s;
  try {
    s = nlohmann::json::parse(f);
  } catch (const std::exception&) {
    return h;
  }
  for (const auto& m : s.value("modules", nlohmann::json::array())) {
    if (!m.contains("pic") || !m["pic"].contains("host")) continue;
    const auto& x = m["pic"]["host"];
    h.gpsim_cpu_s += x.value("gpsim_cpu_s", 0.0);
    h.bridge_cpu_s += x.value("bridge_cpu_s", 0.0);
    h.wait_s += x.value("server_wait_s", 0.0);
    h.cycles_per_s += x.value("cycles_per_cpu_s", 0.0);
    ++h.chips;
  }
  if (h.chips) h.cycles_per_s /= h.chips;
  return h;
}

int cmd_bench_lockstep(const BenchArgs& a) {
  std::vector<Target> targets;
  if (a.targets == "native,pic") targets = {Target::Native, Target::Pic};
  else targets = {a.targets == "pic" ? Target::Pic : Target::Native};
  // every scene is loaded and checked before anything runs: a bad one is a bad option
  std::vector<Scene> scenes;
  std::vector<std::string> outs;
  try {
    for (size_t i = 0; i < a.scenes.size(); ++i) {
      Scene s = load_scene_file(a.scenes[i]);
      if (a.duration > 0) s.duration_s = a.duration;
      scenes.push_back(std::move(s));
      // named after the file: a scene's own name may hold anything
      outs.push_back(a.out + "/" + std::to_string(i) + "-" + std::filesystem::path(a.scenes[i]).stem().string());
    }
    if (a.scenes.empty()) {
      for (int n : a.sizes) {
        scenes.push_back(bench_chain(n, a));
        outs.push_back(a.out + "/" + std::to_string(n));
      }
    }
    for (const Scene& s : scenes) {
      if (const std::string e = duration_error(a.duration, s); !e.empty()) throw SceneError(s.source + ": " + e);
      for (Target t : targets) {
        Scene on = s;
        if (targets.size() > 1 || t == Target::Pic) set_target(&on, t);
        check_scene_programs(on, "");
      }
    }
  } catch (const SceneError& e) {
    std::fprintf(stderr, "chainsim: %s\n", e.what());
    return kExitBadInput;
  }
  std::printf("# lockstep price: co-simulation (processes + sockets + firmware) vs physics only\n");
  std::printf("# (the same servo commands replayed into the same world with no processes; best of %d)\n", a.repeat);
  std::printf("# ratio: wall clock; cpu_ratio: the server's CPU against the replay's; modules_cpu_s: the module\n"
              "# processes' CPU in one co-simulation; target pic: every program's .hex in gpsim\n");
  std::printf("%-24s %7s %8s %8s %10s %12s %8s %10s %14s %10s %11s\n", "scene", "target", "modules", "sim_s",
              "cosim_rtf", "physics_rtf", "ratio", "cpu_ratio", "modules_cpu_s", "exch/tick", "same_trace");
  int rc = 0;
  struct PicRow {
    std::string scene;
    double sim_s, wall_native, wall_pic, modules_cpu_s, server_cpu_s;
    PicHost host;
  };
  std::vector<PicRow> pic_rows;
  for (size_t i = 0; i < scenes.size(); ++i) {
    double native_wall = 0;
    for (Target t : targets) {
      Scene scene = scenes[i];
      if (targets.size() > 1 || t == Target::Pic) set_target(&scene, t);
      RunOptions opt;
      opt.out_dir = outs[i] + (targets.size() > 1 ? std::string("-") + target_name(t) : "");
      opt.quiet = true;
      const RunDirCheck dir = prepare_run_dir(opt.out_dir);
      if (!dir.error.empty()) {
        std::fprintf(stderr, "chainsim: %s\n", dir.error.c_str());
        return kExitBadInput;
      }
      LockstepFigures f;
      try {
        f = measure_lockstep(scene, opt, a.repeat);
      } catch (const WorldSetupError& e) {  // the scene asks for a world that cannot be built
        std::fprintf(stderr, "chainsim: %s: %s\n", scene.source.c_str(), e.what());
        return kExitBadInput;
      } catch (const std::exception& e) {
        std::fprintf(stderr, "chainsim: bench run of %s: %s\n", scene.name.c_str(), e.what());
        return kExitInternal;
      }
      if (f.exit_code != kExitOk) {
        std::fprintf(stderr, "chainsim: bench run of %s failed: %s\n", scene.name.c_str(), f.message.c_str());
        rc = kExitModuleFault;
        continue;
      }
      std::printf("%-24s %7s %8zu %8.2f %10.3f %12.3f %8.3f %10.3f %14.3f %10.2f %11s\n", scene.name.c_str(),
                  target_name(t), scene.modules.size(), f.sim_s, f.cosim_rtf(), f.physics_rtf(), f.ratio(),
                  f.cpu_ratio(), f.modules_cpu_s, f.exchanges / f.ticks, f.same_trace ? "yes" : "NO");
      std::fflush(stdout);
      if (t == Target::Native) native_wall = f.cosim_wall_s;
      else
        pic_rows.push_back({scene.name, f.sim_s, native_wall, f.cosim_wall_s, f.modules_cpu_s, f.cosim_cpu_s,
                            pic_host(opt.out_dir)});
    }
  }
  if (!pic_rows.empty()) {
    // where a PIC run's time goes, per simulated second (the last run of each)
    std::printf("\n# target pic: where the time goes, CPU seconds per simulated second; chips = modules + central\n");
    std::printf("%-24s %6s %12s %14s %12s %12s %14s %10s\n", "scene", "chips", "pic/native", "gpsim_cpu", "bridge_cpu",
                "server_cpu", "cycles/cpu_s", "wait/chip");
    for (const PicRow& r : pic_rows)
      std::printf("%-24s %6d %12s %14.3f %12.3f %12.3f %14.3g %10.3f\n", r.scene.c_str(), r.host.chips,
                  r.wall_native > 0 ? (fixed_text(r.wall_pic / r.wall_native, 2) + "x").c_str() : "-",
                  r.host.gpsim_cpu_s / r.sim_s, r.host.bridge_cpu_s / r.sim_s, r.server_cpu_s / r.sim_s,
                  r.host.cycles_per_s, r.host.chips ? r.host.wait_s / r.sim_s / r.host.chips : 0.0);
  }
  return rc;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"chainsim: firmware-in-the-loop co-simulator for chained modular robots"};
  app.require_subcommand(1);

  RunArgs ra;
  auto* run = app.add_subcommand("run", "run a scene: one process per module, lockstep with the ODE world");
  run->add_option("scene", ra.scene, "scene file (YAML); default: the built-in snake in open air")
      ->check(CLI::ExistingFile);
  run->add_option("--out,-o", ra.out, "run directory to write (default: runs/<scene>-<date>-<time>)");
  run->add_option("--duration", ra.duration, "simulated seconds (default: the scene's)")->check(CLI::PositiveNumber);
  run->add_option("--seed", ra.seed, "random seed (default: the scene's)")->check(CLI::NonNegativeNumber);
  run->add_option("--on-module-fault", ra.fault, "stop the run, or go on with the module powered off")
      ->check(CLI::IsMember({"stop", "limp"}))
      ->capture_default_str();
  run->add_option("--on-divergence", ra.divergence,
                  "physics diverged (a body faster than 10 m/s or 1000 rad/s, farther than 10 km, or not "
                  "finite): stop the run (exit 4), or warn once and go on (not finite: always stops)")
      ->check(CLI::IsMember({"stop", "warn"}))
      ->capture_default_str();
  run->add_option("--module-timeout", ra.timeout, "wall-clock seconds a module may take to answer")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  run->add_option("--attach", ra.attach,
                  "do not spawn this module (index; the central control is the last index): wait for it "
                  "to be started by hand, e.g. under gdb")
      ->expected(0, -1);
  run->add_option("--firmware-dir", ra.firmware_dir,
                  "where to look for programs first (DIR[:DIR...], e.g. your own build), then next to chainsim");
  run->add_option("--target", ra.target,
                  "run every module and the central control as native programs, or as the board's own .hex "
                  "in gpsim (pic; docs/pic-in-the-loop.md), whatever the scene's target says")
      ->check(CLI::IsMember({"native", "pic"}));
  run->add_option("--compare", ra.compare,
                  "run the scene on two targets (native,pic) into OUT/native and OUT/pic, and report where "
                  "each endpoint's log lines, I2C frames, Sout edges, set-points, faults first differ, and how "
                  "far the runs drift apart (OUT/compare.txt, compare.json)");
  run->add_option("--on-overrun", ra.overrun,
                  "a PIC program's step over the scene's pic.cpu_budget_us: a fault (stop), or a warning in "
                  "the module's .out and summary.json (warn)")
      ->check(CLI::IsMember({"stop", "warn"}))
      ->capture_default_str();
  run->add_flag("--quiet,-q", ra.quiet, "print only errors");
  run->add_flag("--check", ra.check,
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
  run->add_flag("--live", ra.live, "show the run as it happens: serve the viewer on 127.0.0.1 (URL printed)");
  run->add_flag("--watch", ra.watch,
                "run, then rebuild the programs (--firmware-dir's CMake build folders, or chainsim's own) and run "
                "again whenever a source or the scene changes; the live page reloads for each run (docs/firmware.md)");
  run->add_option("--live-port", ra.live_port, "port of the live view (default 0: any free port)")
      ->check(CLI::Range(0, 65535));
  run->add_option("--live-wait", ra.live_wait, "seconds to wait for a page to connect before the run starts")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  run->add_option("--progress-every", ra.progress_every,
                  "wall-clock seconds between progress reports on stderr (default: 1 on a terminal, where one "
                  "line is rewritten; 10 otherwise, a new line each time, e.g. in a CI log)")
      ->check(CLI::PositiveNumber);

  ViewArgs va;
  auto* view = app.add_subcommand("view", "write RUN_DIR/replay.html, a replay of a run that opens from disk "
                                          "(or, with --png, a picture of the scene at a time)");
  view->add_option("run_dir", va.run_dir, "run directory (of chainsim run --out)")->required()
      ->check(CLI::ExistingDirectory);
  view->add_option("other_run_dir", va.other_dir,
                   "a second run directory: RUN_DIR/compare.html shows the two side by side, plots overlaid, their "
                   "summaries' differences and where they first differ (docs/viewer.md)")
      ->check(CLI::ExistingDirectory);
  view->add_option("--png", va.png_time, "render a PNG of the scene at this time (s) with headless Chromium")
      ->check(CLI::NonNegativeNumber);
  view->add_option("--out,-o", va.out, "file to write (default RUN_DIR/replay.html; required with --png)");
  view->add_option("--size", va.size, "picture size WIDTHxHEIGHT (default 960x540)");
  view->add_option("--page-options", va.hash, "more options for the pictured page, e.g. follow=0");

  BenchArgs ba;
  auto* bench = app.add_subcommand("bench-lockstep",
                                   "real-time factor of the co-simulation vs physics only, for chains of rotation modules or scene files");
  auto* modules =
      bench->add_option("--modules", ba.sizes, "chain lengths to measure")->expected(1, -1)->capture_default_str();
  auto* scene_files = bench->add_option("--scene", ba.scenes, "measure these scene files instead of the chains")
                          ->expected(1, -1)
                          ->check(CLI::ExistingFile)
                          ->excludes(modules);
  bench->add_option("--duration", ba.duration,
                    "simulated seconds per run (default 5 for the chains, a scene's own for --scene)")
      ->check(CLI::PositiveNumber);
  bench->add_option("--control-ms", ba.control_ms, "firmware control step of the rotation modules (default: theirs)")
      ->check(CLI::Range(1, 1000))  // fw-rotation's declared range of control_ms
      ->excludes(scene_files);
  bench->add_option("--out", ba.out, "where the bench runs are written")->capture_default_str();
  bench->add_option("--target", ba.targets,
                    "the programs native, as the board's .hex in gpsim (pic), or both side by side (native,pic), "
                    "with where a pic run's time goes")
      ->check(CLI::IsMember({"native", "pic", "native,pic"}))
      ->capture_default_str();
  bench->add_option("--repeat", ba.repeat, "runs per figure; the fastest counts")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  bench->footer("Exit codes: 0 every chain length or scene measured; 1 bad options or scene; 2 a bench run failed.");

  add_bench_command(app);
  add_calibrate_command(app);
  add_test_command(app);
  add_optimize_command(app);
  add_bench_search_command(app);
  add_params_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);  // prints help, or the error and a hint
    return rc == 0 ? 0 : test_command_selected() ? kTestExitMalformed : kExitBadInput;
  }
  if (const int rc = bench_command_exit_code(); rc >= 0) return rc;
  if (const int rc = calibrate_command_exit_code(); rc >= 0) return rc;
  if (const int rc = test_command_exit_code(); rc >= 0) return rc;
  if (const int rc = optimize_command_exit_code(); rc >= 0) return rc;
  if (const int rc = bench_search_command_exit_code(); rc >= 0) return rc;
  if (const int rc = params_command_exit_code(); rc >= 0) return rc;
  if (*run) return cmd_run(ra);
  if (*view) return cmd_view(va);
  if (*bench) return cmd_bench_lockstep(ba);
  return kExitBadInput;
}
