// Runs of a robot calibration's scenes (scene_runner.h).
#include "analysis/robot_calibration/scene_runner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "analysis/robot_calibration/head_speed.h"
#include "cosim/child_process.h"

namespace chainsim {
namespace {

std::string log_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  std::string t = s.str();
  while (!t.empty() && (t.back() == '\n' || t.back() == '\r' || t.back() == ' ' || t.back() == '\t')) t.pop_back();
  return t;
}

}  // namespace

SceneRunner::SceneRunner(const SceneVariants& scenes, std::vector<std::string> keys, SceneRunOptions options)
    : scenes_(scenes), keys_(std::move(keys)), opt_(std::move(options)) {
  std::error_code ec;
  std::filesystem::remove_all(opt_.work_dir, ec);
  std::filesystem::create_directories(opt_.work_dir, ec);
  if (!std::filesystem::is_directory(opt_.work_dir))
    throw RobotError(opt_.work_dir + ": cannot create the directory of the runs");
}

std::vector<double> SceneRunner::speeds(const KnobSetting& st) {
  const std::string key = setting_key(st);
  if (auto it = cache_.find(key); it != cache_.end()) return it->second;
  const size_t n = keys_.size();
  const std::string dir = opt_.work_dir + "/e" + std::to_string(cache_.size());
  std::filesystem::create_directories(dir);
  std::vector<std::string> scene(n), out(n), log(n);
  for (size_t i = 0; i < n; ++i) {
    scene[i] = dir + "/scene-" + keys_[i] + ".yaml";
    out[i] = dir + "/run-" + keys_[i];
    log[i] = out[i] + ".log";
    std::ofstream f(scene[i]);
    f << scenes_.scene_text(i, st, dir);
    if (!f) throw RobotError(scene[i] + ": cannot write");
  }
  const auto t0 = std::chrono::steady_clock::now();
  // at most `jobs` runs at once; a new one starts when one ends
  std::vector<std::unique_ptr<ChildProcess>> procs(n);
  std::vector<ChildProcess*> running;
  std::vector<size_t> row_of;
  std::vector<double> v(n, NAN);
  size_t next = 0;
  while (next < n || !running.empty()) {
    while (next < n && static_cast<int>(running.size()) < std::max(1, opt_.jobs)) {
      ChildSpec spec;
      spec.program = opt_.chainsim_exe;
      // a candidate effect may be unphysical (a body over 10 m/s): its run is
      // judged by the speed it gives, as before divergence stopped runs
      spec.args = {"run", scene[next], "--out", out[next], "--duration", std::to_string(opt_.duration_s), "--quiet",
                   "--on-divergence", "warn"};
      if (!opt_.firmware_dir.empty()) spec.args.insert(spec.args.end(), {"--firmware-dir", opt_.firmware_dir});
      spec.stdout_path = log[next];
      procs[next] = std::make_unique<ChildProcess>();
      procs[next]->spawn(spec);
      running.push_back(procs[next].get());
      row_of.push_back(next);
      ++next;
    }
    const int done = wait_any(running);
    const size_t i = row_of[done];
    running.erase(running.begin() + done);
    row_of.erase(row_of.begin() + done);
    ++runs_;
    const ExitStatus& st_i = *procs[i]->poll();
    if (!st_i.exited || st_i.code != 0)
      throw RobotError("chainsim run " + scene[i] + " failed (" + st_i.text() + "): " + log_text(log[i]));
    try {
      v[i] = head_speed_of_run(out[i], opt_.window_start_s, pipe_axis(scenes_.scene(i)));
    } catch (const std::exception& e) {
      throw RobotError(std::string("chainsim run ") + scene[i] + ": " + e.what());
    }
  }
  run_wall_s_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // the run directories are large (trace, bus log): keep only the first (base) evaluation's
  if (!cache_.empty())
    for (size_t i = 0; i < n; ++i) std::filesystem::remove_all(out[i]);
  cache_[key] = v;
  return v;
}

}  // namespace chainsim
