#include "optimize/evaluation.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <regex>
#include <sstream>
#include <thread>

#include "cosim/run_options.h"
#include "optimize/individual_scene.h"
#include "optimize/problem.h"
#include "optimize/run_outcome.h"
#include "scene/scene.h"
#include "physics/splitmix64.h"

namespace chainsim {

namespace {

nlohmann::json number_json(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return v;
}

double number_from_json(const nlohmann::json& j) {
  if (j.is_string()) {
    const std::string s = j.get<std::string>();
    if (s == "inf") return std::numeric_limits<double>::infinity();
    if (s == "-inf") return -std::numeric_limits<double>::infinity();
    if (s == "nan") return std::numeric_limits<double>::quiet_NaN();
    throw nlohmann::json::type_error::create(302, "not a number: " + s, &j);
  }
  return j.get<double>();
}

bool same_number(double a, double b) { return (std::isnan(a) && std::isnan(b)) || a == b; }

std::string last_lines(const std::string& path, size_t max_chars) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  std::string t = s.str();
  while (!t.empty() && (t.back() == '\n' || t.back() == ' ')) t.pop_back();
  if (t.size() > max_chars) t = "..." + t.substr(t.size() - max_chars);
  return t;
}

}  // namespace

bool EvalResult::operator==(const EvalResult& o) const {
  if (!same_number(fitness, o.fitness) || failed != o.failed || why != o.why || wall_s != o.wall_s) return false;
  if (infra != o.infra) return false;
  if (early_stop != o.early_stop || trials != o.trials || !same_number(fitness_sd, o.fitness_sd) ||
      !same_number(fitness_min, o.fitness_min) || !same_number(fitness_max, o.fitness_max))
    return false;
  if (measures.size() != o.measures.size()) return false;
  for (size_t i = 0; i < measures.size(); ++i)
    if (!same_number(measures[i], o.measures[i])) return false;
  return true;
}

nlohmann::json eval_result_to_json(const EvalResult& r) {
  nlohmann::json m = nlohmann::json::array();
  for (double v : r.measures) m.push_back(number_json(v));
  return {{"fitness", number_json(r.fitness)},
          {"measures", m},
          {"failed", r.failed},
          {"why", r.why},
          {"early_stop", r.early_stop},
          {"trials", r.trials},
          {"fitness_sd", number_json(r.fitness_sd)},
          {"fitness_min", number_json(r.fitness_min)},
          {"fitness_max", number_json(r.fitness_max)},
          {"wall_s", r.wall_s},
          {"infra", r.infra}};
}

std::string infrastructure_fault(const ExitStatus& st, const std::string& run_fault) {
  if (!st.exited) return "the evaluator was ended by " + st.text() + " from outside";
  switch (st.code) {
    case kExitOk:
    case kExitModuleFault:
    case kExitDivergence:
    case kExitSilentModule:
      break;
    case kExitOutput:
      return "the run could not write its files (" + (run_fault.empty() ? st.text() : run_fault) +
             "): is the disk under --out full?";
    case kExitInterrupted:
      return "the run was interrupted";
    case kExitInternal:
      return "internal error of the run" + (run_fault.empty() ? std::string() : ": " + run_fault);
    default:
      return "the run could not start (" + st.text() + (run_fault.empty() ? "" : ": " + run_fault) + ")";
  }
  // a module killed by a signal its own program does not send itself
  static const std::regex killed("ended: signal (9|15|1|2) \\(");
  if (std::regex_search(run_fault, killed))
    return run_fault + " (from outside the program: the OOM killer, or a user)";
  return "";
}

EvalResult eval_result_of(const Score& s, double wall_s) {
  EvalResult r;
  r.fitness = s.fitness;
  r.measures = s.measures;
  r.failed = s.failed;
  r.why = deterministic_fault_text(s.why);
  r.early_stop = s.early_stop;
  r.trials = s.trials;
  r.fitness_sd = s.fitness_sd;
  r.fitness_min = s.fitness_min;
  r.fitness_max = s.fitness_max;
  r.wall_s = wall_s;
  return r;
}

EvalResult eval_result_from_json(const nlohmann::json& j) {
  EvalResult r;
  r.fitness = number_from_json(j.at("fitness"));
  for (const auto& v : j.at("measures")) r.measures.push_back(number_from_json(v));
  r.failed = j.at("failed").get<bool>();
  r.why = j.at("why").get<std::string>();
  r.early_stop = j.value("early_stop", std::string());
  r.trials = j.value("trials", 1);
  if (j.contains("fitness_sd")) r.fitness_sd = number_from_json(j["fitness_sd"]);
  if (j.contains("fitness_min")) r.fitness_min = number_from_json(j["fitness_min"]);
  if (j.contains("fitness_max")) r.fitness_max = number_from_json(j["fitness_max"]);
  r.wall_s = j.at("wall_s").get<double>();
  r.infra = j.value("infra", false);
  return r;
}

uint64_t trial_seed(uint64_t seed, int trial) {
  if (trial == 0) return seed;
  // the trial-th output of splitmix64's sequence from seed
  return splitmix64(seed + 0x9E3779B97F4A7C15ull * static_cast<uint64_t>(trial - 1)) >> 2;
}

std::string deterministic_fault_text(const std::string& text) {
  static const std::regex pid(", pid [0-9]+");
  return std::regex_replace(text, pid, "");
}

Evaluation::Evaluation(const EvalContext& ctx, EvalTask task, const std::string& dir)
    : ctx_(ctx), task_(std::move(task)) {
  const Problem& pr = *ctx_.problem;
  t0_ = std::chrono::steady_clock::now();
  dir_ = !dir.empty() ? dir : ctx_.work_dir + "/" + std::to_string(task_.index) + "-" + std::to_string(task_.seed);
  std::error_code ec;
  std::filesystem::remove_all(dir_, ec);
  std::filesystem::create_directories(dir_, ec);
  auto fail_now = [&](const std::string& why, bool infra) {
    result_ = eval_result_of(failed_score(pr.measures.size(), pr.objective, why), 0.0);
    result_.infra = infra;
    done_ = true;
  };
  if (ec) {
    fail_now("cannot create " + dir_ + ": " + ec.message(), true);
    return;
  }
  try {
    // every trial's scene, checked here: a scene the genome spoils fails here, not in a child
    for (int r = 0; r < std::max(1, task_.trials); ++r) {
      const std::string text = individual_scene_yaml(pr, task_.phenotype, trial_seed(task_.seed, task_.first_trial + r),
                                                     task_.solver, task_.target);
      load_scene_text(text, scene_path(r));
      std::ofstream out(scene_path(r), std::ios::binary);
      out << text;
      out.flush();
      if (!out) {
        fail_now("cannot write " + scene_path(r) + ": is the disk under --out full?", true);
        return;
      }
    }
  } catch (const SceneError& e) {
    fail_now(std::string("scene: ") + e.what(), false);  // the genome spoils the scene: the design's
    return;
  }
  start_trial();
}

std::string Evaluation::scene_path(int r) const {
  return dir_ + (r == 0 ? "/scene.yaml" : "/scene-" + std::to_string(r) + ".yaml");
}

std::string Evaluation::run_dir(int r) const { return dir_ + (r == 0 ? "/run" : "/run-" + std::to_string(r)); }

void Evaluation::start_trial() {
  const Problem& pr = *ctx_.problem;
  const int r = static_cast<int>(scores_.size());
  ChildSpec spec;
  spec.program = ctx_.evaluator_exe;
  char timeout[32];
  std::snprintf(timeout, sizeof timeout, "%g", pr.evaluation.module_timeout_s);
  spec.args = {scene_path(r), run_dir(r), timeout};
  if (!pr.evaluation.firmware_dir.empty()) spec.args.push_back(pr.evaluation.firmware_dir);
  spec.stdout_path = dir_ + "/chainsim.out";
  try {
    child_.spawn(spec);
  } catch (const std::exception& e) {
    result_ = eval_result_of(failed_score(pr.measures.size(), pr.objective,
                                          std::string("cannot start " + ctx_.evaluator_exe + ": ") + e.what()),
                             0.0);
    result_.infra = true;
    done_ = true;
  }
}

bool Evaluation::poll() {
  if (done_) return true;
  if (const auto& st = child_.poll()) finish(*st);
  return done_;
}

void Evaluation::terminate() {
  if (!done_) child_.terminate(500);
  done_ = true;
}

void Evaluation::finish(const ExitStatus& st) {
  const Problem& pr = *ctx_.problem;
  const int r = static_cast<int>(scores_.size());
  Score s;
  std::string infra;
  try {
    const RunOutcome rec = read_run_outcome(run_dir(r));
    infra = infrastructure_fault(st, rec.fault);
    s = score_run(pr.measures, pr.objective, pr.constraints, rec, pr.pipe.get());
  } catch (const RunReadError& e) {
    // no usable outputs: say what the process said
    const std::string said = last_lines(dir_ + "/chainsim.out", 600);
    infra = infrastructure_fault(st, said);
    if (infra.empty()) infra = "the run left no usable outputs (" + std::string(e.what()) + "); it said: " + said;
    s = failed_score(pr.measures.size(), pr.objective, "the run ended with " + st.text() + ": " + said);
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
  if (!infra.empty()) {
    result_ = eval_result_of(failed_score(pr.measures.size(), pr.objective, infra), wall);
    result_.infra = true;
    done_ = true;  // the run directory stays, for whoever looks into it
    return;
  }
  scores_.push_back(s);
  // a failed trial fails the individual: no need to run the others
  if (!s.failed && static_cast<int>(scores_.size()) < task_.trials) {
    start_trial();
    return;
  }
  const Score all =
      combine_trials(scores_, pr.objective, pr.evaluation.fitness, pr.evaluation.quantile, std::max(1, task_.trials));
  result_ = eval_result_of(all, wall);
  done_ = true;
  if (!ctx_.keep_runs) {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
}

EvalResult evaluate_now(const EvalContext& ctx, const EvalTask& task, const std::string& dir) {
  EvalContext c = ctx;
  c.keep_runs = c.keep_runs || !dir.empty();
  Evaluation e(c, task, dir);
  while (!e.poll()) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  return e.result();
}

}  // namespace chainsim
