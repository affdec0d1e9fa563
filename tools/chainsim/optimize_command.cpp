#include "chainsim/optimize_command.h"

#include <CLI/CLI.hpp>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <thread>

#include "cosim/lockstep_server.h"
#include "cosim/program_params.h"
#include "optimize/local_pool.h"
#include "optimize/mpi_pool.h"
#include "optimize/problem_params.h"
#include "optimize/report.h"
#include "optimize/search.h"
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
};

OptimizeArgs g_args;
int g_exit_code = -1;

std::string self_exe() {
  char buf[4096];
  const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
  return n > 0 ? std::string(buf, static_cast<size_t>(n)) : "chainsim";
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// runs best.yaml again into DIR/best (the replay's run), says whether it reproduced the search's result
std::string replay_best(const EvalContext& ctx, const Problem& pr, const BestSoFar& best, const std::string& dir) {
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
  const EvalResult r = evaluate_now(ctx, individual_task(pr, best.genes, best.individual), dir);
  char b[256];
  if (r.fitness == best.fitness && r.failed == best.failed && pr.evaluation.repeats == 1)
    std::snprintf(b, sizeof b, "Run again from best.yaml, it gave the same fitness (%.10g) in %.1f s.", r.fitness,
                  r.wall_s);
  else if (r.fitness == best.fitness && r.failed == best.failed)
    std::snprintf(b, sizeof b, "Run again (its %d repeats; best.yaml is the first), it gave the same fitness (%.10g) "
                  "in %.1f s.", pr.evaluation.repeats, r.fitness, r.wall_s);
  else
    std::snprintf(b, sizeof b, "WARNING: best.yaml run again gave fitness %.10g, the search recorded %.10g: "
                               "the run is not deterministic.", r.fitness, best.fitness);
  return b;
}

int finish(const OptimizeArgs& a, const Problem& pr, const EvalContext& ctx, const SearchSummary& s) {
  const std::string& dir = a.out;
  std::string note, replay;
  if (s.best.valid && !a.no_replay) {
    note = replay_best(ctx, pr, s.best, dir + "/best");
    try {
      std::vector<std::string> warnings;
      replay = viewer_page(replay_boot(dir + "/best/run", &warnings), pr.name + ": best individual");
    } catch (const std::exception& e) {
      std::fprintf(stderr, "optimize: the report has no replay: %s\n", e.what());
    }
  }
  std::vector<HistoryRow> rows;
  try {
    rows = parse_history(read_text(history_path(dir)), pr.measures.size(), history_path(dir));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "optimize: %s\n", e.what());
    return kExitInternal;
  }
  std::ofstream(dir + "/report.html", std::ios::binary) << report_html(pr, rows, s.best, note, replay);
  if (!a.quiet) {
    std::fprintf(stderr,
                 "optimize: best %s: fitness %.10g%s (generation %d); %llu evaluations, %llu simulated, %llu cache "
                 "hits, %.1f s\noptimize: %s\noptimize: %s/best.yaml, history.csv, report.html\n",
                 s.best.key.c_str(), s.best.fitness, s.best.failed ? " (failed)" : "", s.best.generation,
                 static_cast<unsigned long long>(s.evaluations), static_cast<unsigned long long>(s.simulations),
                 static_cast<unsigned long long>(s.cache_hits), s.wall_s, note.empty() ? "(no replay)" : note.c_str(),
                 dir.c_str());
  }
  return kExitOk;
}

int run_optimize(const OptimizeArgs& a) {
  std::unique_ptr<MpiSession> mpi;
  if (launched_by_mpirun()) mpi = std::make_unique<MpiSession>(nullptr, nullptr);
  const int rank = mpi ? mpi->rank() : 0;
  auto leave = [&](int code, bool lost) {
    if (mpi) mpi->exit(code, lost);
    return code;
  };
  install_interrupt_handlers();

  Problem pr;
  try {
    pr = load_problem_file(a.problem);
    check_problem_params(pr, "");  // the evaluations find the programs next to chainsim
  } catch (const std::exception& e) {
    if (rank == 0) std::fprintf(stderr, "chainsim: %s\n", e.what());
    return leave(kExitBadInput, false);
  }
  if (a.seed >= 0) pr.ga.seed = static_cast<uint64_t>(a.seed);
  if (a.population > 0) pr.ga.population = a.population;
  if (a.generations >= 0) pr.ga.generations = a.generations;
  if (a.exhaustive) pr.exhaustive = true;
  if (!a.target.empty()) {
    pr.evaluation.target = a.target;
    try {  // the .hex of the base scene's programs are there
      Scene s = load_scene_text(pr.scene_text, pr.scene_file);
      set_target(&s, a.target == "pic" ? Target::Pic : Target::Native);
      check_scene_programs(s, "");
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
  MpiPool* mpi_pool = nullptr;
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
  auto stop = [&](bool finalize) {
    if (mpi_pool) mpi_pool->stop_workers(finalize);
  };

  SearchOptions so;
  so.out_dir = a.out;
  so.resume = a.resume;
  so.quiet = a.quiet;
  SearchSummary s;
  try {
    if (!a.quiet)
      std::fprintf(stderr, "optimize: %s: %zu genes (%lld gene vectors), %s, population %d, generations 0..%d, seed %llu, "
                           "%s; writing %s\n",
                   pr.name.c_str(), pr.genome.gene_count(), static_cast<long long>(pr.genome.gene_space_size()),
                   pr.exhaustive ? "exhaustive" : "pagmo sga", pr.ga.population, last_generation(pr),
                   static_cast<unsigned long long>(pr.ga.seed), pool->describe().c_str(), a.out.c_str());
    s = run_search(pr, so, *pool);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "chainsim: %s\n", e.what());
    const bool any_lost = mpi_pool && mpi_pool->lost_ranks() > 0;
    stop(!any_lost);
    return leave(kExitBadInput, any_lost);
  }
  const bool any_lost = mpi_pool && mpi_pool->lost_ranks() > 0;
  stop(!any_lost);
  if (s.interrupted) {
    std::fprintf(stderr, "optimize: interrupted (signal %d) after generation %d; continue with --resume\n",
                 interrupt_signal(), s.generations_done);
    return leave(kExitInterrupted, any_lost);
  }
  int rc = kExitOk;
  try {
    rc = finish(a, pr, ctx, s);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "chainsim: %s\n", e.what());
    rc = kExitInternal;
  }
  std::error_code ec;
  std::filesystem::remove(ctx.work_dir, ec);  // only when empty
  return leave(rc, any_lost);
}

}  // namespace

void add_optimize_command(CLI::App& app) {
  CLI::App* sub = app.add_subcommand(
      "optimize",
      "design search: a genetic algorithm (pagmo sga) over chains and program parameters, each individual a "
      "real co-simulation; local workers, or MPI ranks under mpirun (docs/optimize.md)");
  sub->add_option("problem", g_args.problem, "problem file (YAML, docs/optimize.md)")->required()
      ->check(CLI::ExistingFile);
  sub->add_option("--out,-o", g_args.out, "directory of the search: history.csv, best.yaml, report.html, checkpoint")
      ->required();
  sub->add_option("--workers,-j", g_args.workers,
                  "evaluations at once (default: the number of cores; under mpirun: per worker rank, default 1)")
      ->check(CLI::PositiveNumber);
  sub->add_option("--seed", g_args.seed, "search seed (default: the problem's ga.seed)")->check(CLI::NonNegativeNumber);
  sub->add_option("--population", g_args.population, "individuals per generation (default: the problem's, else 40)")
      ->check(CLI::Range(2, 100000));
  sub->add_option("--generations", g_args.generations, "generations after the initial population (default: the problem's)")
      ->check(CLI::NonNegativeNumber);
  sub->add_flag("--resume", g_args.resume, "continue the search in --out from its last checkpoint");
  sub->add_flag("--exhaustive", g_args.exhaustive, "evaluate every individual of the genome instead of the GA");
  sub->add_flag("--keep-runs", g_args.keep_runs, "keep every evaluation's run directory in OUT/work");
  sub->add_flag("--no-replay", g_args.no_replay, "do not run the best again for the report's replay");
  sub->add_option("--rank-timeout", g_args.rank_timeout,
                  "under mpirun: seconds of silence after which a rank holding work is given up")
      ->check(CLI::PositiveNumber);
  sub->add_option("--target", g_args.target,
                  "every evaluation's programs native, or the board's own .hex in gpsim (pic: about 1 CPU second "
                  "per simulated second per module; for checking a few designs, docs/pic-in-the-loop.md)")
      ->check(CLI::IsMember({"native", "pic"}));
  sub->add_flag("--quiet,-q", g_args.quiet, "print only errors");
  sub->callback([] { g_exit_code = run_optimize(g_args); });
}

int optimize_command_exit_code() { return g_exit_code; }

}  // namespace chainsim
