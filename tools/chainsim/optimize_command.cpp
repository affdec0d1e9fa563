#include "chainsim/optimize_command.h"

#include <CLI/CLI.hpp>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "cosim/lockstep_server.h"
#include "cosim/program_params.h"
#include "optimize/individual_scene.h"
#include "optimize/local_pool.h"
#include "optimize/mpi_pool.h"
#include "optimize/output_error.h"
#include "optimize/problem_params.h"
#include "optimize/report.h"
#include "optimize/search.h"
#include "optimize/search_lock.h"
#include "optimize/verify.h"
#include "readers/text_file.h"
#include "viewer/viewer_page.h"

namespace chainsim {
namespace {

struct OptimizeArgs {
  std::string problem;
  std::string out;
  int workers = 0;            // 0: the number of cores (MPI: 1 per worker rank)
  int64_t seed = -1;
  int population = 0;
  int generations = -1;
  bool resume = false;
  bool exhaustive = false;
  bool keep_runs = false;
  bool no_replay = false;
  double rank_timeout = 60;
  bool quiet = false;
  std::string target;         // every evaluation's programs native or on the PIC
  std::string firmware_dir;   // --firmware-dir: where evaluations look for programs first
  std::string verify_dir;     // --verify DIR: verify a search's winners, no search
  int verify_top = 3;         // leaders verified at the end (0: none)
  int verify_trials = 0;      // fresh trials each (0: the search's, at least 3)
  bool no_verify_exact = false;
  std::string verify_pic = "auto";  // auto: when every leader's .hex is there; no
};

OptimizeArgs g_optimize_args;

std::string self_exe() {
  char buf[4096];
  const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
  return n > 0 ? std::string(buf, static_cast<size_t>(n)) : "chainsim";
}

// runs best.yaml again into DIR/best (the replay's run), says whether it reproduced the search's result
std::string replay_best(const EvalContext& ctx, const Problem& pr, const BestSoFar& best, int trials,
                        const std::string& dir) {
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
  EvalTask task = individual_task(pr, best.genes, best.individual);
  task.trials = trials;
  const EvalResult r = evaluate_now(ctx, task, dir);
  char b[320];
  // best.fitness may come from history.csv, which keeps 10 digits
  const bool same = history_number(r.fitness) == history_number(best.fitness) && r.failed == best.failed;
  if (same && trials == 1)
    std::snprintf(b, sizeof b, "Run again from best.yaml, it gave the same fitness (%.10g) in %.1f s.", r.fitness,
                  r.wall_s);
  else if (same)
    std::snprintf(b, sizeof b, "Run again (its %d trials; best.yaml is the first), it gave the same fitness (%.10g) "
                  "in %.1f s.", trials, r.fitness, r.wall_s);
  else
    std::snprintf(b, sizeof b, "WARNING: best.yaml run again gave fitness %.10g, the search recorded %.10g: "
                               "the run is not deterministic.", r.fitness, best.fitness);
  return b;
}

// the first history row of a genome
const HistoryRow* row_of(const std::vector<HistoryRow>& rows, const std::string& key) {
  for (const HistoryRow& r : rows)
    if (r.genome == key) return &r;
  return nullptr;
}

// "" when every leader's programs have their .hex, else why not
std::string pic_missing(const Problem& pr, const std::vector<HistoryRow>& top) {
  for (const HistoryRow& r : top) {
    try {
      const Phenotype p = phenotype_from_key(pr.genome, r.genome);
      const Scene s = load_scene_text(individual_scene_yaml(pr, p, 1, "", "pic"), r.genome);
      check_scene_programs(s, pr.evaluation.firmware_dir);
    } catch (const std::exception& e) {
      return e.what();
    }
  }
  return "";
}

std::string num6(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

// after the search (or for --verify): the leaders, the noise, the
// verification, best.yaml, the best's replay and the report
// (workers_done: the pool's work is over, before the best's replay, which
// runs here: MPI worker ranks then leave rather than wait for rank 0;
// history_bytes: how much of history.csv the checkpoint holds, 0 all)
int finish(const OptimizeArgs& a, const Problem& pr, const EvalContext& ctx, const SearchSummary& s,
           EvaluatorPool& pool, bool* interrupted, const std::function<void()>& workers_done, uint64_t history_bytes) {
  const std::string& dir = a.out;
  std::vector<HistoryRow> rows;
  try {
    std::string text = read_text_file(history_path(dir));
    if (history_bytes > 0 && text.size() > history_bytes) text.resize(history_bytes);  // past the checkpoint: not the search's yet
    rows = parse_history(text, pr.measures.size(), history_path(dir));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "optimize: %s\n", e.what());
    return kExitInternal;
  }
  ReportNotes notes;
  notes.trials = s.trials_note;
  notes.noise = noise_warning(pr, leaders(pr, rows, 5));
  if (!notes.noise.empty() && !a.quiet) std::fprintf(stderr, "optimize: warning: %s\n", notes.noise.c_str());

  BestSoFar best = s.best;
  Verification ver;
  bool verified = false;
  if (a.verify_top > 0 && !rows.empty()) {
    const std::vector<HistoryRow> top = leaders(pr, rows, static_cast<size_t>(a.verify_top));
    VerifySettings vs;
    vs.top = a.verify_top;
    vs.trials = a.verify_trials;
    vs.exact = !a.no_verify_exact;
    if (a.verify_pic == "auto") {
      const std::string why = pic_missing(pr, top);
      vs.pic = why.empty();
      if (!vs.pic)
        notes.verification_note = "Not verified on the board's binaries: " + why +
                                  " (tools/pic-build.sh builds every shipped program's .hex).";
    }
    if (!verify_leaders(pr, top, vs, pool, &ver, a.quiet)) {
      *interrupted = true;
      return kExitInterrupted;
    }
    verified = true;
    notes.verification = &ver;
    write_file_atomic(dir + "/verify.csv", verification_csv(ver));
    write_file_atomic(dir + "/verify.json", verification_json(ver).dump(1) + "\n");
    if (ver.best >= 0) {
      const VerifiedLeader& v = ver.leaders[static_cast<size_t>(ver.best)];
      const HistoryRow& r = v.search;
      best = {true, r.generation, r.island, r.individual, r.genome,
              encode_phenotype(pr.genome, phenotype_from_key(pr.genome, r.genome)), r.result.fitness, r.result.failed};
      std::string more = "# Verified: the best of the search's " + std::to_string(ver.leaders.size()) +
                         " leaders with " + std::to_string(ver.fresh_trials) + " fresh seeds: fitness " +
                         num6(v.fresh.fitness) +
                         (std::isfinite(v.fresh.fitness_sd) ? " (sd " + num6(v.fresh.fitness_sd) + ")" : "") + "\n";
      for (const auto& f : v.flags) more += "# Flag: " + f + "\n";
      write_file_atomic(best_scene_path(dir), best_scene_text(pr, best, more));
    }
    if (!a.quiet) {
      for (size_t l = 0; l < ver.leaders.size(); ++l) {
        const VerifiedLeader& v = ver.leaders[l];
        std::fprintf(stderr, "optimize: verified %s: search %s, fresh %s%s%s%s\n", v.search.genome.c_str(),
                     v.search.result.failed ? "failed" : num6(v.search.result.fitness).c_str(),
                     v.fresh.failed ? "fails" : (num6(v.fresh.fitness) + " sd " + num6(v.fresh.fitness_sd)).c_str(),
                     v.has_exact ? (std::string(", exact ") + (v.exact.failed ? "fails" : num6(v.exact.fitness))).c_str() : "",
                     v.has_pic ? (std::string(", board ") + (v.pic.failed ? "fails" : num6(v.pic.fitness))).c_str() : "",
                     static_cast<int>(l) == ver.best ? " <- verified best" : "");
        for (const auto& f : v.flags) std::fprintf(stderr, "optimize:   flag: %s\n", f.c_str());
      }
      if (ver.best < 0) std::fprintf(stderr, "optimize: no leader passed with fresh seeds: best.yaml stays the search's best\n");
    }
  }

  workers_done();
  std::string replay;
  if (best.valid && !a.no_replay) {
    const HistoryRow* r = row_of(rows, best.key);
    notes.replay = replay_best(ctx, pr, best, r ? std::max(1, r->result.trials) : 1, dir + "/best");
    try {
      std::vector<std::string> warnings;
      replay = viewer_page(replay_boot(dir + "/best/run", &warnings), pr.name + ": best individual");
    } catch (const std::exception& e) {
      std::fprintf(stderr, "optimize: the report has no replay: %s\n", e.what());
    }
  }
  write_file_atomic(dir + "/report.html", report_html(pr, rows, best, notes, replay));
  if (!a.quiet) {
    const bool changed = verified && ver.best >= 0 && best.key != s.best.key;
    std::fprintf(stderr,
                 "optimize: best %s: fitness %.10g%s (generation %d)%s; %llu evaluations, %llu simulated, %llu cache "
                 "hits, %.1f s\noptimize: %s\noptimize: %s/best.yaml, history.csv, report.html%s\n",
                 best.key.c_str(), best.fitness, best.failed ? " (failed)" : "", best.generation,
                 changed ? (", verified best; the search's own best " + s.best.key + " did worse with fresh seeds").c_str()
                         : "",
                 static_cast<unsigned long long>(s.evaluations), static_cast<unsigned long long>(s.simulations),
                 static_cast<unsigned long long>(s.cache_hits), s.wall_s,
                 notes.replay.empty() ? "(no replay)" : notes.replay.c_str(), dir.c_str(),
                 verified ? ", verify.csv" : "");
  }
  return kExitOk;
}

// the exit code of what stopped a search: a fault of the machine is not bad
// input (a full disk: 5, as chainsim run; an evaluator killed or failing
// inside: 3); anything else the problem, the options or the directory
int exit_code_of(const std::exception& e) {
  if (const auto* i = dynamic_cast<const InfrastructureError*>(&e)) return i->disk_full ? kExitOutput : kExitInternal;
  if (dynamic_cast<const OutputError*>(&e)) return kExitOutput;
  return kExitBadInput;
}

// DIR[:DIR...] with each DIR absolute (evaluations run in their own directories)
std::string absolute_dirs(const std::string& dirs) {
  std::string out;
  for (size_t b = 0; b < dirs.size();) {
    const size_t e = std::min(dirs.find(':', b), dirs.size());
    if (e > b) {
      const std::string d = dirs.substr(b, e - b);
      std::error_code ec;
      if (!std::filesystem::is_directory(d, ec)) throw std::runtime_error("--firmware-dir: " + d + " is no folder");
      if (!out.empty()) out += ':';
      std::string a = std::filesystem::absolute(d).lexically_normal().string();
      while (a.size() > 1 && a.back() == '/') a.pop_back();  // "." and "/x/build" are one folder
      out += a;
    }
    b = e + 1;
  }
  return out;
}

// what a search was started with, beside it (DIR/search.json): --verify DIR
// loads the same problem with the same overrides
void write_search_args(const OptimizeArgs& a) {
  nlohmann::json j = {{"problem", std::filesystem::absolute(a.problem).lexically_normal().string()}};
  if (a.seed >= 0) j["seed"] = a.seed;
  if (a.population > 0) j["population"] = a.population;
  if (a.generations >= 0) j["generations"] = a.generations;
  if (a.exhaustive) j["exhaustive"] = true;
  if (!a.target.empty()) j["target"] = a.target;
  if (!a.firmware_dir.empty()) j["firmware_dir"] = absolute_dirs(a.firmware_dir);  // --verify may run elsewhere
  write_file_atomic(a.out + "/search.json", j.dump(1) + "\n");
}

// --verify DIR: the arguments the search there was started with
bool read_search_args(OptimizeArgs* a, std::string* why) {
  const std::string path = a->verify_dir + "/search.json";
  std::ifstream in(path);
  if (!in) {
    *why = path + ": cannot open (no search of this chainsim there)";
    return false;
  }
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (!j.is_object() || !j.contains("problem") || !j["problem"].is_string()) {
    *why = path + ": damaged";
    return false;
  }
  a->problem = j["problem"].get<std::string>();
  a->seed = j.value("seed", int64_t{-1});
  a->population = j.value("population", 0);
  a->generations = j.value("generations", -1);
  a->exhaustive = j.value("exhaustive", false);
  a->target = j.value("target", std::string());
  if (a->firmware_dir.empty()) a->firmware_dir = j.value("firmware_dir", std::string());
  a->out = a->verify_dir;
  return true;
}

int run_optimize(const OptimizeArgs& given) {
  OptimizeArgs a = given;
  std::unique_ptr<MpiSession> mpi;
  if (launched_by_mpirun()) mpi = std::make_unique<MpiSession>(nullptr, nullptr);
  const int rank = mpi ? mpi->rank() : 0;
  MpiPool* mpi_pool = nullptr;
  auto leave = [&](int code, bool lost) {
    if (mpi) mpi->exit(code, lost, mpi_pool && mpi_pool->lost_remote_ranks() > 0);
    return code;
  };
  install_interrupt_handlers();
  const bool verify_only = !a.verify_dir.empty();
  if (verify_only) {
    std::string why;
    if (!read_search_args(&a, &why)) {
      if (rank == 0) std::fprintf(stderr, "chainsim: --verify: %s\n", why.c_str());
      return leave(kExitBadInput, false);
    }
  } else if (a.problem.empty() || a.out.empty()) {
    if (rank == 0) std::fprintf(stderr, "chainsim: optimize needs a problem file and --out DIR (or --verify DIR)\n");
    return leave(kExitBadInput, false);
  }

  Problem pr;
  try {
    pr = load_problem_file(a.problem);
    pr.evaluation.firmware_dir = absolute_dirs(a.firmware_dir);
    // the evaluations find the programs there first, then next to chainsim
    check_problem_params(pr, pr.evaluation.firmware_dir);
  } catch (const std::exception& e) {
    if (rank == 0) std::fprintf(stderr, "chainsim: %s\n", e.what());
    return leave(kExitBadInput, false);
  }
  if (a.seed >= 0) pr.ga.seed = static_cast<uint64_t>(a.seed);
  if (a.population > 0) pr.ga.population = a.population;
  if (a.generations >= 0) pr.ga.generations = a.generations;
  if (a.exhaustive) pr.exhaustive = true;
  if (pr.exhaustive && pr.ga.islands > 1) {
    if (rank == 0) std::fprintf(stderr, "chainsim: --exhaustive: the problem's ga.islands applies to a GA search only\n");
    return leave(kExitBadInput, false);
  }
  if (!a.target.empty()) {
    pr.evaluation.target = a.target;
    try {  // the .hex of the base scene's programs are there
      Scene s = load_scene_text(pr.scene_text, pr.scene_file);
      set_target(&s, a.target == "pic" ? Target::Pic : Target::Native);
      check_scene_programs(s, pr.evaluation.firmware_dir);
    } catch (const std::exception& e) {
      if (rank == 0) std::fprintf(stderr, "chainsim: --target %s: %s\n", a.target.c_str(), e.what());
      return leave(kExitBadInput, false);
    }
  }
  if (pr.ga.selection_size > pr.ga.population) {
    if (rank == 0)
      std::fprintf(stderr, "chainsim: --population %d is smaller than the problem's ga.selection_size %d\n",
                   pr.ga.population, pr.ga.selection_size);
    return leave(kExitBadInput, false);
  }
  if (pr.ga.migrants >= pr.ga.population) {
    if (rank == 0)
      std::fprintf(stderr, "chainsim: --population %d leaves no room for the problem's ga.migrants %d\n",
                   pr.ga.population, pr.ga.migrants);
    return leave(kExitBadInput, false);
  }

  EvalContext ctx;
  ctx.problem = &pr;
  ctx.evaluator_exe = (std::filesystem::path(self_exe()).parent_path() / "chainsim-evaluate").string();
  if (access(ctx.evaluator_exe.c_str(), X_OK) != 0) {
    if (rank == 0) std::fprintf(stderr, "chainsim: %s is missing: build the target chainsim-evaluate\n", ctx.evaluator_exe.c_str());
    return leave(kExitInternal, false);
  }
  ctx.work_dir = a.out + "/work" + (rank > 0 ? "/rank-" + std::to_string(rank) : "");
  ctx.keep_runs = a.keep_runs;
  if (rank > 0) {
    bool finalize = true;
    const int rc = mpi_worker_main(ctx, rank, a.workers > 0 ? a.workers : 1, a.rank_timeout, &finalize);
    return leave(rc, !finalize);
  }

  std::unique_ptr<EvaluatorPool> pool;
  if (mpi && mpi->size() > 1) {
    auto p = std::make_unique<MpiPool>(mpi->size(), a.rank_timeout, a.quiet);
    mpi_pool = p.get();
    pool = std::move(p);
    if (!MpiSession::recovery_enabled() && !a.quiet)
      std::fprintf(stderr,
                   "optimize: mpirun was started without --enable-recovery --mca orte_abort_on_non_zero_status 0: "
                   "if a rank dies, OpenMPI ends the whole job (continue it with --resume)\n");
  } else {
    const int n = a.workers > 0 ? a.workers : std::max(1u, std::thread::hardware_concurrency());
    pool = std::make_unique<LocalPool>(ctx, n);
  }
  bool stopped = false;
  auto stop = [&](bool finalize) {  // once: the worker ranks leave
    if (mpi_pool && !stopped) mpi_pool->stop_workers(finalize);
    stopped = true;
  };
  // the workers released before the replay: they finalize MPI only when no
  // rank was lost (MPI_Finalize can wait for ever for a dead rank: under load,
  // mpirun then never ended after a search that had lost one)
  const std::function<void()> release_workers = [&] { stop(!(mpi_pool && mpi_pool->lost_ranks() > 0)); };
  auto fail = [&](const std::exception& e, int code) {
    std::fprintf(stderr, "chainsim: %s\n", e.what());
    const bool any_lost = mpi_pool && mpi_pool->lost_ranks() > 0;
    const bool remote_lost = mpi_pool && mpi_pool->lost_remote_ranks() > 0;
    stop(!any_lost);
    mpi_pool = nullptr;
    pool.reset();  // ends the evaluations still running here
    if (mpi) mpi->exit(code, any_lost, remote_lost);
    return code;
  };

  // the directory, with the worker ranks waiting (a refusal tells them to
  // leave): this process's lock on it, then what --verify needs or what a
  // new search must not overwrite
  std::unique_ptr<SearchLock> lock;
  SearchSummary verify_summary;
  uint64_t history_bytes = 0;  // of history.csv, what the checkpoint holds (--verify)
  try {
    lock = std::make_unique<SearchLock>(a.out);  // until this process ends
    if (verify_only) {
      if (!std::filesystem::exists(checkpoint_path(a.out)))
        throw CheckpointError(a.out + ": the search there has not finished a generation yet: nothing to verify");
      const Checkpoint cp = read_checkpoint(checkpoint_path(a.out));
      if (cp.fingerprint != search_fingerprint(pr))
        throw CheckpointError(checkpoint_path(a.out) + ": the problem file or its base scene changed since the "
                              "search ran (" + a.problem + ")");
      verify_summary = summary_of(cp);
      history_bytes = cp.history_bytes;
      if (cp.generation < last_generation(pr) && !a.quiet)
        std::fprintf(stderr, "optimize: the search in %s stopped after generation %d of %d: verifying what it has\n",
                     a.out.c_str(), cp.generation, last_generation(pr));
    } else if (!a.resume && (std::filesystem::exists(checkpoint_path(a.out)) ||
                             std::filesystem::exists(history_path(a.out)))) {
      throw std::runtime_error(a.out + " already holds a search: continue it with --resume, or choose another --out");
    } else if (!a.resume) {
      write_search_args(a);
    }
  } catch (const std::exception& e) {
    return fail(e, exit_code_of(e));
  }

  if (verify_only) {
    bool interrupted = false;
    int rc = kExitOk;
    try {
      rc = finish(a, pr, ctx, verify_summary, *pool, &interrupted, release_workers, history_bytes);
    } catch (const std::exception& e) {
      rc = exit_code_of(e);
      return fail(e, rc == kExitBadInput ? kExitInternal : rc);
    }
    const bool any_lost = mpi_pool && mpi_pool->lost_ranks() > 0;
    stop(!any_lost);
    return leave(rc, any_lost);
  }

  SearchOptions so;
  so.out_dir = a.out;
  so.resume = a.resume;
  so.quiet = a.quiet;
  SearchSummary s;
  try {
    if (!a.quiet)
      std::fprintf(stderr, "optimize: %s: %zu genes (%s gene vectors), %s, population %d%s, generations 0..%d, seed %llu, "
                           "trials %s, %s; writing %s\n",
                   pr.name.c_str(), pr.genome.gene_count(),
                   pr.genome.gene_space_size() == INT64_MAX  // gene_space_size saturates there
                       ? "more than 9.2e18"
                       : std::to_string(pr.genome.gene_space_size()).c_str(),
                   pr.exhaustive ? "exhaustive" : "pagmo sga", pr.ga.population,
                   pr.ga.islands > 1 ? (" x " + std::to_string(pr.ga.islands) + " islands").c_str() : "",
                   last_generation(pr), static_cast<unsigned long long>(pr.ga.seed),
                   pr.evaluation.trials > 0 ? std::to_string(pr.evaluation.trials).c_str() : "auto",
                   pool->describe().c_str(), a.out.c_str());
    s = run_search(pr, so, *pool);
  } catch (const std::exception& e) {
    return fail(e, exit_code_of(e));
  }
  if (s.interrupted) {
    const bool any_lost = mpi_pool && mpi_pool->lost_ranks() > 0;
    stop(!any_lost);
    std::fprintf(stderr, "optimize: interrupted (signal %d) after generation %d; continue with --resume\n",
                 interrupt_signal(), s.generations_done);
    return leave(kExitInterrupted, any_lost);
  }
  int rc = kExitOk;
  bool interrupted = false;
  try {
    rc = finish(a, pr, ctx, s, *pool, &interrupted, release_workers, 0);
  } catch (const std::exception& e) {
    rc = exit_code_of(e);
    return fail(e, rc == kExitBadInput ? kExitInternal : rc);
  }
  if (interrupted)
    std::fprintf(stderr, "optimize: interrupted during the verification; the search is complete: run "
                         "chainsim optimize --verify %s to verify it\n", a.out.c_str());
  const bool any_lost = mpi_pool && mpi_pool->lost_ranks() > 0;
  stop(!any_lost);
  std::error_code ec;
  std::filesystem::remove(ctx.work_dir, ec);  // only when empty
  return leave(rc, any_lost);
}

}  // namespace

Command add_optimize_command(CLI::App& app) {
  CLI::App* sub = app.add_subcommand(
      "optimize",
      "design search: a genetic algorithm (pagmo sga) over chains and program parameters, each individual a "
      "real co-simulation; local workers, or MPI ranks under mpirun (docs/optimize.md)");
  sub->add_option("problem", g_optimize_args.problem, "problem file (YAML, docs/optimize.md)")->check(CLI::ExistingFile);
  sub->add_option("--out,-o", g_optimize_args.out, "directory of the search: history.csv, best.yaml, report.html, checkpoint");
  sub->add_option("--verify", g_optimize_args.verify_dir,
                  "verify the winners of the search in DIR (no search): fresh seeds, the exact solver, the board")
      ->check(CLI::ExistingDirectory);
  sub->add_option("--verify-top", g_optimize_args.verify_top,
                  "distinct best individuals verified at the end (default 3; 0: no verification)")
      ->check(CLI::Range(0, 1000));
  sub->add_option("--verify-trials", g_optimize_args.verify_trials,
                  "fresh trials per verified individual (default: the search's trials, at least 3)")
      ->check(CLI::Range(1, 1000));
  sub->add_flag("--no-verify-exact", g_optimize_args.no_verify_exact, "do not verify with the converged solver");
  sub->add_option("--verify-pic", g_optimize_args.verify_pic,
                  "verify once on the board's binaries: auto (when every .hex is there, the default) or no")
      ->check(CLI::IsMember({"auto", "no"}));
  sub->add_option("--workers,-j", g_optimize_args.workers,
                  "evaluations at once (default: the number of cores; under mpirun: per worker rank, default 1)")
      ->check(CLI::PositiveNumber);
  sub->add_option("--seed", g_optimize_args.seed, "search seed (default: the problem's ga.seed)")->check(CLI::NonNegativeNumber);
  sub->add_option("--population", g_optimize_args.population, "individuals per generation (default: the problem's, else 40)")
      ->check(CLI::Range(2, 100000));
  sub->add_option("--generations", g_optimize_args.generations, "generations after the initial population (default: the problem's)")
      ->check(CLI::NonNegativeNumber);
  sub->add_flag("--resume", g_optimize_args.resume, "continue the search in --out from its last checkpoint");
  sub->add_flag("--exhaustive", g_optimize_args.exhaustive, "evaluate every individual of the genome instead of the GA");
  sub->add_flag("--keep-runs", g_optimize_args.keep_runs, "keep every evaluation's run directory in OUT/work");
  sub->add_flag("--no-replay", g_optimize_args.no_replay, "do not run the best again for the report's replay");
  sub->add_option("--rank-timeout", g_optimize_args.rank_timeout,
                  "under mpirun: seconds of silence after which a rank holding work is given up")
      ->check(CLI::PositiveNumber);
  sub->add_option("--firmware-dir", g_optimize_args.firmware_dir,
                  "where every evaluation looks for programs first (DIR[:DIR...]), before next to chainsim: your own "
                  "programs, built out of tree (docs/firmware.md)");
  sub->add_option("--target", g_optimize_args.target,
                  "every evaluation's programs native, or the board's own .hex in gpsim (pic: about 1 CPU second "
                  "per simulated second per module; for checking a few designs, docs/pic-in-the-loop.md)")
      ->check(CLI::IsMember({"native", "pic"}));
  sub->add_flag("--quiet,-q", g_optimize_args.quiet, "print only errors");
  return {sub, [] { return run_optimize(g_optimize_args); }};
}


}  // namespace chainsim
