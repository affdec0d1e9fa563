// Many-seed study of `chainsim calibrate` on the synthetic cases
// (synth_cases.h), each seed with its own recording conditions
// (synth_record.h: noise level, load, 200 Hz..2 kHz with jitter, a quarter
// without the current column). Prints the per-case table of
// docs/calibration.md, the targets, a breakdown by condition and the CPU time
// of one calibration, and every run that is not right. Not a ctest (an hour
// of CPU):
//   build/bin/calibration_study [--seeds 10] [--first 100] [--cases REGEX] [--jobs 1] [--plain] [--keep DIR] [--check]
//   [--chainsim PATH]   (a copy of chainsim to study, e.g. while the tree is rebuilt; default: the one built with it)
//   [--reports DIR]     each record's report.json kept as DIR/<case>-<seed>.json, to compare two builds record by record
//   [--generator c]     the held-out study on generator C (synth_c.h), seeds 900-909 unless --first says otherwise:
//                       run once per change of the method and reported, never tuned on (docs/calibration.md)
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>
#include <numeric>
#include <regex>
#include <thread>

#include <unistd.h>

#include "common.h"
#include "determinism/libm_variants.h"
#include "synth_c.h"

namespace {

// one case of the study, whichever generator made it
struct StudyCase {
  std::string name;
  std::vector<std::string> expect;   // what a perfect method names (generator C: per record, Run)
  std::string verdict;
  std::map<std::string, std::string> variant;   // the form expected where it is checked
  size_t hidden = 0;                 // the catalogue effects hidden (1: a single, 2: a pair)
  bool null = false;                 // nothing hidden
};

struct Run {
  size_t c = 0;
  unsigned seed = 0;
  synth::Conditions cond;   // (generator C: its own conditions, summarised in these fields)
  std::vector<std::string> expect;   // what a perfect method answers on this record
  std::string verdict;
  synth::Outcome o;
  double size = -1;   // the weakest hidden effect's size in the record (synth::effect_size; -1: none)
};

std::vector<StudyCase> study_cases_ab() {
  std::vector<StudyCase> v;
  for (const synth::Case& c : synth::cases())
    v.push_back({c.name, c.expect, c.verdict, c.variant, c.expect.size(), c.expect.empty() && c.verdict == "no_missing_effect"});
  return v;
}

std::vector<StudyCase> study_cases_c() {
  std::vector<StudyCase> v;
  for (const synth_c::Case& c : synth_c::cases()) {
    size_t n = 0;
    for (const std::string& e : c.hidden) n += !synth_c::outside_catalogue(e);
    v.push_back({c.name, c.expect, c.verdict, {}, n, c.hidden.empty()});
  }
  return v;
}

// right: exactly the hidden effects and the verdict; outside the catalogue,
// the verdict 'unexplained'
bool right(const Run& r) {
  if (r.verdict == "unexplained") return r.o.report.is_object() && r.o.report["verdict"] == "unexplained";
  return synth::exactly_right(r.expect, r.verdict, r.o);
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& x : v) s += (s.empty() ? "" : " + ") + x;
  return s.empty() ? "-" : s;
}

// the bins of the table by effect size
std::string size_bin(double s) {
  return s < 10 ? "a: below 10" : s < 100 ? "b: 10 to 100" : s < 1000 ? "c: 100 to 1 000" : "d: 1 000 or more";
}

bool has(const std::vector<std::string>& v, const std::string& x) {
  return std::find(v.begin(), v.end(), x) != v.end();
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1) + 0.5))];
}

std::string rate_bin(double hz) { return hz < 400 ? "200-400 Hz" : hz < 900 ? "400-900 Hz" : "0.9-2 kHz"; }

}  // namespace

int main(int argc, char** argv) {
  chainsim::use_baseline_libm("calibration_study", argv);  // the records' bytes as on every CPU
  int seeds = 10, first = -1, jobs = 1;   // first: 100 (A, B), 900 (C)
  char generator = 'a';   // a: generators A and B (synth_cases.h); c: generator C (synth_c.h)
  bool plain = false, check = false;   // check: exit 1 unless every run comes out right
  std::string pattern = ".*", keep;   // keep: a folder where one job's files stay (one job)
  std::string reports;   // a folder where every record's report.json is copied
  std::string exe = CHAINSIM_EXE;
  for (int i = 1; i < argc; ++i) {
    const bool more = i + 1 < argc;
    if (!std::strcmp(argv[i], "--seeds") && more) seeds = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--first") && more) first = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--jobs") && more) jobs = std::max(1, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--cases") && more) pattern = argv[++i];
    else if (!std::strcmp(argv[i], "--plain")) plain = true;
    else if (!std::strcmp(argv[i], "--check")) check = true;
    else if (!std::strcmp(argv[i], "--keep") && more) keep = argv[++i], jobs = 1;
    else if (!std::strcmp(argv[i], "--chainsim") && more) exe = argv[++i];
    else if (!std::strcmp(argv[i], "--reports") && more) reports = argv[++i];
    else if (!std::strcmp(argv[i], "--generator") && more && (!std::strcmp(argv[i + 1], "ab") || !std::strcmp(argv[i + 1], "c")))
      generator = argv[++i][0];
    else {
      // --help, a typo or a missing value: say so rather than start an hour of work
      const bool help = !std::strcmp(argv[i], "--help");
      if (!help) std::fprintf(stderr, "calibration_study: not understood: %s\n", argv[i]);
      std::fprintf(help ? stdout : stderr,
                   "usage: calibration_study [--seeds 10] [--first 100] [--cases REGEX] [--jobs 1] [--plain] "
                   "[--keep DIR] [--check] [--chainsim PATH] [--reports DIR] [--generator ab|c]\n");
      return help ? 0 : 2;
    }
  }
  if (access(exe.c_str(), X_OK) != 0) {
    std::fprintf(stderr, "calibration_study: %s: not an executable chainsim\n", exe.c_str());
    return 2;
  }
  const bool held_out = generator == 'c';
  if (first < 0) first = held_out ? 900 : 100;
  const auto ab_cases = synth::cases();
  const auto c_cases = synth_c::cases();
  const std::vector<StudyCase> cases = held_out ? study_cases_c() : study_cases_ab();
  const std::regex re(pattern);
  std::vector<Run> runs;
  for (size_t c = 0; c < cases.size(); ++c)
    if (std::regex_search(cases[c].name, re))
      for (int s = 0; s < seeds; ++s) {
        Run r;
        r.c = c;
        r.seed = static_cast<unsigned>(first + s);
        r.expect = cases[c].expect;
        r.verdict = cases[c].verdict;
        if (held_out) {
          const synth_c::Conditions k = synth_c::conditions(r.seed);
          r.cond.noise = k.noise, r.cond.jl = k.jl, r.cond.sample_hz = k.sample_hz, r.cond.current = k.current;
        } else {
          r.cond = plain ? synth::plain_conditions() : synth::conditions(r.seed);
        }
        runs.push_back(r);
      }
  if (!keep.empty()) std::filesystem::create_directories(keep);  // the files of the last run stay there
  if (!reports.empty()) std::filesystem::create_directories(reports);
  std::atomic<size_t> next{0};
  std::mutex mu;
  auto worker = [&] {
    const std::string dir = keep.empty() ? synth::make_temp_dir() : keep;
    for (size_t i; (i = next++) < runs.size();) {
      Run& r = runs[i];
      if (held_out) {
        // the record, and what a perfect method answers on it (an effect the
        // record does not show is not expected)
        const synth_c::Answer a = synth_c::write_case(c_cases[r.c], r.seed, dir);
        r.expect = a.expect, r.verdict = a.verdict, r.size = a.weakest;
        r.o = synth::calibrate_files(dir, exe);
      } else {
        r.size = synth::weakest_effect_size(ab_cases[r.c], r.seed, r.cond);
        r.o = synth::calibrate_case(ab_cases[r.c], r.seed, r.cond, dir, exe);
      }
      if (!reports.empty() && std::filesystem::exists(dir + "/out/report.json"))
        std::filesystem::copy_file(dir + "/out/report.json",
                                   reports + "/" + cases[r.c].name + "-" + std::to_string(r.seed) + ".json",
                                   std::filesystem::copy_options::overwrite_existing);
      std::string found = r.o.report.is_object() ? r.o.report["verdict"].get<std::string>() : "error";
      for (const auto& n : r.o.names) found += " " + n + (r.o.variants.count(n) ? "(" + r.o.variants[n] + ")" : "");
      std::lock_guard<std::mutex> lock(mu);
      const double gb = r.o.report.is_object() ? r.o.report["gap_before"].get<double>() : 0.0;
      const double ga = r.o.report.is_object() ? r.o.report["gap_after"].get<double>() : 0.0;
      const std::string size = r.size < 0 ? "" : "; size " + std::to_string(static_cast<long>(std::lround(r.size)));
      const long model_runs = r.o.report.is_object() ? r.o.report["model_runs"].get<long>() : 0;
      const std::string truth = held_out ? " (truth: " + r.verdict + " " + joined(r.expect) + ")" : "";
      std::fprintf(stderr,
                   "%s seed %u [noise %d, load %g, %.0f Hz, %s]: %s%s; gap %.4f -> %.4f; %.1f s CPU, %ld model runs%s\n",
                   cases[r.c].name.c_str(), r.seed, r.cond.noise, r.cond.jl, r.cond.sample_hz,
                   r.cond.current ? "current" : "angle only", found.c_str(), truth.c_str(), gb, ga, r.o.cpu_s,
                   model_runs, size.c_str());
    }
    if (keep.empty()) std::filesystem::remove_all(dir);
  };
  std::vector<std::thread> pool;
  for (int j = 0; j < jobs; ++j) pool.emplace_back(worker);
  for (auto& t : pool) t.join();

  std::printf("| case | runs | named exactly | hidden all named | extra effects | verdict as expected | form right | "
              "median gap before -> after | gap halved when explained | outcomes |\n"
              "|---|---|---|---|---|---|---|---|---|---|\n");
  int single_ok = 0, single_n = 0, pair_ok = 0, pair_n = 0, null_fp = 0, null_n = 0, out_ok = 0, out_n = 0;
  int expl = 0, expl_halved = 0;
  std::map<std::string, std::pair<int, int>> by_cond;   // exactly right over runs, per condition
  std::map<std::string, std::pair<int, int>> by_size;   // the same, per bin of the weakest effect's size
  std::vector<double> cpu, model_runs;   // per calibration: CPU seconds, and the model runs (the same on any machine)
  std::map<std::string, std::vector<double>> cpu_by_rate;
  for (size_t c = 0; c < cases.size(); ++c) {
    const StudyCase& k = cases[c];
    int n = 0, exact = 0, all_named = 0, extra = 0, verdict = 0, form = 0, form_n = 0, halved = 0, n_expl = 0;
    std::vector<double> gb, ga;
    std::map<std::string, int> outcomes;
    for (const Run& r : runs) {
      if (r.c != c) continue;
      ++n;
      cpu.push_back(r.o.cpu_s);
      cpu_by_rate[rate_bin(r.cond.sample_hz)].push_back(r.o.cpu_s);
      if (!r.o.report.is_object()) {
        ++outcomes["error " + std::to_string(r.o.exit_code)];
        continue;
      }
      const nlohmann::json& j = r.o.report;
      model_runs.push_back(j["model_runs"].get<double>());
      std::string key = j["verdict"].get<std::string>();
      for (const auto& e : r.o.names) key += " " + e;
      ++outcomes[key];
      const bool ex = synth::exactly_right(r.expect, r.verdict, r.o);
      exact += ex;
      bool all = true;
      for (const auto& e : r.expect) all = all && has(r.o.names, e);
      all_named += all;
      for (const auto& e : r.o.names) extra += !has(r.expect, e);
      verdict += j["verdict"] == r.verdict;
      for (const auto& [e, v] : k.variant)
        if (r.o.variants.count(e)) ++form_n, form += r.o.variants.at(e) == v;
      gb.push_back(j["gap_before"]);
      ga.push_back(j["gap_after"]);
      if (j["verdict"] == "explained") {
        ++n_expl, ++expl;
        const bool h = j["gap_after"].get<double>() <= 0.5 * j["gap_before"].get<double>();
        halved += h, expl_halved += h;
      }
      if (k.hidden > 0) {
        const std::string conds[] = {"noise " + std::to_string(r.cond.noise), "load " + std::to_string(r.cond.jl),
                                     rate_bin(r.cond.sample_hz), r.cond.current ? "with current" : "angle only"};
        for (const std::string& s : conds) ++by_cond[s].second, by_cond[s].first += ex;
        std::pair<int, int>& b = by_size[size_bin(r.size)];
        ++b.second, b.first += ex;
      }
    }
    if (n == 0) continue;
    if (k.hidden == 1 && k.verdict != "unexplained") single_n += n, single_ok += exact;
    if (k.hidden == 2) pair_n += n, pair_ok += all_named;
    if (k.null) null_n += n, null_fp += n - outcomes["no_missing_effect"];
    if (k.verdict == "unexplained") out_n += n, out_ok += verdict;
    std::string oc;
    for (const auto& [key, m] : outcomes) oc += (oc.empty() ? "" : "; ") + key + ": " + std::to_string(m);
    std::printf("| %s | %d | %d | %s | %d | %d | %s | %.3f -> %.3f | %s | %s |\n", k.name.c_str(), n, exact,
                k.hidden == 0 ? "-" : std::to_string(all_named).c_str(), extra, verdict,
                form_n ? (std::to_string(form) + "/" + std::to_string(form_n)).c_str() : "-", median(gb), median(ga),
                n_expl ? (std::to_string(halved) + "/" + std::to_string(n_expl)).c_str() : "-", oc.c_str());
    std::fflush(stdout);
  }
  std::printf("\nTargets: single effects named exactly %d/%d; pairs both named %d/%d; null data with an effect added "
              "%d/%d; outside the catalogue unexplained %d/%d; gap halved when explained %d/%d\n",
              single_ok, single_n, pair_ok, pair_n, null_fp, null_n, out_ok, out_n, expl_halved, expl);
  std::printf("\nBy condition (cases with hidden effects, named exactly):\n\n| condition | runs | named exactly |\n|---|---|---|\n");
  for (const auto& [k, v] : by_cond) std::printf("| %s | %d | %d (%.0f %%) |\n", k.c_str(), v.second, v.first, 100.0 * v.first / v.second);
  std::printf("\nBy the size of the weakest hidden effect in the record (the likelihood ratio of the effect at its "
              "true value, synth::effect_size), named exactly:\n\n| size | runs | named exactly |\n|---|---|---|\n");
  for (const auto& [k, v] : by_size)
    std::printf("| %s | %d | %d (%.0f %%) |\n", k.substr(3).c_str(), v.second, v.first, 100.0 * v.first / v.second);
  std::printf("\nCPU time of one calibration (s): median %.2f, 90 %% %.2f, max %.2f; <= 10 s: %ld of %zu\n", median(cpu),
              quantile(cpu, 0.9), quantile(cpu, 1.0), std::count_if(cpu.begin(), cpu.end(), [](double x) { return x <= 10; }),
              cpu.size());
  for (const auto& [k, v] : cpu_by_rate)
    std::printf("  %s: median %.2f, max %.2f (%zu runs)\n", k.c_str(), median(v), quantile(v, 1.0), v.size());
  if (!model_runs.empty())
    std::printf("Model runs of one calibration (the work, whatever the machine's speed): median %.0f, 90 %% %.0f, "
                "max %.0f; in all %.0f\n",
                median(model_runs), quantile(model_runs, 0.9), quantile(model_runs, 1.0),
                std::accumulate(model_runs.begin(), model_runs.end(), 0.0));
  // every run that is not right, with what it should have answered
  int wrong = 0;
  for (const Run& r : runs) {
    if (right(r)) continue;
    if (!wrong++)
      std::printf("\nRuns not right:\n\n| case | seed | record | truth | answer | gap before -> after | weakest size |\n"
                  "|---|---|---|---|---|---|---|\n");
    std::string answer = r.o.report.is_object() ? r.o.report["verdict"].get<std::string>() : "error";
    for (const auto& e : r.o.names) answer += " " + e;
    const bool rep = r.o.report.is_object();
    std::printf("| %s | %u | noise %d, load %g, %.0f Hz%s | %s %s | %s | %.4f -> %.4f | %s |\n", cases[r.c].name.c_str(),
                r.seed, r.cond.noise, r.cond.jl, r.cond.sample_hz, r.cond.current ? "" : ", angle only",
                r.verdict.c_str(), joined(r.expect).c_str(), answer.c_str(),
                rep ? r.o.report["gap_before"].get<double>() : 0.0, rep ? r.o.report["gap_after"].get<double>() : 0.0,
                r.size < 0 ? "-" : std::to_string(std::lround(r.size)).c_str());
  }
  if (check && wrong) return 1;
  return 0;
}
