// `chainsim optimize` end to end: the GA finds what enumeration finds; the
// history is the same with 1 and 2 local workers and under mpirun; a search
// killed mid-generation and resumed ends as an uninterrupted one; a crashing
// module is a failed individual, not a failed search; a rank killed under
// mpirun is named and its work done by another.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "optimize_problems.h"
#include "scenario_util.h"

using optimize_test::history_without_wall;
using optimize_test::write_problem;

namespace {

struct Proc {
  pid_t pid = -1;
  std::string err_path;
};

// starts argv with stderr to err_path (stdout too); fsize_limit > 0: a
// file-size limit (as ulimit -f) for it and its children, a full disk in small
Proc start(const std::vector<std::string>& args, const std::string& err_path, long fsize_limit = 0) {
  std::vector<std::string> all = args;
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, 1);
    dup2(fd, 2);
    setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    if (fsize_limit > 0) {
      const struct rlimit lim = {static_cast<rlim_t>(fsize_limit), static_cast<rlim_t>(fsize_limit)};
      setrlimit(RLIMIT_FSIZE, &lim);
    }
    execv(argv[0], argv.data());
    _exit(127);
  }
  return {pid, err_path};
}

// waits (killing after timeout_s); the exit code, -signal when killed
int wait_for(const Proc& p, double timeout_s = 240) {
  const auto t0 = std::chrono::steady_clock::now();
  int st = 0;
  while (waitpid(p.pid, &st, WNOHANG) == 0) {
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > timeout_s) {
      kill(p.pid, SIGKILL);
      waitpid(p.pid, &st, 0);
      ADD_FAILURE() << "timed out; its output:\n" << scenario::read_file(p.err_path);
      return -SIGKILL;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return WIFEXITED(st) ? WEXITSTATUS(st) : -WTERMSIG(st);
}

// a search with no replay and (unless verify) no verification of its winners
std::vector<std::string> optimize_args(const std::string& problem, const std::string& out,
                                       const std::vector<std::string>& more, bool verify = false) {
  std::vector<std::string> a{CHAINSIM_EXE, "optimize", problem, "--out", out, "--no-replay"};
  if (!verify) a.insert(a.end(), {"--verify-top", "0"});
  a.insert(a.end(), more.begin(), more.end());
  return a;
}

// runs a search to the end; its stderr
std::string search(const std::vector<std::string>& args, const std::string& err_path, int expect_rc = 0) {
  const Proc p = start(args, err_path);
  const int rc = wait_for(p);
  const std::string err = scenario::read_file(err_path);
  EXPECT_EQ(rc, expect_rc) << err;
  return err;
}

std::vector<std::string> mpirun(int np, const std::vector<std::string>& cmd, bool recovery) {
  std::vector<std::string> a{MPIEXEC, "--oversubscribe", "--allow-run-as-root", "-np", std::to_string(np)};
  if (recovery) a.insert(a.end(), {"--enable-recovery", "--mca", "orte_abort_on_non_zero_status", "0"});
  a.insert(a.end(), cmd.begin(), cmd.end());
  return a;
}

// a best.yaml without its comment header (which names the problem file's path)
std::string scene_part(const std::string& best_yaml) {
  std::string out, l;
  std::istringstream in(best_yaml);
  while (std::getline(in, l))
    if (l.rfind("#", 0) != 0) out += l + "\n";
  return out;
}

// the reference: the gait problem with population 4, 3 generations, 1 worker
struct Reference {
  std::string dir, history, best;
};
const Reference& reference() {
  static const Reference r = [] {
    Reference ref;
    ref.dir = scenario::temp_dir("opt-ref");
    const std::string p = write_problem(ref.dir, "gait");
    search(optimize_args(p, ref.dir + "/out", {"--workers", "1", "--population", "4", "--generations", "3"}),
           ref.dir + "/err.txt");
    ref.history = history_without_wall(ref.dir + "/out/history.csv");
    ref.best = scene_part(scenario::read_file(ref.dir + "/out/best.yaml"));
    return ref;
  }();
  return r;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string l;
  while (std::getline(in, l)) out.push_back(l);
  return out;
}

// the chainsim process of rank r among mpirun's children
pid_t rank_pid(pid_t mpirun_pid, int r) {
  for (pid_t c : scenario::children_of(mpirun_pid)) {
    const std::string env = scenario::read_file("/proc/" + std::to_string(c) + "/environ");
    if (env.find(std::string("OMPI_COMM_WORLD_RANK=") + std::to_string(r) + '\0') != std::string::npos) return c;
  }
  return -1;
}

}  // namespace

TEST(Optimize, TheGaFindsTheEnumeratedOptimum) {
  const std::string d = scenario::temp_dir("opt-enum");
  const std::string p = write_problem(d, "gait");
  search(optimize_args(p, d + "/all", {"--exhaustive", "--workers", "2", "--population", "9"}), d + "/all.txt");
  search(optimize_args(p, d + "/ga", {"--workers", "2"}), d + "/ga.txt");
  const auto all = lines(history_without_wall(d + "/all/history.csv"));
  ASSERT_EQ(all.size(), 1u + 27u);  // every individual once
  // the enumerated optimum
  std::string best_key;
  double best = -1e300;
  for (size_t i = 1; i < all.size(); ++i) {
    std::vector<std::string> f;
    std::stringstream s(all[i]);
    std::string x;
    while (std::getline(s, x, ',')) f.push_back(x);
    if (std::stod(f[4]) > best) {
      best = std::stod(f[4]);
      best_key = f[3];
    }
  }
  // the GA's best, from its best.yaml header, and where it found it
  const std::string ga_best = scenario::read_file(d + "/ga/best.yaml");
  EXPECT_NE(ga_best.find("#   " + best_key + ", fitness"), std::string::npos) << ga_best << "\nenumerated: " << best_key;
  const std::string ga_hist = scenario::read_file(d + "/ga/history.csv");
  size_t in_gen0 = 0;
  for (const auto& l : lines(ga_hist))
    if (l.rfind("0,", 0) == 0 && l.find("," + best_key + ",") != std::string::npos) ++in_gen0;
  EXPECT_EQ(in_gen0, 0u) << "the optimum was in the random initial population: the test shows nothing about the GA";
  // the GA simulated fewer individuals than there are
  const auto ga_rows = lines(ga_hist);
  size_t simulated = 0;
  for (size_t i = 1; i < ga_rows.size(); ++i) simulated += ga_rows[i].find(",no,") != std::string::npos;
  EXPECT_LT(simulated, 27u);
  EXPECT_EQ(ga_rows.size(), 1u + 6u * 8u);
}

TEST(Optimize, TheHistoryIsTheSameWithOneAndTwoWorkersAndUnderMpirun) {
  const Reference& ref = reference();
  const std::string d = scenario::temp_dir("opt-workers");
  const std::string p = write_problem(d, "gait");
  const std::vector<std::string> gens{"--population", "4", "--generations", "3"};
  std::vector<std::string> two = gens;
  two.insert(two.end(), {"--workers", "2"});
  search(optimize_args(p, d + "/two", two), d + "/two.txt");
  EXPECT_EQ(history_without_wall(d + "/two/history.csv"), ref.history);
  EXPECT_EQ(scene_part(scenario::read_file(d + "/two/best.yaml")), ref.best);
  const std::string err = search(mpirun(3, optimize_args(p, d + "/mpi", gens), false), d + "/mpi.txt");
  EXPECT_NE(err.find("2 MPI worker ranks"), std::string::npos) << err;
  EXPECT_EQ(history_without_wall(d + "/mpi/history.csv"), ref.history);
  EXPECT_EQ(scene_part(scenario::read_file(d + "/mpi/best.yaml")), ref.best);
  EXPECT_EQ(lines(ref.history).size(), 1u + 4u * 4u);
}

TEST(Optimize, ResumeAfterSigkillMidGenerationEqualsAnUninterruptedSearch) {
  const Reference& ref = reference();
  const std::string d = scenario::temp_dir("opt-resume");
  const std::string p = write_problem(d, "gait");
  const std::string out = d + "/out";
  const Proc proc = start(optimize_args(p, out, {"--workers", "1", "--population", "4", "--generations", "3"}),
                          d + "/first.txt");
  // kill it when generation 1 is done and generation 2 has simulated some but not all
  bool mid = scenario::wait_until(
      [&] {
        const nlohmann::json cp = nlohmann::json::parse(scenario::read_file(out + "/checkpoint.json"), nullptr, false);
        if (!cp.is_object() || cp.value("generation", -1) < 1) return false;
        const size_t journaled = lines(scenario::read_file(out + "/evaluations.jsonl")).size() - 1;  // a header
        return journaled > cp["cache_keys"].size();
      },
      120);
  kill(proc.pid, SIGKILL);
  wait_for(proc);
  ASSERT_TRUE(mid) << scenario::read_file(d + "/first.txt");
  const nlohmann::json cp = nlohmann::json::parse(scenario::read_file(out + "/checkpoint.json"));
  ASSERT_LT(cp["generation"].get<int>(), 3) << "the search ended before it was killed";
  const std::string err = search(optimize_args(p, out, {"--workers", "2", "--resume", "--population", "4",
                                                        "--generations", "3"}),
                                 d + "/second.txt");
  EXPECT_EQ(history_without_wall(out + "/history.csv"), ref.history);
  EXPECT_EQ(scene_part(scenario::read_file(out + "/best.yaml")), ref.best);
  // no chainsim run left behind by the kill
  EXPECT_EQ(scenario::children_of(proc.pid).size(), 0u);
  // and a second start without --resume refuses to overwrite it
  const std::string again = search(optimize_args(p, out, {"--population", "4"}), d + "/third.txt", 1);
  EXPECT_NE(again.find("already holds a search: continue it with --resume"), std::string::npos) << again;
}

TEST(Optimize, ResumeBeforeTheFirstGenerationEndedStartsOverAndKeepsTheJournal) {
  const Reference& ref = reference();
  const std::string d = scenario::temp_dir("opt-resume0");
  const std::string p = write_problem(d, "gait");
  const std::string out = d + "/out";
  const std::vector<std::string> gens{"--population", "4", "--generations", "3"};
  std::vector<std::string> one = gens;
  one.insert(one.end(), {"--workers", "1"});
  const Proc proc = start(optimize_args(p, out, one), d + "/first.txt");
  const bool some = scenario::wait_until(
      [&] { return lines(scenario::read_file(out + "/evaluations.jsonl")).size() >= 2; }, 120);
  kill(proc.pid, SIGKILL);
  wait_for(proc);
  ASSERT_TRUE(some) << scenario::read_file(d + "/first.txt");
  ASSERT_FALSE(std::filesystem::exists(out + "/checkpoint.json")) << "generation 0 ended before the kill";
  std::vector<std::string> resume = gens;
  resume.push_back("--resume");
  search(optimize_args(p, out, resume), d + "/second.txt");
  EXPECT_EQ(history_without_wall(out + "/history.csv"), ref.history);
}

TEST(Optimize, AnIndividualWhoseModuleCrashesGetsTheFailedFitnessAndTheSearchGoesOn) {
  const std::string d = scenario::temp_dir("opt-fault");
  const std::string p = write_problem(d, "fault");
  search(optimize_args(p, d + "/out", {"--workers", "2"}), d + "/err.txt");
  const auto rows = lines(scenario::read_file(d + "/out/history.csv"));
  ASSERT_EQ(rows.size(), 1u + 4u * 3u);
  int crashed = 0, fine = 0;
  for (size_t i = 1; i < rows.size(); ++i) {
    if (rows[i].find("chain[1].mode=2") != std::string::npos) {
      ++crashed;
      EXPECT_NE(rows[i].find(",-1,"), std::string::npos) << rows[i];  // the failed fitness
      EXPECT_NE(rows[i].find("module 1 (rotation) ended: signal 11 (Segmentation fault); backtrace in modules/01-rotation.out at t=0.151000 s"), std::string::npos) << rows[i];
    } else {
      ++fine;
      EXPECT_EQ(rows[i].find("ended: signal"), std::string::npos) << rows[i];
    }
  }
  EXPECT_GT(crashed, 0);
  EXPECT_GT(fine, 0);
  EXPECT_NE(scenario::read_file(d + "/out/best.yaml").find("chain[1].mode=0"), std::string::npos);
}

TEST(Optimize, MalformedProblemFilesGiveFileLineColumn) {
  const std::string d = scenario::temp_dir("opt-bad");
  write_problem(d, "gait");
  const std::string p = scenario::write_file(d, "bad.yaml",
                                             "scene: base.yaml\ngenome:\n  params:\n"
                                             "    - {target: central.amplitude_cdeg, min: 1000, max: 5000, stpe: 2}\n");
  const std::string err = search({CHAINSIM_EXE, "optimize", p, "--out", d + "/out"}, d + "/err.txt", 1);
  EXPECT_NE(err.find(p + ":4:62: unknown key 'stpe' in 'genome.params[0]' (known: max, min, step, target)"),
            std::string::npos)
      << err;
  EXPECT_FALSE(std::filesystem::exists(d + "/out/history.csv"));
  // a gene whose range leaves the declared one, and a gene of a parameter the program does not declare:
  // named at the gene before any evaluation runs
  const std::string wide = scenario::write_file(d, "wide.yaml",
                                                "scene: base.yaml\ngenome:\n  params:\n"
                                                "    - {target: central.amplitude_cdeg, min: 1000, max: 19000, step: 2000}\n"
                                                "measures: {speed: {kind: speed, of: chain}}\nobjective: {maximize: speed}\n");
  const std::string err2 = search({CHAINSIM_EXE, "optimize", wide, "--out", d + "/out2"}, d + "/err2.txt", 1);
  EXPECT_NE(err2.find(wide + ":4:7: 'central.amplitude_cdeg' ranges over 1000..19000, beyond the range 0..18000 that "
                             "program fw-central of the central control declares (amplitude A of the wave, cdeg)"),
            std::string::npos)
      << err2;
  const std::string typo = scenario::write_file(d, "typo.yaml",
                                                "scene: base.yaml\ngenome:\n  params:\n"
                                                "    - {target: central.omega_mrad, min: 1000, max: 9000, step: 2000}\n"
                                                "measures: {speed: {kind: speed, of: chain}}\nobjective: {maximize: speed}\n");
  const std::string err3 = search({CHAINSIM_EXE, "optimize", typo, "--out", d + "/out3"}, d + "/err3.txt", 1);
  EXPECT_NE(err3.find(typo + ":4:7: 'central.omega_mrad': program fw-central of the central control declares no "
                             "parameter 'omega_mrad' (did you mean 'omega_mrad_s'?"),
            std::string::npos)
      << err3;
  EXPECT_FALSE(std::filesystem::exists(d + "/out2/history.csv"));
  // a gene of a program that lists no parameters (not linked with hal-sim): named at the gene
  const std::string silent = scenario::write_file(d, "silent.sh", "#!/bin/sh\nexit 0\n");
  std::filesystem::permissions(silent, std::filesystem::perms::owner_all);
  scenario::write_file(d, "base-silent.yaml",
                       "name: opt-silent\nduration_s: 0.4\nchain:\n  - {type: rotation}\n"
                       "  - {type: rotation, firmware: ./silent.sh}\n");
  const std::string gene = scenario::write_file(d, "silent.yaml",
                                                "scene: base-silent.yaml\ngenome:\n  params:\n"
                                                "    - {target: \"chain[1].speed\", min: 1, max: 3, step: 1}\n"
                                                "measures: {speed: {kind: speed, of: chain}}\nobjective: {maximize: speed}\n");
  const std::string err4 = search({CHAINSIM_EXE, "optimize", gene, "--out", d + "/out4"}, d + "/err4.txt", 1);
  EXPECT_NE(err4.find(gene + ":4:7: 'chain[1].speed': program " + silent + " did not list its parameters: it printed "
                              "nothing instead of the line"),
            std::string::npos)
      << err4;
  EXPECT_FALSE(std::filesystem::exists(d + "/out4/history.csv"));
}

// runs of 3 s: with the 0.4 s runs of the other tests an evaluation could end,
// and the search with it, between the moment rank 2 was seen busy and its kill
TEST(Optimize, ARankKilledUnderMpirunIsNamedAndItsWorkDoneByAnother) {
  const std::string d = scenario::temp_dir("opt-rankkill");
  const std::string p = write_problem(d, "gait-long");
  const std::vector<std::string> ga = {"--population", "4", "--generations", "3"};
  std::vector<std::string> local = ga;
  local.insert(local.end(), {"--workers", "2"});
  search(optimize_args(p, d + "/uninterrupted", local), d + "/uninterrupted.txt");
  const std::string uninterrupted = history_without_wall(d + "/uninterrupted/history.csv");
  // rank 2 killed while it runs an evaluation. On a loaded machine the kill
  // can land after that evaluation's result has gone and the search has
  // ended (a rank that dies with nothing left to do loses nothing): then the
  // case did not happen and it is tried again, at most three times
  std::string err, out;
  pid_t victim = -1;
  int rc = -1;
  for (int attempt = 0; attempt < 3; ++attempt) {
    out = d + "/out" + std::to_string(attempt);
    const Proc proc = start(mpirun(3, optimize_args(p, out, ga), true), d + "/err.txt");
    const bool busy = scenario::wait_until(
        [&] {
          // mid-simulation: its evaluation's module processes are running
          // (a finished evaluation can stay a child for a moment after its
          // result has gone)
          victim = rank_pid(proc.pid, 2);
          if (victim <= 0) return false;
          for (pid_t c : scenario::children_of(victim))
            if (!scenario::children_of(c).empty()) return true;
          return false;
        },
        60);
    ASSERT_TRUE(busy) << scenario::read_file(d + "/err.txt");
    kill(victim, SIGKILL);
    rc = wait_for(proc);
    err = scenario::read_file(d + "/err.txt");
    if (err.find("optimize: rank 2 (pid ") != std::string::npos) break;
    std::fprintf(stderr, "attempt %d: the search ended before rank 2's death was seen; again\n", attempt + 1);
  }
  EXPECT_EQ(rc, 0) << err;
  EXPECT_NE(err.find("optimize: rank 2 (pid " + std::to_string(victim) + " on "), std::string::npos) << err;
  EXPECT_NE(err.find(") has died; its evaluation of central."), std::string::npos) << err;
  EXPECT_NE(err.find(" goes to another rank"), std::string::npos) << err;
  EXPECT_EQ(history_without_wall(out + "/history.csv"), uninterrupted);
}

// --target pic: every evaluation on the board's binaries (docs/pic-in-the-loop.md)
TEST(Optimize, TargetPicEvaluatesOnTheBoardsBinaries) {
  const std::string exe = CHAINSIM_EXE;
  const std::string pic = exe.substr(0, exe.rfind('/')) + "/../pic/fw-rotation.hex";
  if (access(pic.c_str(), R_OK) != 0 || access((exe.substr(0, exe.rfind('/')) + "/chainsim-pic").c_str(), X_OK) != 0)
    GTEST_SKIP() << "the PIC build is missing (" << pic << "): run tools/pic-build.sh, as tools/test-all.sh does";
  const std::string d = scenario::temp_dir("opt-pic");
  const std::string p = write_problem(d, "gait");
  search(optimize_args(p, d + "/pic", {"--workers", "2", "--population", "4", "--generations", "0", "--target", "pic",
                                       "--keep-runs"}),
         d + "/pic.txt");
  const auto rows = lines(history_without_wall(d + "/pic/history.csv"));
  ASSERT_EQ(rows.size(), 1u + 4u);
  EXPECT_NE(scenario::read_file(d + "/pic/best.yaml").find("target: pic"), std::string::npos);
  // every evaluation ran its programs on the PIC
  int runs = 0;
  for (const auto& e : std::filesystem::recursive_directory_iterator(d + "/pic/work")) {
    if (e.path().filename() != "summary.json") continue;
    std::ifstream f(e.path());
    const auto s = nlohmann::json::parse(f);
    for (const auto& m : s["modules"]) EXPECT_EQ(m["target"], "pic") << e.path();
    ++runs;
  }
  EXPECT_EQ(runs, 4);
}

namespace {

// history.csv's rows as fields (a genome has no comma)
std::vector<std::vector<std::string>> history_fields(const std::string& path) {
  std::vector<std::vector<std::string>> out;
  const auto ls = lines(scenario::read_file(path));
  for (size_t i = 1; i < ls.size(); ++i) {
    std::vector<std::string> f;
    std::string x;
    bool quoted = false;
    for (char c : ls[i]) {
      if (c == '"') quoted = !quoted;
      if (c == ',' && !quoted) {
        f.push_back(x);
        x.clear();
      } else {
        x += c;
      }
    }
    f.push_back(x);
    out.push_back(f);
  }
  return out;
}

// columns of history.csv: generation, island, individual, genome, fitness, trials, fitness_sd, ...
enum { kGen = 0, kIsland = 1, kGenome = 3, kFitness = 4, kTrials = 5, kSd = 6, kMin = 7, kMax = 8 };

}  // namespace

// trials: auto runs generation 0 three times over; when an individual's
// fitness differs between its seeds every later one runs three times too,
// and with a solver that no seed changes they run once
TEST(Optimize, TrialsAutoMeasuresTheSpreadAndKeepsTrialsOnlyWhenTheFitnessVaries) {
  const std::string d = scenario::temp_dir("opt-auto");
  const std::vector<std::string> small{"--workers", "2", "--population", "4", "--generations", "1"};
  const std::string err = search(optimize_args(write_problem(d, "gait-auto"), d + "/auto", small), d + "/auto.txt");
  EXPECT_NE(err.find("trials: auto: the fitness varied between an individual's trials in generation 0"),
            std::string::npos)
      << err;
  const auto rows = history_fields(d + "/auto/history.csv");
  ASSERT_EQ(rows.size(), 8u);
  for (const auto& r : rows) {
    EXPECT_EQ(r[kTrials], "3") << r[kGenome];
    EXPECT_FALSE(r[kSd].empty()) << r[kGenome];
    EXPECT_LE(std::stod(r[kMin]), std::stod(r[kFitness]));
    EXPECT_GE(std::stod(r[kMax]), std::stod(r[kFitness]));
  }
  const std::string ex = search(optimize_args(write_problem(d, "gait-exact"), d + "/exact", small), d + "/exact.txt");
  EXPECT_NE(ex.find("trials: auto: no individual's fitness varied between its 3 trials in generation 0 (4 measured)"),
            std::string::npos)
      << ex;
  const auto exact = history_fields(d + "/exact/history.csv");
  ASSERT_EQ(exact.size(), 8u);
  for (const auto& r : exact) {
    const bool cached = r[13] == "yes";  // (a cache hit keeps the trials it was run with)
    if (!cached) {
      EXPECT_EQ(r[kTrials], r[kGen] == "0" ? "3" : "1") << r[kGenome];
    }
    if (r[kGen] == "0") {
      EXPECT_EQ(r[kSd], "0") << r[kGenome];
    }
  }
  // the report shows the spread beside the fitness
  EXPECT_NE(scenario::read_file(d + "/auto/report.html").find("<th>sd</th>"), std::string::npos);
}

// the winners run again with fresh seeds and the exact solver (and on the
// board when its binaries are built); best.yaml is the best of them with
// fresh seeds; --verify DIR verifies a finished search again, the same way
TEST(Optimize, TheWinnersAreVerifiedWithFreshSeedsTheExactSolverAndTheBoard) {
  const std::string d = scenario::temp_dir("opt-verify");
  const std::string p = write_problem(d, "gait");
  const std::string out = d + "/out";
  const std::string err = search(optimize_args(p, out, {"--workers", "2", "--population", "4", "--generations", "1",
                                                        "--verify-top", "2"},
                                               true),
                                 d + "/err.txt");
  EXPECT_NE(err.find("optimize: verifying the 2 best: 3 fresh trials each, again with the exact solver"),
            std::string::npos)
      << err;
  const auto v = lines(scenario::read_file(out + "/verify.csv"));
  ASSERT_EQ(v.size(), 3u) << scenario::read_file(out + "/verify.csv");
  EXPECT_EQ(v[0].rfind("rank,genome,search_fitness,search_sd,search_trials,search_fault,fresh_fitness", 0), 0u);
  const nlohmann::json j = nlohmann::json::parse(scenario::read_file(out + "/verify.json"));
  ASSERT_EQ(j["leaders"].size(), 2u);
  int best = -1;
  double best_fresh = -1e300;
  for (size_t l = 0; l < 2; ++l) {
    const auto& x = j["leaders"][l];
    EXPECT_EQ(x["fresh"]["trials"], 3);
    EXPECT_EQ(x["exact"]["trials"], 3);
    // fresh seeds are not the search's: the fitness differs from the search's one run
    EXPECT_NE(x["fresh"]["fitness"], x["search"]["fitness"]);
    if (x["fresh"]["fitness"].get<double>() > best_fresh) {
      best_fresh = x["fresh"]["fitness"].get<double>();
      best = static_cast<int>(l);
    }
  }
  ASSERT_GE(best, 0);
  EXPECT_EQ(j["verified_best"], j["leaders"][best]["genome"]);
  const std::string best_yaml = scenario::read_file(out + "/best.yaml");
  EXPECT_NE(best_yaml.find("#   " + j["verified_best"].get<std::string>() + ", fitness"), std::string::npos) << best_yaml;
  EXPECT_NE(best_yaml.find("# Verified: the best of the search's 2 leaders with 3 fresh seeds"), std::string::npos);
  EXPECT_NE(scenario::read_file(out + "/report.html").find("<h2>Verification</h2>"), std::string::npos);
  const std::string exe = CHAINSIM_EXE;
  const bool pic = access((exe.substr(0, exe.rfind('/')) + "/../pic/fw-rotation.hex").c_str(), R_OK) == 0;
  EXPECT_EQ(j["leaders"][0].contains("pic"), pic);
  // verified again on demand: the same table
  const std::string first = scenario::read_file(out + "/verify.csv");
  std::filesystem::remove(out + "/verify.csv");
  search({CHAINSIM_EXE, "optimize", "--verify", out, "--verify-top", "2", "--no-replay"}, d + "/again.txt");
  EXPECT_EQ(scenario::read_file(out + "/verify.csv"), first);
  // a directory with no search is named
  const std::string none = search({CHAINSIM_EXE, "optimize", "--verify", d}, d + "/none.txt", 1);
  EXPECT_NE(none.find("--verify: " + d + "/search.json: cannot open"), std::string::npos) << none;
}

// a time_to_reach constraint's max ends the runs that cannot meet it there,
// says so in history.csv, and changes no verdict and no fitness
TEST(Optimize, AConstraintThatCanNoLongerBeMetEndsTheRunAndChangesNoVerdict) {
  const std::string d = scenario::temp_dir("opt-stop");
  const std::vector<std::string> all{"--exhaustive", "--workers", "2", "--population", "9"};
  search(optimize_args(write_problem(d, "stop"), d + "/stop", all), d + "/stop.txt");
  search(optimize_args(write_problem(d, "stop-off"), d + "/off", all), d + "/off.txt");
  const auto on = history_fields(d + "/stop/history.csv"), off = history_fields(d + "/off/history.csv");
  ASSERT_EQ(on.size(), 27u);
  ASSERT_EQ(off.size(), 27u);
  const size_t fault = 11, early = 12;  // the fixed columns, x, t, then fault and early_stop
  int stopped = 0, passed = 0;
  for (size_t i = 0; i < on.size(); ++i) {
    EXPECT_EQ(on[i][kGenome], off[i][kGenome]);
    EXPECT_EQ(on[i][fault].empty(), off[i][fault].empty()) << on[i][kGenome];  // the same verdict
    EXPECT_TRUE(off[i][early].empty());
    if (on[i][fault].empty()) {
      ++passed;
      EXPECT_EQ(on[i][kFitness], off[i][kFitness]) << on[i][kGenome];  // a run that passes runs to the end
      EXPECT_TRUE(on[i][early].empty());
    } else {
      ++stopped;
      EXPECT_EQ(on[i][fault], "constraint: t = inf > 0.3");
      EXPECT_EQ(on[i][early].rfind("\"early stop at 0.320 s: the tail got no further than ", 0), 0u) << on[i][early];
    }
  }
  EXPECT_GT(stopped, 0);
  EXPECT_GT(passed, 0);
  EXPECT_EQ(scene_part(scenario::read_file(d + "/stop/best.yaml")).find("not_reached") != std::string::npos, true);
}

// islands: two populations of 4 with migration every generation; the same
// history with one worker, two, and under mpirun, and a migrant is seen
TEST(Optimize, IslandsGiveTheSameHistoryWhateverTheWorkersAndMigrate) {
  const std::string d = scenario::temp_dir("opt-islands");
  const std::string p = write_problem(d, "gait");
  std::string text = scenario::read_file(p);
  text.replace(text.find("ga: {population: 6, generations: 7, seed: 1}"), 44,
               "ga: {population: 4, generations: 3, seed: 1, islands: 2, migration_every: 1, migrants: 1}");
  const std::string isl = scenario::write_file(d, "islands.yaml", text);
  search(optimize_args(isl, d + "/one", {"--workers", "1"}), d + "/one.txt");
  search(optimize_args(isl, d + "/two", {"--workers", "2"}), d + "/two.txt");
  const std::string err = search(mpirun(3, optimize_args(isl, d + "/mpi", {}), false), d + "/mpi.txt");
  const std::string one = history_without_wall(d + "/one/history.csv");
  EXPECT_EQ(history_without_wall(d + "/two/history.csv"), one);
  EXPECT_EQ(history_without_wall(d + "/mpi/history.csv"), one);
  const auto rows = history_fields(d + "/one/history.csv");
  ASSERT_EQ(rows.size(), 4u * 2u * 4u);  // generations x islands x population
  // generation order, then island order
  for (size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i][kGen], std::to_string(i / 8));
    EXPECT_EQ(rows[i][kIsland], std::to_string((i / 4) % 2));
  }
  // the islands started apart: generation 0's populations differ
  std::set<std::string> g0_a, g0_b;
  for (size_t i = 0; i < 8; ++i) (i < 4 ? g0_a : g0_b).insert(rows[i][kGenome]);
  EXPECT_NE(g0_a, g0_b);
}

// the scheduler on simulated cores (chainsim bench-search): evaluations sleep
// a real search's recorded times; the history is the same whatever the
// number of cores, and every row of the table is there (its busy fractions
// are wall-clock figures: printed, not asserted)
TEST(Optimize, TheSchedulerOnSimulatedCoresGivesTheSameHistoryWhateverTheCores) {
  const std::string d = scenario::temp_dir("opt-bench-search");
  const std::string p = write_problem(d, "gait");
  search(optimize_args(p, d + "/all", {"--exhaustive", "--workers", "2", "--population", "9"}), d + "/all.txt");
  const auto [out, rc] = scenario::chainsim_stdout("bench-search " + p + " --history " + d + "/all/history.csv" +
                                                   " --cores 1 4 64 --islands 1 3 --generations 4 --scale 0.2");
  ASSERT_EQ(rc, 0) << out;
  std::map<std::string, std::set<std::string>> hashes;  // islands -> history hashes over the core counts
  int rows = 0;
  for (const auto& l : lines(out)) {
    if (l.empty() || l[0] == '#' || l.find("cores") != std::string::npos) continue;
    std::istringstream f(l);
    std::string cores, islands, population, evaluations, simulated, busy, wall, ideal, hash;
    ASSERT_TRUE(static_cast<bool>(f >> cores >> islands >> population >> evaluations >> simulated >> busy >> wall >> ideal >> hash)) << l;
    EXPECT_EQ(std::stoi(evaluations), std::stoi(islands) * 6 * 5) << l;  // islands x population x generations
    EXPECT_GT(std::stod(busy), 0.0) << l;
    EXPECT_LE(std::stod(busy), 1.0 + 1e-9) << l;
    hashes[islands].insert(hash);
    ++rows;
  }
  EXPECT_EQ(rows, 6) << out;
  ASSERT_EQ(hashes.size(), 2u) << out;
  for (const auto& [islands, h] : hashes) EXPECT_EQ(h.size(), 1u) << islands << " islands: " << out;

  // times only (--times): the recorded wall times with synthetic results, for
  // populations other than the recorded search's; the history is again the
  // same whatever the cores
  const auto [t_out, t_rc] = scenario::chainsim_stdout("bench-search " + p + " --times " + d + "/all/history.csv" +
                                                       " --cores 2 16 --islands 2 --population 7 --generations 2 "
                                                       "--scale 0.05");
  ASSERT_EQ(t_rc, 0) << t_out;
  EXPECT_NE(t_out.find("# results: synthetic"), std::string::npos) << t_out;
  std::set<std::string> t_hashes;
  for (const auto& l : lines(t_out)) {
    if (l.empty() || l[0] == '#' || l.find("cores") != std::string::npos) continue;
    std::istringstream f(l);
    std::string cores, islands, population, evaluations, simulated, busy, wall, ideal, hash;
    ASSERT_TRUE(static_cast<bool>(f >> cores >> islands >> population >> evaluations >> simulated >> busy >> wall >> ideal >> hash)) << l;
    EXPECT_EQ(population, "7") << l;
    EXPECT_EQ(std::stoi(evaluations), 2 * 7 * 3) << l;
    t_hashes.insert(hash);
  }
  EXPECT_EQ(t_hashes.size(), 1u) << t_out;
}

// a fault of the machine is no verdict on a design: a run that cannot write
// its files (a file-size limit, as a full disk) or an evaluator killed from
// outside stops the search with the reason, exit 5 or 3, and nothing
// recorded for that individual; --resume then ends as the uninterrupted search
TEST(Optimize, AFaultOfTheMachineStopsTheSearchRecordsNothingAndResumeRedoesIt) {
  const Reference& ref = reference();
  const std::string d = scenario::temp_dir("opt-infra");
  const std::string p = write_problem(d, "gait");
  const std::string out = d + "/out";
  const std::vector<std::string> gens{"--workers", "1", "--population", "4", "--generations", "3"};
  // 12 KB: history.csv and the journal fit, a run's trace.csv (18 KB) does not
  const Proc full = start(optimize_args(p, out, gens), d + "/full.txt", 12 * 1024);
  EXPECT_EQ(wait_for(full), 5);
  const std::string err = scenario::read_file(d + "/full.txt");
  EXPECT_NE(err.find("could not be done: the run could not write its files"), std::string::npos) << err;
  EXPECT_NE(err.find("is the disk under --out full?"), std::string::npos) << err;
  EXPECT_NE(err.find("a fault of the machine, not of the design: nothing was recorded"), std::string::npos) << err;
  EXPECT_EQ(lines(scenario::read_file(out + "/evaluations.jsonl")).size(), 1u);  // the fingerprint, no result
  EXPECT_EQ(scenario::children_of(full.pid).size(), 0u);
  // an evaluator killed from outside, in a search with 3 s runs
  const std::string lp = write_problem(d, "gait-long");
  const std::string out2 = d + "/killed";
  const Proc proc = start(optimize_args(lp, out2, {"--workers", "1", "--population", "4", "--generations", "0"}),
                          d + "/killed.txt");
  pid_t evaluator = -1;
  ASSERT_TRUE(scenario::wait_until(
      [&] {
        for (pid_t c : scenario::children_of(proc.pid))
          if (scenario::read_file("/proc/" + std::to_string(c) + "/comm").rfind("chainsim-evalua", 0) == 0) {
            evaluator = c;
            return true;
          }
        return false;
      },
      60));
  kill(evaluator, SIGKILL);
  EXPECT_EQ(wait_for(proc), 3);
  const std::string killed = scenario::read_file(d + "/killed.txt");
  EXPECT_NE(killed.find("the evaluator was ended by signal 9 (Killed) from outside"), std::string::npos) << killed;
  // resumed, without the limit: the uninterrupted search's history and best
  search(optimize_args(p, out, {"--workers", "2", "--resume", "--population", "4", "--generations", "3"}),
         d + "/resume.txt");
  EXPECT_EQ(history_without_wall(out + "/history.csv"), ref.history);
  EXPECT_EQ(scene_part(scenario::read_file(out + "/best.yaml")), ref.best);
}

// with the documented recovery options mpirun exits 0 whatever its ranks do;
// rank 0 of a search that did not finish ends its mpirun so that it does not
TEST(Optimize, AnUnfinishedSearchUnderMpirunWithRecoveryExitsNonZero) {
  const std::string d = scenario::temp_dir("opt-mpi-rc");
  write_problem(d, "gait");
  const std::string bad = scenario::write_file(d, "bad.yaml", "scene: base.yaml\n");
  const std::string err = search(mpirun(2, {CHAINSIM_EXE, "optimize", bad, "--out", d + "/out"}, true), d + "/err.txt", 1);
  EXPECT_NE(err.find("missing key 'genome'"), std::string::npos) << err;
  EXPECT_NE(err.find("ending mpirun"), std::string::npos) << err;
}

// one process per search directory: a second one (a resume, a verification)
// on a directory in use is refused with the holder's pid, and writes nothing
TEST(Optimize, ASecondProcessOnASearchDirectoryInUseIsRefused) {
  const std::string d = scenario::temp_dir("opt-lock");
  const std::string lp = write_problem(d, "gait-long");
  const std::string out = d + "/out";
  const Proc first = start(optimize_args(lp, out, {"--workers", "1", "--population", "4", "--generations", "0"}),
                           d + "/first.txt");
  ASSERT_TRUE(scenario::wait_until([&] { return std::filesystem::exists(out + "/evaluations.jsonl"); }, 60));
  const std::string second = search(optimize_args(lp, out, {"--resume", "--population", "4", "--generations", "0"}),
                                    d + "/second.txt", 1);
  EXPECT_NE(second.find(out + " is in use by another chainsim optimize (pid " + std::to_string(first.pid) + ")"),
            std::string::npos)
      << second;
  const std::string verify = search({CHAINSIM_EXE, "optimize", "--verify", out}, d + "/verify.txt", 1);
  EXPECT_NE(verify.find("is in use by another chainsim optimize"), std::string::npos) << verify;
  kill(first.pid, SIGTERM);
  EXPECT_EQ(wait_for(first), 130);
  // the holder gone, its lock is gone with it
  search(optimize_args(lp, out, {"--resume", "--workers", "2", "--population", "4", "--generations", "0"}),
         d + "/third.txt");
}

// a checkpoint or history that does not fit the search is refused by name
// before anything runs, and nothing is changed
TEST(Optimize, ADamagedCheckpointOrHistoryIsRefusedByNameBeforeAResume) {
  const std::string d = scenario::temp_dir("opt-damaged");
  const std::string p = write_problem(d, "gait");
  const std::string out = d + "/out";
  const std::vector<std::string> gens{"--workers", "2", "--population", "4", "--generations", "1"};
  search(optimize_args(p, out, gens), d + "/first.txt");
  const std::string cp_text = scenario::read_file(out + "/checkpoint.json");
  const std::string history = scenario::read_file(out + "/history.csv");
  std::vector<std::string> resume = gens;
  resume.push_back("--resume");
  resume[resume.size() - 2] = "3";  // --generations 3: there is more to do
  const std::vector<std::pair<std::function<void(nlohmann::json&)>, std::string>> damage = {
      {[](nlohmann::json& j) { j["generation"] = 7; }, "damaged: generation 7 is not one of the search's 0..3"},
      {[](nlohmann::json& j) { j["generation"] = -7; }, "damaged: generation -7"},
      {[](nlohmann::json& j) { j["islands"][0]["genes"][1][0] = 99; }, "is outside 0..2"},
      {[](nlohmann::json& j) {
         j["islands"][0]["genes"].erase(0);
         j["islands"][0]["f"].erase(0);
       },
       "island 0 has 3 individuals, the population is 4"},
      {[](nlohmann::json& j) { j["history_bytes"] = 0; }, "history_bytes is 0"},
      {[](nlohmann::json& j) { j["evaluations"] = 5; }, "do not add up"},
  };
  for (const auto& [hurt, said] : damage) {
    nlohmann::json j = nlohmann::json::parse(cp_text);
    hurt(j);
    std::ofstream(out + "/checkpoint.json") << j.dump(1);
    const std::string err = search(optimize_args(p, out, resume), d + "/err.txt", 1);
    EXPECT_NE(err.find(out + "/checkpoint.json: damaged: "), std::string::npos) << err;
    EXPECT_NE(err.find(said), std::string::npos) << err;
    EXPECT_EQ(scenario::read_file(out + "/history.csv"), history);
  }
  std::ofstream(out + "/checkpoint.json") << cp_text;
  // a history.csv that is not the checkpoint's: one row fewer, or another search's
  std::string cut = history.substr(0, history.rfind('\n', history.size() - 2) + 1);
  std::ofstream(out + "/history.csv") << cut;
  std::string err = search(optimize_args(p, out, resume), d + "/err.txt", 1);
  EXPECT_NE(err.find(out + "/history.csv: shorter"), std::string::npos) << err;
  std::string other = history;
  other.replace(other.find("\n0,0,0,") + 1, 5, "1,0,0");
  std::ofstream(out + "/history.csv") << other;
  err = search(optimize_args(p, out, resume), d + "/err.txt", 1);
  EXPECT_NE(err.find("rows up to the checkpoint do not match"), std::string::npos) << err;
  // repaired, it resumes
  std::ofstream(out + "/history.csv") << history;
  search(optimize_args(p, out, resume), d + "/ok.txt");
}
