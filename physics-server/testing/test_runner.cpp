#include "testing/test_runner.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <list>
#include <set>
#include <sstream>

#include "cosim/lockstep_server.h"
#include "cosim/program_params.h"
#include "text/number_text.h"
#include "testing/junit.h"
#include "testing/run_compare.h"
#include "output/run_reader.h"
#include "testing/test_file.h"

namespace chainsim {
namespace fs = std::filesystem;
namespace {

using Clock = std::chrono::steady_clock;

// Ctrl-C or SIGTERM, at any moment of chainsim test (docs/testing.md): the
// handler notes it, and ends every run going on at once with a SIGTERM of
// its own, whatever the main loop is doing then (loading, waiting,
// measuring); the main loop then stops starting runs and measuring, waits
// for the runs to end and exits 130
volatile sig_atomic_t g_interrupted = 0;
// the pids of the runs going on (0: a free slot), for the handler; a pid
// leaves its slot before the run is reaped, so the handler never signals a
// pid the system may have given to another process
static_assert(std::atomic<pid_t>::is_always_lock_free, "the signal handler reads the pids");
std::atomic<pid_t>* g_runs = nullptr;
size_t g_run_slots = 0;

struct Case {
  const TestFile* test = nullptr;
  std::optional<Scene> scene;
  int partner = -1;  // --compare: the index of the same test and seed on the other target
  std::string dir;
  pid_t pid = 0;
  size_t slot = 0;  // in g_runs while it runs
  Clock::time_point started;
  TestCaseResult result;
};

std::string safe_name(const std::string& s) {
  std::string o;
  for (char c : s) o += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.') ? c : '_';
  return o.empty() ? "test" : o;
}

std::string default_root() {
  char stamp[32];
  const std::time_t now = std::time(nullptr);
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", std::localtime(&now));
  return std::string("runs/test-") + stamp;
}

std::string tail_of(const std::string& path, size_t n) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  std::string t = s.str();
  while (!t.empty() && (t.back() == '\n' || t.back() == ' ')) t.pop_back();
  if (t.size() > n) t = "..." + t.substr(t.size() - n);
  for (char& c : t)
    if (c == '\n') c = ' ';
  return t;
}

// the forked process: one normal run, its messages into the run directory;
// SIGINT and SIGTERM come blocked from the parent, and are let in (mask) once
// this process has its own disposition of them (the run's, below)
[[noreturn]] void run_child(const Case& c, const TestRunOptions& o, pid_t parent, const sigset_t& mask) {
  signal(SIGINT, SIG_DFL);
  signal(SIGTERM, SIG_DFL);
  sigprocmask(SIG_SETMASK, &mask, nullptr);
  prctl(PR_SET_PDEATHSIG, SIGTERM);  // the run ends cleanly if chainsim test is killed
  if (getppid() != parent) _exit(kExitInterrupted);
  std::error_code ec;
  fs::create_directories(c.dir, ec);
  const int fd = open((c.dir + "/chainsim.log").c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd >= 0) {
    dup2(fd, 1);
    dup2(fd, 2);
    close(fd);
  }
  RunOptions opt;
  opt.out_dir = c.dir;
  opt.on_fault = c.test->on_module_fault == "limp" ? FaultMode::Limp : FaultMode::Stop;
  opt.module_timeout_s = o.module_timeout_s;
  opt.firmware_dir = o.firmware_dir;
  opt.overrun_warn = o.overrun_warn;
  opt.quiet = true;
  int rc = kExitInternal;
  try {
    const RunResult r = run_scene(*c.scene, opt);
    if (r.exit_code != kExitOk) std::fprintf(stderr, "chainsim: run stopped: %s\n", r.message.c_str());
    rc = r.exit_code;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "chainsim: %s\n", e.what());
  }
  std::fflush(stdout);
  std::fflush(stderr);
  _exit(rc);
}

// measures a finished run: each expectation (evaluate.h); a read or a
// measurement stops with RunReadStopped once interrupted
void measure_run(Case& c, int exit_code) {
  TestCaseResult& r = c.result;
  if (exit_code != kExitOk && exit_code != kExitModuleFault && exit_code != kExitSilentModule) {
    r.status = TestCaseResult::Status::error;
    r.error = "the run could not start or did not finish (exit " + std::to_string(exit_code) +
              "): " + tail_of(c.dir + "/chainsim.log", 600);
    return;
  }
  RunReader run(c.dir, {[] { return g_interrupted != 0; }, {}});
  try {
    const auto& s = run.summary();
    r.trace_sha256 = s.value("trace_sha256", "");
    r.sim_s = run.end_s();
  } catch (const RunReadError&) {
  }
  r.status = TestCaseResult::Status::passed;
  for (const TestExpectation& te : c.test->expect) {
    CheckOutcome co{te.expectation.text, te.where, {}};
    try {
      co.result = evaluate(te.expectation, run);
    } catch (const EvaluationError& e) {
      r.status = TestCaseResult::Status::error;
      r.error = te.where + ": " + e.what();
      return;
    }
    if (!co.result.pass) r.status = TestCaseResult::Status::failed;
    r.checks.push_back(co);
  }
}

void interrupted(TestCaseResult& r, const std::string& why) {
  r.status = TestCaseResult::Status::interrupted;
  r.error = why;
  r.checks.clear();
}

void measure(Case& c, int exit_code) {
  TestCaseResult& r = c.result;
  if (exit_code == kExitInterrupted || g_interrupted) return interrupted(r, "interrupted");
  try {
    measure_run(c, exit_code);
  } catch (const RunReadStopped&) {
    interrupted(r, "interrupted while measuring");
  }
}

void on_signal(int) {
  const int saved = errno;
  g_interrupted = 1;
  for (size_t i = 0; i < g_run_slots; ++i)
    if (const pid_t p = g_runs[i].load(); p > 0) kill(p, SIGTERM);
  errno = saved;
}

}  // namespace

std::string result_line(const TestCaseResult& r) {
  std::string s;
  switch (r.status) {
    case TestCaseResult::Status::passed: s = "PASS  "; break;
    case TestCaseResult::Status::failed: s = "FAIL  "; break;
    case TestCaseResult::Status::error: s = "ERROR "; break;
    case TestCaseResult::Status::interrupted: s = "INTR  "; break;
  }
  s += r.name + " seed " + std::to_string(r.seed);
  if (r.status == TestCaseResult::Status::error || r.status == TestCaseResult::Status::interrupted)
    return s + ": " + r.error;
  s += " (" + fixed_text(r.sim_s, 2) + " s simulated in " + fixed_text(r.wall_s, 1) + " s)";
  for (const CheckOutcome& c : r.checks)
    s += " | " + c.expectation + ": " + c.result.measured + (c.result.pass ? "" : " FAILED");
  return s;
}

namespace {

// interrupted before any run started
int interrupted_before_running(FILE* out) {
  std::fprintf(out, "chainsim test: interrupted; nothing was run\n");
  return kExitInterrupted;
}

int run_all(const TestRunOptions& o, const FailureViewer& viewer, FILE* out, std::atomic<pid_t>* slots) {
  const auto t0 = Clock::now();
  std::vector<TestCaseResult> errors;  // malformed files
  std::list<TestFile> tests;
  std::vector<std::string> files;
  try {
    files = find_test_files(o.paths);
  } catch (const TestFileError& e) {
    std::fprintf(stderr, "chainsim: %s\n", e.what());
    return kTestExitMalformed;
  }
  for (const std::string& f : files) {
    if (g_interrupted) return interrupted_before_running(out);
    try {
      tests.push_back(load_test_file(f));
    } catch (const TestFileError& e) {
      TestCaseResult r;
      r.file = f;
      r.name = fs::path(f).filename().string();
      r.error = e.what();
      errors.push_back(r);
    }
  }
  // every test and seed, with its scene loaded (and checked) before anything runs
  std::vector<Case> cases;
  const std::string root = o.keep_dir.empty() ? default_root() : o.keep_dir;
  std::set<std::string> dirs;
  for (const TestFile& t : tests) {
    std::vector<std::optional<uint64_t>> seeds;
    if (o.seeds) seeds.assign(o.seeds->begin(), o.seeds->end());
    else if (!t.seeds.empty()) seeds.assign(t.seeds.begin(), t.seeds.end());
    else seeds.push_back(std::nullopt);
    // the targets each test and seed runs on: as the scene says, --target, or both of --compare
    std::vector<std::optional<Target>> targets;
    if (!o.compare.empty()) targets.assign(o.compare.begin(), o.compare.end());
    else targets.push_back(o.target);
    bool bad = false;
    for (const auto& seed : seeds) {
      for (const auto& target : targets) {
        if (g_interrupted) return interrupted_before_running(out);
        Case c;
        c.test = &t;
        c.result.file = t.file;
        c.result.name = t.name + (o.compare.empty() ? "" : std::string(" on ") + target_name(*target));
        try {
          // programs found, their parameters declared and in range, before any run
          c.scene = load_test_scene(t, seed, [&](const Scene& s) {
            Scene on = s;
            if (target) set_target(&on, *target);
            check_scene_programs(on, o.firmware_dir);
          });
          if (target) set_target(&*c.scene, *target);
          c.result.seed = c.scene->world.seed;
        } catch (const TestFileError& e) {
          c.result.error = e.what();
          c.result.seed = seed.value_or(0);
          errors.push_back(c.result);
          bad = true;
          break;
        }
        const std::string base = safe_name(t.name) + (o.compare.empty() ? "" : "-" + std::string(target_name(*target)));
        std::string dir = root + "/" + base + "-seed" + std::to_string(c.result.seed);
        for (int k = 2; dirs.count(dir); ++k) dir = root + "/" + base + "-" + std::to_string(k) + "-seed" + std::to_string(c.result.seed);
        dirs.insert(dir);
        c.dir = dir;
        if (!o.compare.empty() && target == targets.back()) {
          c.partner = static_cast<int>(cases.size()) - 1;
          cases.back().partner = static_cast<int>(cases.size());
        }
        cases.push_back(std::move(c));
      }
      if (bad) break;
    }
  }
  // a program listing its parameters may have been ended by the same Ctrl-C
  if (g_interrupted) return interrupted_before_running(out);
  if (!errors.empty()) {
    for (const auto& e : errors) std::fprintf(stderr, "chainsim: %s\n", e.error.c_str());
    std::fprintf(stderr, "chainsim: %zu malformed test file%s; nothing was run\n", errors.size(),
                 errors.size() == 1 ? "" : "s");
    if (!o.junit.empty() && !write_junit(o.junit, errors, 0))
      std::fprintf(stderr, "chainsim: cannot write %s\n", o.junit.c_str());
    return kTestExitMalformed;
  }
  std::error_code ec;
  fs::create_directories(root, ec);
  if (ec) {
    std::fprintf(stderr, "chainsim: cannot create %s: %s\n", root.c_str(), ec.message().c_str());
    return kTestExitMalformed;
  }

  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  const pid_t self = getpid();
  size_t next = 0;
  int running = 0;
  const int jobs = std::max(1, o.jobs);
  while (next < cases.size() || running > 0) {
    while (!g_interrupted && running < jobs && next < cases.size()) {
      Case& c = cases[next++];
      std::fflush(out);
      std::fflush(stderr);
      fs::remove_all(c.dir, ec);  // a run kept from an earlier time
      c.started = Clock::now();
      // SIGINT and SIGTERM wait until the run's pid is in its slot, where the
      // handler finds it
      sigset_t mask;
      sigprocmask(SIG_BLOCK, &stop_signals, &mask);
      const pid_t pid = fork();
      if (pid == 0) run_child(c, o, self, mask);
      const int fork_errno = errno;
      if (pid > 0) {
        while (slots[c.slot].load() != 0) ++c.slot;  // one is free: at most jobs runs at once
        slots[c.slot] = pid;
      }
      sigprocmask(SIG_SETMASK, &mask, nullptr);
      if (pid < 0) {
        c.result.status = TestCaseResult::Status::error;
        c.result.error = std::string("cannot start the run: fork: ") + std::strerror(fork_errno);
        continue;
      }
      c.pid = pid;
      ++running;
    }
    if (running == 0) break;
    // a run that ended: out of its slot first, then reaped
    siginfo_t info{};
    if (waitid(P_ALL, 0, &info, WEXITED | WNOWAIT) < 0) {
      if (errno == EINTR) continue;
      break;
    }
    const pid_t pid = info.si_pid;
    for (Case& c : cases)
      if (c.pid == pid) slots[c.slot] = 0;
    int st = 0;
    while (waitpid(pid, &st, 0) < 0 && errno == EINTR) {
    }
    for (Case& c : cases) {
      if (c.pid != pid) continue;
      c.pid = 0;
      --running;
      c.result.wall_s = std::chrono::duration<double>(Clock::now() - c.started).count();
      const int rc = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
      measure(c, rc);
      c.result.run_dir = c.dir;
      std::fprintf(out, "%s\n", result_line(c.result).c_str());
      std::fflush(out);
    }
  }

  // --compare: each test and seed, one target against the other
  for (size_t i = 0; i < cases.size(); ++i) {
    const Case& a = cases[i];
    if (a.partner <= static_cast<int>(i) || g_interrupted) continue;
    const Case& b = cases[static_cast<size_t>(a.partner)];
    if (a.started == Clock::time_point{} || b.started == Clock::time_point{}) continue;
    const std::string file = root + "/" + safe_name(a.test->name) + "-seed" + std::to_string(a.result.seed) +
                             "-compare.txt";
    try {
      const auto stop = [] { return g_interrupted != 0; };
      RunReader ra(a.dir, {stop, {}}), rb(b.dir, {stop, {}});
      const CompareReport rep = compare_runs(ra, rb, target_name(o.compare[0]), target_name(o.compare[1]));
      std::ofstream(file) << compare_text(rep);
      const Divergence* d = rep.first();
      std::fprintf(out, "COMPARE %s seed %llu: %s (%s)\n", a.test->name.c_str(),
                   static_cast<unsigned long long>(a.result.seed),
                   d ? ("first divergence: " + d->who + ", " + d->channel + ": \"" + d->a + "\" against \"" + d->b + "\"")
                           .c_str()
                     : "no divergence",
                   file.c_str());
    } catch (const std::exception& e) {
      std::fprintf(out, "COMPARE %s seed %llu: not compared: %s\n", a.test->name.c_str(),
                   static_cast<unsigned long long>(a.result.seed), e.what());
    }
  }

  // the failed runs: a replay and a picture of the failure; passed runs go
  // unless kept
  std::vector<TestCaseResult> results;
  int failed = 0, errored = 0, passed = 0;
  for (Case& c : cases) {
    TestCaseResult& r = c.result;
    if (c.started == Clock::time_point{}) {  // never started: interrupted first
      r.status = TestCaseResult::Status::interrupted;
      r.error = "not run (interrupted)";
      c.dir.clear();
    }
    if (r.status == TestCaseResult::Status::failed && !g_interrupted) {
      double t = r.sim_s;
      for (const CheckOutcome& ch : r.checks)
        if (!ch.result.pass) {
          if (ch.result.t_s >= 0) t = ch.result.t_s;
          break;
        }
      r.failure_t_s = std::clamp(t, 0.0, r.sim_s);
      std::string err;
      if (viewer) r.artefacts = viewer(c.dir, r.failure_t_s, &err);
      if (!err.empty()) std::fprintf(stderr, "chainsim: %s: %s\n", c.dir.c_str(), err.c_str());
      std::fprintf(out, "      %s seed %llu: run kept in %s", r.name.c_str(), static_cast<unsigned long long>(r.seed),
                   c.dir.c_str());
      for (const std::string& a : r.artefacts) std::fprintf(out, ", %s", a.c_str());
      std::fprintf(out, "\n");
    }
    if (r.status == TestCaseResult::Status::passed && o.keep_dir.empty() && !c.dir.empty()) {
      fs::remove_all(c.dir, ec);
      r.run_dir.clear();
    }
    passed += r.status == TestCaseResult::Status::passed;
    failed += r.status == TestCaseResult::Status::failed;
    errored += r.status == TestCaseResult::Status::error || r.status == TestCaseResult::Status::interrupted;
    results.push_back(r);
  }
  if (o.keep_dir.empty() && fs::is_empty(root, ec)) {
    fs::remove(root, ec);
    if (fs::is_empty("runs", ec)) fs::remove("runs", ec);  // made for it
  }
  const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
  std::fprintf(out, "chainsim test: %d passed, %d failed, %d errors (%zu runs in %.1f s)%s%s\n", passed, failed,
               errored, results.size(), wall, fs::exists(root, ec) ? "; runs in " : "",
               fs::exists(root, ec) ? root.c_str() : "");
  if (!o.junit.empty()) {
    if (write_junit(o.junit, results, wall)) std::fprintf(out, "chainsim test: JUnit report %s\n", o.junit.c_str());
    else std::fprintf(stderr, "chainsim: cannot write %s\n", o.junit.c_str());
  }
  if (g_interrupted) return kExitInterrupted;
  if (errored) return kTestExitMalformed;
  return failed ? kTestExitFailed : kTestExitPassed;
}

}  // namespace

int run_tests(const TestRunOptions& o, const FailureViewer& viewer, FILE* out) {
  // the handler is in place from the start to the end: an interruption
  // while the files are loaded, the runs go, the results are measured or a
  // failure is drawn ends it all with 130
  std::vector<std::atomic<pid_t>> slots(static_cast<size_t>(std::max(1, o.jobs)));
  for (auto& s : slots) s = 0;
  g_runs = slots.data();
  g_run_slots = slots.size();
  g_interrupted = 0;
  struct sigaction sa {}, old_int {}, old_term {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, &old_int);
  sigaction(SIGTERM, &sa, &old_term);
  const int rc = run_all(o, viewer, out, slots.data());
  sigaction(SIGINT, &old_int, nullptr);
  sigaction(SIGTERM, &old_term, nullptr);
  g_run_slots = 0;
  g_runs = nullptr;
  return rc;
}

}  // namespace chainsim
