#include "optimize/search.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>

#include "optimize/eval_cache.h"
#include "optimize/history.h"
#include "optimize/output_error.h"
#include "optimize/individual_scene.h"
#include "optimize/sga_stepper.h"
#include "output/sha256.h"
#include "physics/splitmix64.h"

namespace chainsim {

namespace {

using Clock = std::chrono::steady_clock;

// what must not change between a search and its resumption
std::string fingerprint_of(const Problem& pr) {
  const GaSettings& g = pr.ga;
  char settings[512];
  std::snprintf(settings, sizeof settings, "seed=%llu population=%d exhaustive=%d %s %.17g %s %.17g %.17g %s %d",
                static_cast<unsigned long long>(g.seed), g.population, pr.exhaustive ? 1 : 0, g.crossover.c_str(),
                g.crossover_probability, g.mutation.c_str(), g.mutation_probability, g.mutation_width,
                g.selection.c_str(), g.selection_size);
  if (g.islands > 1) {  // one island fingerprints as before
    char isl[96];
    std::snprintf(isl, sizeof isl, " islands=%d every=%d migrants=%d", g.islands, g.migration_every, g.migrants);
    std::strncat(settings, isl, sizeof settings - std::strlen(settings) - 1);
  }
  std::string data = pr.text + '\0' + pr.scene_text + '\0' + settings;
  if (!pr.evaluation.target.empty()) data += std::string(1, '\0') + "target=" + pr.evaluation.target;
  // other programs are another search
  if (!pr.evaluation.firmware_dir.empty()) data += std::string(1, '\0') + "firmware_dir=" + pr.evaluation.firmware_dir;
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
  Progress(bool quiet, int last_gen, uint64_t total, uint64_t done_before)
      : quiet_(quiet), tty_(isatty(2)), last_gen_(last_gen), total_(total), done_before_(done_before),
        t0_(Clock::now()) {}
  // gen: the generation being finished; done: individuals with a result
  void update(int gen, uint64_t done, uint64_t hits, const BestSoFar& best, bool gen_end) {
    if (quiet_ || (!tty_ && !gen_end)) return;
    const double wall = std::chrono::duration<double>(Clock::now() - t0_).count();
    const uint64_t this_session = done > done_before_ ? done - done_before_ : 0;
    std::string eta = "?";
    if (this_session > 0 && done <= total_)
      eta = fmt_duration(wall / static_cast<double>(this_session) * static_cast<double>(total_ - done));
    char best_s[160] = "none yet";
    if (best.valid) std::snprintf(best_s, sizeof best_s, "%s%.6g (%s)", best.failed ? "failed " : "", best.fitness, best.key.c_str());
    std::fprintf(stderr, "%soptimize: generation %d/%d: %llu/%llu evaluations, %llu cache hits, best %s, ETA %s%s",
                 tty_ ? "\r\033[K" : "", std::min(gen, last_gen_), last_gen_, static_cast<unsigned long long>(done),
                 static_cast<unsigned long long>(total_), static_cast<unsigned long long>(hits), best_s, eta.c_str(),
                 gen_end ? "\n" : "");
    std::fflush(stderr);
  }

 private:
  bool quiet_, tty_;
  int last_gen_;
  uint64_t total_, done_before_;
  Clock::time_point t0_;
};

void write_text_atomic(const std::string& path, const std::string& text) { write_file_atomic(path, text); }

}  // namespace

std::string search_fingerprint(const Problem& pr) { return fingerprint_of(pr); }

SearchSummary summary_of(const Checkpoint& cp) {
  SearchSummary s;
  s.best = cp.best;
  s.evaluations = cp.evaluations;
  s.simulations = cp.simulations;
  s.cache_hits = cp.cache_hits;
  s.generations_done = cp.generation;
  s.trials = cp.trials;
  s.trials_note = cp.trials_note;
  return s;
}

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

GaSettings island_ga(const GaSettings& ga, int island) {
  GaSettings g = ga;
  if (island > 0) g.seed = splitmix64(ga.seed ^ splitmix64(0x15A7D5ull + static_cast<uint64_t>(island))) >> 2;
  return g;
}

int trials_for_generation(const Problem& pr, int generation, int decided) {
  if (pr.evaluation.trials > 0) return pr.evaluation.trials;
  return generation == 0 || decided == 0 ? kAutoProbeTrials : decided;
}

int decide_trials(const std::vector<HistoryRow>& gen0, std::string* note) {
  size_t measured = 0;
  for (const HistoryRow& r : gen0) {
    // failed after a passing trial: the verdict itself varied
    if (r.result.failed && r.result.trials >= 2) {
      *note = "trials: auto: an individual passed a trial and failed a later one in generation 0 (" + r.genome + ": " +
              r.result.why + "), so every individual runs " + std::to_string(kAutoProbeTrials) + " trials";
      return kAutoProbeTrials;
    }
    if (r.result.failed || r.result.trials < 2) continue;
    ++measured;
    if (r.result.fitness_min != r.result.fitness_max) {
      char b[512];
      std::snprintf(b, sizeof b,
                    "trials: auto: the fitness varied between an individual's trials in generation 0 (%s: %.6g .. "
                    "%.6g over %d trials), so every individual runs %d trials",
                    r.genome.c_str(), r.result.fitness_min, r.result.fitness_max, r.result.trials, kAutoProbeTrials);
      *note = b;
      return kAutoProbeTrials;
    }
  }
  if (measured == 0) {  // no evidence either way: keep measuring
    *note = "trials: auto: no individual of generation 0 passed its trials, so nothing showed whether the seed "
            "matters; every individual runs " + std::to_string(kAutoProbeTrials) + " trials";
    return kAutoProbeTrials;
  }
  char b[256];
  std::snprintf(b, sizeof b,
                "trials: auto: no individual's fitness varied between its %d trials in generation 0 (%zu measured), "
                "so from generation 1 on each runs once",
                kAutoProbeTrials, measured);
  *note = b;
  return 1;
}

std::string best_scene_text(const Problem& pr, const BestSoFar& best, const std::string& more) {
  const EvalTask t = individual_task(pr, best.genes, best.individual);
  char head[512];
  std::snprintf(head, sizeof head,
                "# The best individual of the design search '%s' (problem %s, seed %llu):\n"
                "#   %s, fitness %.10g%s, found in generation %d (island %d, individual %zu).\n"
                "# Run it with: chainsim run best.yaml\n",
                pr.name.c_str(), pr.file.c_str(), static_cast<unsigned long long>(pr.ga.seed), t.key.c_str(),
                best.fitness, best.failed ? " (failed)" : "", best.generation, best.island, best.individual);
  return head + more + individual_scene_yaml(pr, t.phenotype, t.seed);
}

namespace {

// one individual of an island's generation
struct Slot {
  Genes genes;
  EvalTask task;
  bool have = false;
  EvalResult result;
};

struct Island {
  std::unique_ptr<SgaStepper> ga;
  int produced = -1;                               // the last generation made
  int done = -1;                                   // the last generation scored and the GA advanced
  std::map<int, std::vector<Slot>> inflight;       // generation -> its individuals
  std::map<int, Checkpoint::Island> snaps;         // the population after generation g
  // finished generations, not yet written: each row with its individual's genes
  std::map<int, std::vector<std::pair<HistoryRow, Genes>>> rows;
};

// a checkpoint that does not fit the problem is damaged, whatever its
// fingerprint says: refused field by field, naming the file
void validate_checkpoint(const Checkpoint& cp, const Problem& pr, int n_islands, int last_gen, const std::string& path) {
  auto bad = [&](const std::string& what) { throw CheckpointError(path + ": damaged: " + what); };
  if (cp.generation < 0 || cp.generation > last_gen)
    bad("generation " + std::to_string(cp.generation) + " is not one of the search's 0.." + std::to_string(last_gen));
  if (static_cast<int>(cp.islands.size()) != n_islands)
    bad(std::to_string(cp.islands.size()) + " islands, the problem has " + std::to_string(n_islands));
  const std::vector<int64_t> up = pr.genome.gene_upper();
  for (size_t i = 0; i < cp.islands.size(); ++i) {
    const Checkpoint::Island& is = cp.islands[i];
    const size_t want = pr.exhaustive ? is.genes.size() : static_cast<size_t>(pr.ga.population);
    if (is.genes.size() != want || is.genes.empty())
      bad("island " + std::to_string(i) + " has " + std::to_string(is.genes.size()) + " individuals, the population is " +
          std::to_string(pr.ga.population));
    for (const Genes& g : is.genes) {
      if (g.size() != up.size())
        bad("an individual of island " + std::to_string(i) + " has " + std::to_string(g.size()) + " genes, the genome " +
            std::to_string(up.size()));
      for (size_t k = 0; k < g.size(); ++k)
        if (g[k] < 0 || g[k] > up[k])
          bad("gene " + std::to_string(k) + " = " + std::to_string(g[k]) + " of an individual of island " +
              std::to_string(i) + " is outside 0.." + std::to_string(up[k]));
    }
  }
  if (cp.trials < 0 || cp.trials > 1000) bad("trials = " + std::to_string(cp.trials));
  const uint64_t rows_at_least = static_cast<uint64_t>(cp.generation + 1);
  if (cp.evaluations < rows_at_least || cp.simulations + cp.cache_hits != cp.evaluations)
    bad("its counts of evaluations (" + std::to_string(cp.evaluations) + "), simulations and cache hits do not add up");
  if (cp.history_bytes == 0) bad("history_bytes is 0 after generation " + std::to_string(cp.generation));
  if (cp.best.valid && cp.best.genes.size() != up.size()) bad("the best's genes do not fit the genome");
}

}  // namespace

void migrate_best(const Checkpoint::Island& src, int m, Checkpoint::Island* dst) {
  std::vector<size_t> best(src.f.size()), worst(dst->f.size());
  for (size_t i = 0; i < best.size(); ++i) best[i] = i;
  for (size_t i = 0; i < worst.size(); ++i) worst[i] = i;
  std::stable_sort(best.begin(), best.end(), [&](size_t a, size_t b) { return src.f[a] < src.f[b]; });
  std::stable_sort(worst.begin(), worst.end(), [&](size_t a, size_t b) { return dst->f[a] > dst->f[b]; });
  size_t w = 0;
  for (int k = 0; k < m && static_cast<size_t>(k) < best.size() && w < worst.size(); ++k) {
    const size_t b = best[static_cast<size_t>(k)];
    bool there = false;
    for (const auto& g : dst->genes) there |= g == src.genes[b];
    if (there || !(src.f[b] < dst->f[worst[w]])) continue;
    dst->genes[worst[w]] = src.genes[b];
    dst->f[worst[w]] = src.f[b];
    ++w;
  }
}


SearchSummary run_search(const Problem& pr, const SearchOptions& opt, EvaluatorPool& pool) {
  namespace fs = std::filesystem;
  const auto t_start = Clock::now();
  fs::create_directories(opt.out_dir);
  const std::string fp = fingerprint_of(pr);
  const int last_gen = last_generation(pr);
  const std::vector<Genes> everyone = pr.exhaustive ? enumerate_individuals(pr) : std::vector<Genes>{};
  const int n_islands = pr.exhaustive ? 1 : pr.ga.islands;

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
    validate_checkpoint(cp, pr, n_islands, last_gen, checkpoint_path(opt.out_dir));
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
  if (resume) {  // history.csv must be what the checkpoint says it wrote
    std::ifstream in(history_path(opt.out_dir), std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (text.size() < cp.history_bytes)
      throw CheckpointError(history_path(opt.out_dir) + ": shorter (" + std::to_string(text.size()) +
                            " bytes) than the checkpoint says (" + std::to_string(cp.history_bytes) + "): cannot resume");
    text.resize(cp.history_bytes);
    std::vector<HistoryRow> rows;
    try {
      rows = parse_history(text, names.size(), history_path(opt.out_dir));
    } catch (const std::exception& e) {
      throw CheckpointError(std::string(e.what()) + ": cannot resume");
    }
    bool in_order = !rows.empty() && rows.front().generation == 0;
    for (size_t i = 1; i < rows.size() && in_order; ++i)
      in_order = rows[i].generation == rows[i - 1].generation || rows[i].generation == rows[i - 1].generation + 1;
    if (!in_order || rows.size() != cp.evaluations || rows.back().generation != cp.generation)
      throw CheckpointError(history_path(opt.out_dir) + ": its " + std::to_string(rows.size()) +
                            " rows up to the checkpoint do not match " + checkpoint_path(opt.out_dir) + " (" +
                            std::to_string(cp.evaluations) + " evaluations to generation " +
                            std::to_string(cp.generation) + "): cannot resume");
  }
  HistoryFile history(history_path(opt.out_dir), names, resume, cp.history_bytes);
  if (resume) cache.restore(cp.cache_keys);

  std::vector<Island> islands(static_cast<size_t>(n_islands));
  for (int i = 0; i < n_islands; ++i) {
    Island& is = islands[static_cast<size_t>(i)];
    is.ga = std::make_unique<SgaStepper>(pr.genome, island_ga(pr.ga, i));
    is.produced = is.done = cp.generation;
    if (resume) {
      const Checkpoint::Island& c = cp.islands[static_cast<size_t>(i)];
      is.ga->set_population(c.genes, c.f);
      is.snaps[cp.generation] = c;
    }
  }

  SearchSummary sum = summary_of(cp);
  const uint64_t per_gen = static_cast<uint64_t>(pr.ga.population) * static_cast<uint64_t>(n_islands);
  const uint64_t total = pr.exhaustive ? everyone.size() : per_gen * static_cast<uint64_t>(last_gen + 1);
  const uint64_t done_before = pr.exhaustive ? std::min<uint64_t>(everyone.size(), per_gen * static_cast<uint64_t>(cp.generation + 1))
                                             : per_gen * static_cast<uint64_t>(cp.generation + 1);
  Progress progress(opt.quiet, last_gen, total, done_before);
  uint64_t scored = done_before;     // rows with a result, written or not

  // simulations in flight: id -> key; key -> the slots waiting for it
  struct Waiter {
    int island, generation;
    size_t slot;
  };
  std::map<uint64_t, std::string> flying;
  std::map<std::string, std::vector<Waiter>> waiting;
  uint64_t next_id = 0;
  size_t next_index = 0;            // run directories: unique per task
  // how far an exhaustive search queues ahead (the pool's parallelism grows as MPI ranks say hello)
  auto lookahead = [&] {
    return static_cast<size_t>(4 * std::max(1, pool.parallelism())) + static_cast<size_t>(pr.ga.population);
  };

  auto fill = [&](const Waiter& w, const EvalResult& r) {
    Slot& s = islands[static_cast<size_t>(w.island)].inflight.at(w.generation)[w.slot];
    if (!s.have) ++scored;
    s.have = true;
    s.result = r;
  };

  auto produce = [&](int i, int g) {
    Island& is = islands[static_cast<size_t>(i)];
    std::vector<Genes> genes;
    if (pr.exhaustive) {
      const size_t a = static_cast<size_t>(g) * static_cast<size_t>(pr.ga.population);
      const size_t b = std::min(everyone.size(), a + static_cast<size_t>(pr.ga.population));
      genes.assign(everyone.begin() + static_cast<long>(a), everyone.begin() + static_cast<long>(b));
    } else if (g == 0) {
      genes = is.ga->initial();
    } else {
      const int after = g - 1;
      if (n_islands > 1 && after > 0 && after % pr.ga.migration_every == 0) {
        const int src = (i + n_islands - 1) % n_islands;
        Checkpoint::Island pop = is.snaps.at(after);
        migrate_best(islands[static_cast<size_t>(src)].snaps.at(after), pr.ga.migrants, &pop);
        is.ga->set_population(pop.genes, pop.f);
      }
      genes = is.ga->offspring(g);
    }
    std::vector<Slot>& slots = is.inflight[g];
    slots.resize(genes.size());
    const int trials = trials_for_generation(pr, g, sum.trials);
    for (size_t k = 0; k < genes.size(); ++k) {
      Slot& s = slots[k];
      s.genes = genes[k];
      s.task = individual_task(pr, genes[k], next_index++);
      s.task.trials = trials;
      const std::string& key = s.task.key;
      if (const EvalResult* j = cache.journaled(key)) {  // simulated before (this search, or before a kill)
        s.have = true;
        s.result = *j;
        ++scored;
      } else if (waiting.count(key)) {
        waiting[key].push_back({i, g, k});
      } else {
        waiting[key].push_back({i, g, k});
        flying[next_id] = key;
        pool.submit(next_id++, s.task);
      }
    }
    is.produced = g;
  };

  auto can_produce = [&](int i) {
    const Island& is = islands[static_cast<size_t>(i)];
    const int g = is.produced + 1;
    if (g > last_gen) return false;
    if (g >= 1 && pr.evaluation.trials == 0 && sum.trials == 0) return false;  // trials: auto waits for generation 0
    if (pr.exhaustive) return pool.pending() < lookahead();
    if (is.done != g - 1) return false;
    const int after = g - 1;
    if (n_islands > 1 && after > 0 && after % pr.ga.migration_every == 0)
      return islands[static_cast<size_t>((i + n_islands - 1) % n_islands)].done >= after;
    return true;
  };

  // an island's generation whose individuals all have results: the GA moves on
  auto finish = [&](int i, int g) {
    Island& is = islands[static_cast<size_t>(i)];
    std::vector<Slot>& slots = is.inflight.at(g);
    std::vector<Genes> genes;
    std::vector<double> f;
    auto& rows = is.rows[g];
    for (size_t k = 0; k < slots.size(); ++k) {
      genes.push_back(slots[k].genes);
      f.push_back(pagmo_f(pr, slots[k].result.fitness));
      HistoryRow row;
      row.generation = g;
      row.island = i;
      row.individual = k;
      row.genome = slots[k].task.key;
      row.result = slots[k].result;
      rows.emplace_back(row, slots[k].genes);
    }
    if (pr.exhaustive || g == 0) is.ga->set_population(genes, f);
    else is.ga->advance(g, f);
    is.snaps[g] = {is.ga->population(), is.ga->fitness()};
    is.done = g;
    is.inflight.erase(g);
  };

  // every island has generation g: its rows in island and index order, the
  // best, the cache, best.yaml and the checkpoint
  auto write_generation = [&](int g) {
    uint64_t hits = 0;
    std::vector<HistoryRow> all;
    for (int i = 0; i < n_islands; ++i) {
      Island& is = islands[static_cast<size_t>(i)];
      for (auto& [row, genes] : is.rows.at(g)) {
        row.cached = cache.find(row.genome) != nullptr;
        if (row.cached) row.result.wall_s = 0;
        hits += row.cached;
        history.append(row);
        const EvalResult& r = row.result;
        const bool better = !sum.best.valid || (sum.best.failed && !r.failed) ||
                            (sum.best.failed == r.failed && better_fitness(pr.objective, r.fitness, sum.best.fitness));
        if (better) sum.best = {true, g, i, row.individual, row.genome, genes, r.fitness, r.failed};
        cache.commit(row.genome);
        all.push_back(row);
      }
      is.rows.erase(g);
    }
    sum.evaluations += all.size();
    sum.cache_hits += hits;
    sum.simulations += all.size() - hits;
    if (g == 0 && pr.evaluation.trials == 0 && sum.trials == 0) {
      sum.trials = decide_trials(all, &sum.trials_note);
      if (!opt.quiet) std::fprintf(stderr, "optimize: %s\n", sum.trials_note.c_str());
    }
    cp.fingerprint = fp;
    cp.generation = g;
    cp.islands.clear();
    for (auto& is : islands) {
      cp.islands.push_back(is.snaps.at(g));
      for (auto it = is.snaps.begin(); it != is.snaps.end() && it->first < g;) it = is.snaps.erase(it);
    }
    cp.trials = sum.trials;
    cp.trials_note = sum.trials_note;
    cp.cache_keys = cache.keys();
    cp.history_bytes = history.flush();
    cp.best = sum.best;
    cp.evaluations = sum.evaluations;
    cp.simulations = sum.simulations;
    cp.cache_hits = sum.cache_hits;
    write_text_atomic(best_scene_path(opt.out_dir), best_scene_text(pr, sum.best));
    write_checkpoint(checkpoint_path(opt.out_dir), cp);
    sum.generations_done = g;
  };

  std::vector<std::pair<uint64_t, EvalResult>> done;
  while (sum.generations_done < last_gen) {
    for (int i = 0; i < n_islands; ++i)
      while (can_produce(i)) produce(i, islands[static_cast<size_t>(i)].produced + 1);
    done.clear();
    if (!pool.poll(0.5, &done) || interrupt_signal()) {
      // a signal to the whole job (Ctrl-C, scancel) ends the runs too: what
      // they returned is not theirs to record
      if (!opt.quiet) std::fprintf(stderr, "\n");
      sum.interrupted = true;
      break;
    }
    for (auto& [id, r] : done) {
      const std::string key = flying.at(id);
      flying.erase(id);
      if (r.infra)  // no verdict on the design: nothing is recorded; the pool's destructor ends the rest
        throw InfrastructureError("the evaluation of " + key + " could not be done: " + r.why +
                                      ". That is a fault of the machine, not of the design: nothing was recorded "
                                      "for it; the search stops after generation " +
                                      std::to_string(sum.generations_done) + " (fix it and continue with --resume)",
                                  r.why.find("disk") != std::string::npos);
      cache.record(key, r);
      sum.busy_s += r.wall_s;
      for (const Waiter& w : waiting.at(key)) fill(w, r);
      waiting.erase(key);
    }
    for (int i = 0; i < n_islands; ++i) {
      Island& is = islands[static_cast<size_t>(i)];
      for (;;) {
        auto it = is.inflight.find(is.done + 1);
        if (it == is.inflight.end()) break;
        bool complete = true;
        for (const Slot& s : it->second) complete &= s.have;
        if (!complete) break;
        finish(i, is.done + 1);
      }
    }
    for (;;) {
      const int g = sum.generations_done + 1;
      bool all_done = g <= last_gen;
      for (const auto& is : islands) all_done &= is.done >= g;
      if (!all_done) break;
      write_generation(g);
      progress.update(g, scored, sum.cache_hits, sum.best, true);
    }
    progress.update(sum.generations_done + 1, scored, sum.cache_hits, sum.best, false);
  }
  sum.wall_s = std::chrono::duration<double>(Clock::now() - t_start).count();
  return sum;
}

}  // namespace chainsim
