// `chainsim bench-lockstep`: the price of processes and sockets against
// physics only, for chains of rotation modules or scene files
// (cosim/lockstep_bench.h; docs/benchmarks.md).
#include "chainsim/bench_lockstep_command.h"
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


namespace chainsim {
namespace {

struct LockstepBenchArgs {
  std::vector<int> sizes{2, 8, 32};
  std::vector<std::string> scenes;  // --scene: these scenes instead of the chains
  double duration = -1;             // -1: 5 s for the chains, a scene's own for --scene
  int64_t control_ms = -1;
  int repeat = 3;
  std::string out = "runs/bench-lockstep";
  std::string targets = "native";   // --target: native, pic, or native,pic (both, side by side)
};

// the chain of n rotation modules of the built-in snake scene
Scene bench_chain(int n, const LockstepBenchArgs& a) {
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
  nlohmann::json s;
  try {
    RunReader run(run_dir);
    s = run.summary();
  } catch (const RunReadError&) {
    return h;  // no summary, no PIC figures: the run's own exit is checked where it ran
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

int cmd_bench_lockstep(const LockstepBenchArgs& a) {
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

LockstepBenchArgs g_lockstep_bench_args;

}  // namespace

Command add_bench_lockstep_command(CLI::App& app) {
  auto* bench = app.add_subcommand("bench-lockstep",
                                   "real-time factor of the co-simulation vs physics only, for chains of rotation modules or scene files");
  auto* modules =
      bench->add_option("--modules", g_lockstep_bench_args.sizes, "chain lengths to measure")->expected(1, -1)->capture_default_str();
  auto* scene_files = bench->add_option("--scene", g_lockstep_bench_args.scenes, "measure these scene files instead of the chains")
                          ->expected(1, -1)
                          ->check(CLI::ExistingFile)
                          ->excludes(modules);
  bench->add_option("--duration", g_lockstep_bench_args.duration,
                    "simulated seconds per run (default 5 for the chains, a scene's own for --scene)")
      ->check(CLI::PositiveNumber);
  bench->add_option("--control-ms", g_lockstep_bench_args.control_ms, "firmware control step of the rotation modules (default: theirs)")
      ->check(CLI::Range(1, 1000))  // fw-rotation's declared range of control_ms
      ->excludes(scene_files);
  bench->add_option("--out", g_lockstep_bench_args.out, "where the bench runs are written")->capture_default_str();
  bench->add_option("--target", g_lockstep_bench_args.targets,
                    "the programs native, as the board's .hex in gpsim (pic), or both side by side (native,pic), "
                    "with where a pic run's time goes")
      ->check(CLI::IsMember({"native", "pic", "native,pic"}))
      ->capture_default_str();
  bench->add_option("--repeat", g_lockstep_bench_args.repeat, "runs per figure; the fastest counts")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  bench->footer("Exit codes: 0 every chain length or scene measured; 1 bad options or scene; 2 a bench run failed.");
  return {bench, [] { return cmd_bench_lockstep(g_lockstep_bench_args); }};
}

}  // namespace chainsim
