#include "chainsim/bench_search_command.h"

#include <CLI/CLI.hpp>

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cosim/run_options.h"
#include "optimize/history.h"
#include "optimize/problem.h"
#include "optimize/search.h"
#include "optimize/simulated_pool.h"
#include "output/sha256.h"
#include "readers/text_file.h"

namespace chainsim {
namespace {

struct SearchBenchArgs {
  std::string problem, history, times, out;
  std::vector<int> cores{8, 64, 256};
  std::vector<int> islands{1, 4, 16};
  int generations = -1;
  int population = -1;
  double scale = 0.01;
};

SearchBenchArgs g_search_bench_args;

// the history's text without wall_s: what must be the same whatever the cores
std::string history_sha(const std::string& path) {
  std::istringstream in(read_text_file(path));
  std::string line, text;
  while (std::getline(in, line)) text += line.substr(0, line.rfind(',')) + "\n";
  Sha256 sha;
  sha.update(text.data(), text.size());
  return sha.hex().substr(0, 12);
}

// the wall_s of the simulated rows of any search's history.csv
std::vector<double> recorded_times(const std::string& path) {
  std::istringstream in(read_text_file(path));
  std::string line;
  std::getline(in, line);
  std::vector<std::string> head;
  {
    std::istringstream h(line);
    for (std::string c; std::getline(h, c, ',');) head.push_back(c);
  }
  const auto col = [&](const std::string& name) {
    for (size_t i = 0; i < head.size(); ++i)
      if (head[i] == name) return i;
    throw std::runtime_error(path + ": no column " + name + " (is it a history.csv of chainsim optimize?)");
  };
  // cached and wall_s are the last two columns, which hold no comma (a fault
  // or an early stop before them may, quoted): read from the end of the line
  if (col("cached") + 2 != head.size() || col("wall_s") + 1 != head.size())
    throw std::runtime_error(path + ": cached and wall_s are not the last columns (is it a history.csv of chainsim "
                             "optimize?)");
  std::vector<double> t;
  for (int n = 2; std::getline(in, line); ++n) {
    std::vector<std::string> f;
    std::istringstream r(line);
    for (std::string c; std::getline(r, c, ',');) f.push_back(c);
    if (f.size() < 2) continue;
    const std::string w = f[f.size() - 1], c = f[f.size() - 2];
    if (c != "no" || w.empty()) continue;
    char* end = nullptr;
    const double v = std::strtod(w.c_str(), &end);
    if (end == w.c_str() || *end || !(v >= 0) || v > 1e6)
      throw std::runtime_error(path + ":" + std::to_string(n) + ": wall_s '" + w.substr(0, 40) +
                               "' is no number of seconds");
    t.push_back(v);
  }
  return t;
}

int run(const SearchBenchArgs& a) {
  try {
    const Problem base = load_problem_file(a.problem);
    if (a.history.empty() == a.times.empty())
      throw std::runtime_error("give --history (a search of this problem: its results and times) or --times (any "
                               "search's history.csv: its times only, with a synthetic landscape)");
    const std::vector<HistoryRow> recorded =
        a.history.empty() ? std::vector<HistoryRow>{} : parse_history(read_text_file(a.history), base.measures.size(), a.history);
    std::vector<double> times;
    if (!a.times.empty()) times = recorded_times(a.times);
    for (const HistoryRow& r : recorded)
      if (!r.cached) times.push_back(r.result.wall_s);
    double recorded_s = 0;
    for (double t : times) recorded_s += t;
    const size_t simulated = times.size();
    const std::string source = a.history.empty() ? a.times : a.history;
    if (simulated == 0) throw std::runtime_error(source + ": no simulated rows (wall times) to replay");
    const std::string out = a.out.empty() ? std::filesystem::temp_directory_path().string() + "/chainsim-bench-search-" +
                                                std::to_string(getpid())
                                          : a.out;
    std::printf("# the search's scheduler on simulated cores: %s, evaluation times from %s (%zu runs, mean %.2f s),\n"
                "# slept %gx; busy = the cores' busy time / (cores x wall)\n",
                base.name.c_str(), source.c_str(), simulated, recorded_s / static_cast<double>(simulated), a.scale);
    if (!a.times.empty())
      std::printf("# results: synthetic (a fitness uniform in [0, 1) drawn from each key): the scheduler is measured, "
                  "not the search\n");
    std::printf("%6s %8s %10s %12s %10s %8s %10s %12s %14s\n", "cores", "islands", "population", "evaluations",
                "simulated", "busy", "wall_s", "ideal_wall_s", "history");
    for (int islands : a.islands) {
      if (base.exhaustive && islands > 1) continue;
      for (int cores : a.cores) {
        Problem pr = base;
        pr.ga.islands = islands;
        if (a.generations >= 0) pr.ga.generations = a.generations;
        if (a.population >= 0) {
          if (a.population <= pr.ga.migrants || a.population < pr.ga.selection_size)
            throw std::runtime_error("--population " + std::to_string(a.population) +
                                     ": the problem's ga.migrants and ga.selection_size need a larger one");
          pr.ga.population = a.population;
        }
        pr.evaluation.trials = 1;  // the recorded rows are whole evaluations
        const std::string dir = out + "/" + std::to_string(islands) + "-" + std::to_string(cores);
        std::filesystem::remove_all(dir);
        SimulatedPool pool = a.times.empty()
                                 ? SimulatedPool(recorded, pr.objective.failed_fitness, pr.measures.size(), cores, a.scale)
                                 : SimulatedPool(times, pr.measures.size(), cores, a.scale);
        SearchOptions so;
        so.out_dir = dir;
        so.quiet = true;
        const SearchSummary s = run_search(pr, so, pool);
        if (s.interrupted) return kExitInterrupted;
        std::printf("%6d %8d %10d %12llu %10llu %8.3f %10.2f %12.2f %14s\n", cores, islands, pr.ga.population,
                    static_cast<unsigned long long>(s.evaluations), static_cast<unsigned long long>(pool.evaluations()),
                    pool.busy_s() / (cores * pool.wall_s()), pool.wall_s(), pool.busy_s() / cores,
                    history_sha(history_path(dir)).c_str());
        std::fflush(stdout);
      }
    }
    if (a.out.empty()) std::filesystem::remove_all(out);
    return kExitOk;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "chainsim bench-search: %s\n", e.what());
    return kExitBadInput;
  }
}

}  // namespace

Command add_bench_search_command(CLI::App& app) {
  CLI::App* sub = app.add_subcommand(
      "bench-search",
      "the design search's scheduler on simulated cores: evaluations sleep the wall times a real search recorded "
      "(history.csv) and return its results; busy fraction per core count and islands (docs/benchmarks.md)");
  sub->add_option("problem", g_search_bench_args.problem, "the problem file of the recorded search")->required()
      ->check(CLI::ExistingFile);
  sub->add_option("--history", g_search_bench_args.history, "history.csv of a real search of that problem (its times and results)")
      ->check(CLI::ExistingFile);
  sub->add_option("--times", g_search_bench_args.times,
                  "history.csv of any search: its wall times only, results synthetic (for a genome larger than the "
                  "recorded search's)")
      ->check(CLI::ExistingFile);
  sub->add_option("--cores", g_search_bench_args.cores, "simulated core counts (default 8 64 256)")->check(CLI::Range(1, 1000000));
  sub->add_option("--islands", g_search_bench_args.islands, "island counts (default 1 4 16)")->check(CLI::Range(1, 10000));
  sub->add_option("--generations", g_search_bench_args.generations, "generations (default: the problem's)")
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--population", g_search_bench_args.population, "each island's population (default: the problem's)")
      ->check(CLI::Range(2, 100000));
  sub->add_option("--scale", g_search_bench_args.scale, "wall seconds slept per recorded second (default 0.01)")
      ->check(CLI::Range(1e-6, 10.0));
  sub->add_option("--out", g_search_bench_args.out, "keep each search's directory here (default: a temporary one, removed)");
  return {sub, [] { return run(g_search_bench_args); }};
}


}  // namespace chainsim
