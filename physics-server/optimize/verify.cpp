#include "optimize/verify.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include "optimize/history.h"
#include "optimize/individual_scene.h"
#include "optimize/search.h"
#include "text/number_text.h"

namespace chainsim {

namespace {

// fitness ± sd (n trials), or the failure
std::string result_text(const EvalResult& r) {
  if (r.failed) return "fails: " + r.why;
  std::string t = general_text(r.fitness);
  if (r.trials > 1 && std::isfinite(r.fitness_sd)) t += " ± " + general_text(r.fitness_sd);
  return t + " (" + std::to_string(r.trials) + (r.trials == 1 ? " trial)" : " trials)");
}

bool leader_before(const Problem& pr, const HistoryRow& a, const HistoryRow& b) {
  if (a.result.failed != b.result.failed) return !a.result.failed;
  return better_fitness(pr.objective, a.result.fitness, b.result.fitness);
}

}  // namespace

std::vector<HistoryRow> leaders(const Problem& pr, const std::vector<HistoryRow>& rows, size_t k) {
  std::vector<HistoryRow> d;
  std::set<std::string> seen;
  for (const HistoryRow& r : rows)
    if (seen.insert(r.genome).second) d.push_back(r);
  std::stable_sort(d.begin(), d.end(), [&](const HistoryRow& a, const HistoryRow& b) { return leader_before(pr, a, b); });
  if (d.size() > k) d.resize(k);
  return d;
}

std::string noise_warning(const Problem& pr, const std::vector<HistoryRow>& top) {
  std::vector<const HistoryRow*> ok;
  for (const HistoryRow& r : top)
    if (!r.result.failed) ok.push_back(&r);
  if (ok.size() < 2) return "";
  bool spread_known = true;
  for (const HistoryRow* r : ok) spread_known &= r->result.trials > 1 && std::isfinite(r->result.fitness_sd);
  if (!spread_known) {
    if (pr.evaluation.trials == 1)
      return "one trial per individual (evaluation.trials: 1): how much the fitness varies from seed to seed is not "
             "known, so neither is whether the ranking is; trials: auto measures it";
    return "";
  }
  auto se = [](const HistoryRow* r) { return r->result.fitness_sd / std::sqrt(static_cast<double>(r->result.trials)); };
  size_t n = 1;
  for (size_t k = 1; k < ok.size(); ++k) {
    const double gap = std::fabs(ok[0]->result.fitness - ok[k]->result.fitness);
    const double noise = 2 * std::sqrt(se(ok[0]) * se(ok[0]) + se(ok[k]) * se(ok[k]));
    if (gap < noise) n = k + 1;
  }
  if (n < 2) return "";
  char b[512];
  std::snprintf(b, sizeof b,
                "the ranking of the top %zu is within the noise: their fitnesses (%s .. %s) differ by less than twice "
                "the standard error of their trials (the best: sd %s over %d trials); raise evaluation.trials, or "
                "trust the verification's fresh seeds",
                n, general_text(ok[0]->result.fitness).c_str(), general_text(ok[n - 1]->result.fitness).c_str(),
                general_text(ok[0]->result.fitness_sd).c_str(), ok[0]->result.trials);
  return b;
}

std::vector<std::string> verdict_flags(const VerifiedLeader& v) {
  std::vector<std::string> f;
  const bool search_pass = !v.search.result.failed, fresh_pass = !v.fresh.failed;
  if (search_pass && !fresh_pass) f.push_back("passed in the search, fails with fresh seeds (" + v.fresh.why + ")");
  if (!search_pass && fresh_pass) f.push_back("failed in the search (" + v.search.result.why + "), passes with fresh seeds");
  if (v.has_exact && fresh_pass && v.exact.failed)
    f.push_back("passes with QuickStep, fails with the solver converged (" + v.exact.why +
                "): the verdict rests on the fast solver's give");
  if (v.has_exact && !fresh_pass && !v.exact.failed) f.push_back("fails with QuickStep, passes with the solver converged");
  if (v.has_pic && fresh_pass && v.pic.failed) f.push_back("passes native, fails on the board's binaries (" + v.pic.why + ")");
  if (v.has_pic && !fresh_pass && !v.pic.failed) f.push_back("fails native, passes on the board's binaries");
  return f;
}

bool verify_leaders(const Problem& pr, const std::vector<HistoryRow>& top, const VerifySettings& st,
                    EvaluatorPool& pool, Verification* out, bool quiet) {
  out->leaders.clear();
  out->best = -1;
  int search_trials = 1;
  for (const HistoryRow& r : top) search_trials = std::max(search_trials, r.result.trials);
  out->fresh_trials = st.trials > 0 ? st.trials : std::max(3, search_trials);
  std::vector<EvalTask> tasks;
  struct Where {
    size_t leader;
    int what;  // 0 fresh, 1 exact, 2 pic
  };
  std::vector<Where> where;
  size_t index = 1000000;  // run directories apart from the search's (--keep-runs)
  for (size_t l = 0; l < top.size(); ++l) {
    VerifiedLeader v;
    v.search = top[l];
    out->leaders.push_back(v);
    EvalTask t;
    t.phenotype = phenotype_from_key(pr.genome, top[l].genome);
    t.key = top[l].genome;
    t.seed = evaluation_seed(pr.ga.seed, t.key);
    t.trials = out->fresh_trials;
    t.first_trial = kFreshTrial;
    t.index = index++;
    tasks.push_back(t);
    where.push_back({l, 0});
    if (st.exact) {
      EvalTask e = t;
      e.index = index++;
      e.solver = "exact";
      tasks.push_back(e);
      where.push_back({l, 1});
    }
    if (st.pic) {
      EvalTask p = t;
      p.index = index++;
      p.trials = 1;
      p.target = "pic";
      tasks.push_back(p);
      where.push_back({l, 2});
    }
  }
  if (!quiet)
    std::fprintf(stderr, "optimize: verifying the %zu best: %d fresh trials each%s%s (%zu runs of tasks)\n", top.size(),
                 out->fresh_trials, st.exact ? ", again with the exact solver" : "",
                 st.pic ? ", once on the board's binaries" : "", tasks.size());
  std::vector<EvalResult> results;
  size_t finished = 0;
  const bool ok = pool.evaluate(tasks, &results, [&](size_t, const EvalResult&) {
    ++finished;
    if (!quiet) std::fprintf(stderr, "optimize: verification %zu/%zu\n", finished, tasks.size());
  });
  if (!ok) return false;
  for (size_t i = 0; i < tasks.size(); ++i)
    if (results[i].infra)
      throw InfrastructureError("verifying " + tasks[i].key + ": " + results[i].why +
                                    " (a fault of the machine; verify again with chainsim optimize --verify)",
                                results[i].why.find("disk") != std::string::npos);
  for (size_t i = 0; i < tasks.size(); ++i) {
    VerifiedLeader& v = out->leaders[where[i].leader];
    if (where[i].what == 0) v.fresh = results[i];
    if (where[i].what == 1) {
      v.exact = results[i];
      v.has_exact = true;
    }
    if (where[i].what == 2) {
      v.pic = results[i];
      v.has_pic = true;
    }
  }
  for (size_t l = 0; l < out->leaders.size(); ++l) {
    VerifiedLeader& v = out->leaders[l];
    v.flags = verdict_flags(v);
    if (v.fresh.failed || v.search.result.failed) continue;  // best.yaml: a leader that passed both
    if (out->best < 0 ||
        better_fitness(pr.objective, v.fresh.fitness, out->leaders[static_cast<size_t>(out->best)].fresh.fitness))
      out->best = static_cast<int>(l);
  }
  return true;
}

std::string verification_csv(const Verification& v) {
  std::string s =
      "rank,genome,search_fitness,search_sd,search_trials,search_fault,fresh_fitness,fresh_sd,fresh_min,fresh_max,"
      "fresh_trials,fresh_fault,exact_fitness,exact_sd,exact_fault,pic_fitness,pic_fault,flags,verified_best\n";
  for (size_t l = 0; l < v.leaders.size(); ++l) {
    const VerifiedLeader& x = v.leaders[l];
    const EvalResult& r = x.search.result;
    std::string flags;
    for (const auto& f : x.flags) flags += (flags.empty() ? "" : "; ") + f;
    s += std::to_string(l + 1) + "," + csv_field(x.search.genome) + "," + history_number(r.fitness) + "," +
         history_number(r.fitness_sd) + "," + std::to_string(r.trials) + "," + csv_field(r.why) + "," +
         history_number(x.fresh.fitness) + "," + history_number(x.fresh.fitness_sd) + "," +
         history_number(x.fresh.fitness_min) + "," + history_number(x.fresh.fitness_max) + "," +
         std::to_string(x.fresh.trials) + "," + csv_field(x.fresh.why) + "," +
         (x.has_exact ? history_number(x.exact.fitness) : "") + "," +
         (x.has_exact ? history_number(x.exact.fitness_sd) : "") + "," + (x.has_exact ? csv_field(x.exact.why) : "") +
         "," + (x.has_pic ? history_number(x.pic.fitness) : "") + "," + (x.has_pic ? csv_field(x.pic.why) : "") + "," +
         csv_field(flags) + "," + (static_cast<int>(l) == v.best ? "yes" : "no") + "\n";
  }
  return s;
}

nlohmann::json verification_json(const Verification& v) {
  nlohmann::json a = nlohmann::json::array();
  for (const VerifiedLeader& x : v.leaders) {
    nlohmann::json j = {{"genome", x.search.genome},
                        {"search", eval_result_to_json(x.search.result)},
                        {"fresh", eval_result_to_json(x.fresh)},
                        {"flags", x.flags}};
    j["search_text"] = result_text(x.search.result);
    j["fresh_text"] = result_text(x.fresh);
    if (x.has_exact) {
      j["exact"] = eval_result_to_json(x.exact);
      j["exact_text"] = result_text(x.exact);
    }
    if (x.has_pic) {
      j["pic"] = eval_result_to_json(x.pic);
      j["pic_text"] = result_text(x.pic);
    }
    a.push_back(j);
  }
  return {{"fresh_trials", v.fresh_trials},
          {"leaders", a},
          {"verified_best", v.best >= 0 ? nlohmann::json(v.leaders[static_cast<size_t>(v.best)].search.genome)
                                        : nlohmann::json(nullptr)}};
}

}  // namespace chainsim
