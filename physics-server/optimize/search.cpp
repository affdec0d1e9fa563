#include "optimize/search.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "optimize/eval_cache.h"
#include "optimize/history.h"
#include "optimize/individual_scene.h"
#include "optimize/sga_stepper.h"
#include "output/sha256.h"

namespace chainsim {

namespace {

using Clock = std::chrono::steady_clock;

// what must not change between a search and its resumption
std::string fingerprint(const Problem& pr) {
  const GaSettings& g = pr.ga;
  char settings[512];
  std::snprintf(settings, sizeof settings, "seed=%llu population=%d exhaustive=%d %s %.17g %s %.17g %.17g %s %d",
                static_cast<unsigned long long>(g.seed), g.population, pr.exhaustive ? 1 : 0, g.crossover.c_str(),
                g.crossover_probability, g.mutation.c_str(), g.mutation_probability, g.mutation_width,
                g.selection.c_str(), g.selection_size);
  std::string data = pr.text + '\0' + pr.scene_text + '\0' + settings;
  if (!pr.evaluation.target.empty()) data += std::string(1, '\0') + "target=" + pr.evaluation.target;
  Sha256 sha;
  sha.update(data.data(), data.size());
  return sha.hex();
}

// pagmo minimises
double pagmo_f(const Problem& pr, double fitness) { return pr.objective.maximize ? -fitness : fitness; }

std::string fmt_duration(double s) {
  char b[32];
  if (s < 90) std::snprintf(b, sizeof b, "%.0f s", s);
  else if (s < 5400) std::snprintf(b, sizeof b, "%.0f min", s / 60);
  else std::snprintf(b, sizeof b, "%.1f h", s / 3600);
  return b;
}

// every distinct individual of the genome, in gene order (the last gene fastest)
std::vector<Genes> enumerate_individuals(const Problem& pr) {
  const std::vector<int64_t> up = pr.genome.gene_upper();
  if (pr.genome.gene_space_size() > 2000000)
    throw ProblemError(pr.file + ": 'search: exhaustive' over " + std::to_string(pr.genome.gene_space_size()) +
                       " gene vectors is too many to enumerate (at most 2000000)");
  std::vector<Genes> out;
  std::set<std::string> seen;
  Genes g(up.size(), 0);
  for (;;) {
    if (seen.insert(phenotype_key(pr.genome, decode_genes(pr.genome, g))).second) out.push_back(g);
    size_t k = g.size();
    while (k > 0 && g[k - 1] == up[k - 1]) g[--k] = 0;
    if (k == 0) break;
    ++g[k - 1];
  }
  return out;
}

class Progress {
 public:
  Progress(bool quiet, int last_gen, uint64_t per_gen, uint64_t total, uint64_t done_before)
      : quiet_(quiet), tty_(isatty(2)), last_gen_(last_gen), per_gen_(per_gen), total_(total),
        done_before_(done_before), t0_(Clock::now()) {}
  void update(int gen, uint64_t done_in_gen, uint64_t hits, const BestSoFar& best, bool gen_end) {
    if (quiet_ || (!tty_ && !gen_end)) return;
    const uint64_t total = total_;
    const uint64_t done = per_gen_ * static_cast<uint64_t>(gen) + done_in_gen;
    const double wall = std::chrono::duration<double>(Clock::now() - t0_).count();
    const uint64_t this_session = done > done_before_ ? done - done_before_ : 0;
    std::string eta = "?";
    if (this_session > 0) eta = fmt_duration(wall / static_cast<double>(this_session) * static_cast<double>(total - done));
    char best_s[160] = "none yet";
    if (best.valid) std::snprintf(best_s, sizeof best_s, "%s%.6g (%s)", best.failed ? "failed " : "", best.fitness, best.key.c_str());
    std::fprintf(stderr, "%soptimize: generation %d/%d: %llu/%llu evaluations, %llu cache hits, best %s, ETA %s%s",
                 tty_ ? "\r\033[K" : "", gen, last_gen_, static_cast<unsigned long long>(done),
                 static_cast<unsigned long long>(total), static_cast<unsigned long long>(hits), best_s, eta.c_str(),
                 gen_end ? "\n" : "");
    std::fflush(stderr);
  }

 private:
  bool quiet_, tty_;
  int last_gen_;
  uint64_t per_gen_, total_, done_before_;
  Clock::time_point t0_;
};

void write_text_atomic(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    if (!out) throw std::runtime_error(tmp + ": cannot write");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) throw std::runtime_error(path + ": cannot write");
}

}  // namespace

std::string history_path(const std::string& d) { return d + "/history.csv"; }
std::string checkpoint_path(const std::string& d) { return d + "/checkpoint.json"; }
std::string journal_path(const std::string& d) { return d + "/evaluations.jsonl"; }
std::string best_scene_path(const std::string& d) { return d + "/best.yaml"; }

int last_generation(const Problem& pr) {
  if (!pr.exhaustive) return pr.ga.generations;
  const size_t n = enumerate_individuals(pr).size();
  const size_t np = static_cast<size_t>(pr.ga.population);
  return static_cast<int>((n + np - 1) / np) - 1;
}

EvalTask individual_task(const Problem& pr, const Genes& genes, size_t index) {
  EvalTask t;
  t.index = index;
  t.phenotype = decode_genes(pr.genome, genes);
  t.key = phenotype_key(pr.genome, t.phenotype);
  t.seed = evaluation_seed(pr.ga.seed, t.key);
  return t;
}

std::string best_scene_text(const Problem& pr, const BestSoFar& best) {
  const EvalTask t = individual_task(pr, best.genes, best.individual);
  char head[512];
  std::snprintf(head, sizeof head,
                "# The best individual of the design search '%s' (problem %s, seed %llu):\n"
                "#   %s, fitness %.10g%s, found in generation %d (individual %zu).\n"
                "# Run it with: chainsim run best.yaml\n",
                pr.name.c_str(), pr.file.c_str(), static_cast<unsigned long long>(pr.ga.seed), t.key.c_str(),
                best.fitness, best.failed ? " (failed)" : "", best.generation, best.individual);
  return head + individual_scene_yaml(pr, t.phenotype, t.seed);
}

SearchSummary run_search(const Problem& pr, const SearchOptions& opt, EvaluatorPool& pool) {
  namespace fs = std::filesystem;
  const auto t_start = Clock::now();
  fs::create_directories(opt.out_dir);
  const std::string fp = fingerprint(pr);
  const int last_gen = last_generation(pr);
  const std::vector<Genes> everyone = pr.exhaustive ? enumerate_individuals(pr) : std::vector<Genes>{};

  Checkpoint cp;
  // resuming a search killed before its first generation ended: start it
  // again, with whatever the journal kept
  const bool resume = opt.resume && fs::exists(checkpoint_path(opt.out_dir));
  if (resume) {
    cp = read_checkpoint(checkpoint_path(opt.out_dir));
    if (cp.fingerprint != fp)
      throw CheckpointError(checkpoint_path(opt.out_dir) +
                            ": the search there was started with another problem file, base scene, seed, "
                            "population or GA settings; resume it with the same ones, or use another --out");
  } else if (opt.resume) {
    if (!fs::exists(journal_path(opt.out_dir)))
      throw CheckpointError(checkpoint_path(opt.out_dir) + ": cannot open (no search to resume here)");
  } else if (fs::exists(checkpoint_path(opt.out_dir)) || fs::exists(history_path(opt.out_dir))) {
    throw std::runtime_error(opt.out_dir + " already holds a search: continue it with --resume, or choose another --out");
  } else {
    std::error_code ec;
    fs::remove(journal_path(opt.out_dir), ec);
  }
  write_text_atomic(opt.out_dir + "/problem.yaml", pr.text);

  EvalCache cache(journal_path(opt.out_dir), fp);
  std::vector<std::string> names;
  for (const auto& m : pr.measures) names.push_back(m.name);
  HistoryFile history(history_path(opt.out_dir), names, resume, cp.history_bytes);
  if (resume) cache.restore(cp.cache_keys);

  SgaStepper ga(pr.genome, pr.ga);
  if (resume && !pr.exhaustive) ga.set_population(cp.genes, cp.f);

  SearchSummary sum;
  sum.best = cp.best;
  sum.evaluations = cp.evaluations;
  sum.simulations = cp.simulations;
  sum.cache_hits = cp.cache_hits;
  sum.generations_done = cp.generation;
  const uint64_t per_gen = static_cast<uint64_t>(pr.ga.population);
  const uint64_t total = pr.exhaustive ? everyone.size() : per_gen * static_cast<uint64_t>(last_gen + 1);
  Progress progress(opt.quiet, last_gen, per_gen, total, per_gen * static_cast<uint64_t>(cp.generation + 1));

  for (int gen = cp.generation + 1; gen <= last_gen; ++gen) {
    std::vector<Genes> genes;
    if (pr.exhaustive) {
      const size_t a = static_cast<size_t>(gen) * per_gen, b = std::min(everyone.size(), a + per_gen);
      genes.assign(everyone.begin() + static_cast<long>(a), everyone.begin() + static_cast<long>(b));
    } else {
      genes = gen == 0 ? ga.initial() : ga.offspring(gen);
    }

    // which individuals need a simulation: the first of each key not known
    std::vector<EvalTask> all, tasks;
    std::vector<EvalResult> results(genes.size());
    std::vector<bool> cached(genes.size(), false);
    std::map<std::string, size_t> first;  // key -> first index in this generation
    uint64_t hits_in_gen = 0;
    for (size_t i = 0; i < genes.size(); ++i) {
      all.push_back(individual_task(pr, genes[i], i));
      const std::string& key = all.back().key;
      if (const EvalResult* r = cache.find(key)) {
        results[i] = *r;
        results[i].wall_s = 0;
        cached[i] = true;
      } else if (first.count(key)) {
        cached[i] = true;  // filled in once its first occurrence is evaluated
      } else {
        first[key] = i;
        if (const EvalResult* j = cache.journaled(key)) results[i] = *j;  // simulated before a kill
        else tasks.push_back(all.back());
      }
      hits_in_gen += cached[i];
    }
    uint64_t done_in_gen = genes.size() - tasks.size();
    progress.update(gen, done_in_gen, sum.cache_hits + hits_in_gen, sum.best, false);
    std::vector<EvalResult> fresh;
    const bool ok = pool.evaluate(tasks, &fresh, [&](size_t t, const EvalResult& r) {
      cache.record(tasks[t].key, r);
      ++done_in_gen;
      progress.update(gen, done_in_gen, sum.cache_hits + hits_in_gen, sum.best, false);
    });
    if (!ok) {
      if (!opt.quiet) std::fprintf(stderr, "\n");
      sum.interrupted = true;
      break;
    }
    for (size_t t = 0; t < tasks.size(); ++t) results[tasks[t].index] = fresh[t];
    for (size_t i = 0; i < genes.size(); ++i)
      if (cached[i] && !cache.find(all[i].key)) {
        results[i] = results[first[all[i].key]];
        results[i].wall_s = 0;
      }

    // the generation's rows, in index order; the best so far
    std::vector<double> f;
    for (size_t i = 0; i < genes.size(); ++i) {
      history.append({gen, i, all[i].key, results[i], cached[i]});
      f.push_back(pagmo_f(pr, results[i].fitness));
      const bool better = !sum.best.valid || (sum.best.failed && !results[i].failed) ||
                          (sum.best.failed == results[i].failed &&
                           better_fitness(pr.objective, results[i].fitness, sum.best.fitness));
      if (better) sum.best = {true, gen, i, all[i].key, genes[i], results[i].fitness, results[i].failed};
      cache.commit(all[i].key);
    }
    sum.evaluations += genes.size();
    sum.cache_hits += hits_in_gen;
    sum.simulations += genes.size() - hits_in_gen;
    if (pr.exhaustive) {
      ga.set_population(genes, f);
    } else if (gen == 0) {
      ga.set_population(genes, f);
    } else {
      ga.advance(gen, f);
    }

    cp.fingerprint = fp;
    cp.generation = gen;
    cp.genes = ga.population();
    cp.f = ga.fitness();
    cp.cache_keys = cache.keys();
    cp.history_bytes = history.flush();
    cp.best = sum.best;
    cp.evaluations = sum.evaluations;
    cp.simulations = sum.simulations;
    cp.cache_hits = sum.cache_hits;
    write_text_atomic(best_scene_path(opt.out_dir), best_scene_text(pr, sum.best));
    write_checkpoint(checkpoint_path(opt.out_dir), cp);
    sum.generations_done = gen;
    progress.update(gen, genes.size(), sum.cache_hits, sum.best, true);
  }
  sum.wall_s = std::chrono::duration<double>(Clock::now() - t_start).count();
  return sum;
}

}  // namespace chainsim
