// The fault-injection suite, malformed inputs: a few hundred mutated scenes
// and module definition files (input_mutator.h), from the shipped
// scenes/*.yaml and scenes/modules/*.yaml. Each is checked by `chainsim run
// --check`, and each that passes is run for a few ticks. Every case must end
// in exit 0 or 1, a refusal being one line that names the file at fault
// (file:line:column where there is a position); never a signal, exit 3 or a
// hang. The unmutated files go through the same steps first: if they do not
// pass, the harness is wrong, not the files.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>
#include <regex>
#include <thread>

#include "input_mutator.h"
#include "scenario_util.h"

using namespace scenario;
namespace fs = std::filesystem;

namespace {

constexpr int kCases = 300;
constexpr uint64_t kSeed = 16;
constexpr double kTimeoutS = 30;      // wall clock; longer is a hang
constexpr double kRunDurationS = 0.05;

// a shipped input file
struct Input {
  std::string name;    // file stem
  std::string text;
  bool module = false; // a module definition (else a scene)
};

std::vector<Input> shipped_inputs(const fs::path& scenes) {
  std::vector<Input> out;
  for (const auto& [dir, module] : {std::pair{scenes, false}, std::pair{scenes / "modules", true}}) {
    std::vector<fs::path> files;
    for (const auto& de : fs::directory_iterator(dir))
      if (de.path().extension() == ".yaml") files.push_back(de.path());
    std::sort(files.begin(), files.end());  // the case list must not depend on directory order
    for (const auto& f : files) out.push_back({f.stem().string(), read_file(f.string()), module});
  }
  return out;
}

// one case on disk: the scene given to chainsim and the files a message may name
struct Case {
  std::string scene;
  std::string mutated;  // the mutated file (the scene, or the module file it uses)
};

// the case's files in work/scenes (a copy of scenes/, so that meshes and
// module files resolve as they do for the shipped scenes)
Case write_case(const fs::path& scenes, const std::string& tag, const Input& in, const Mutation& m) {
  Case c;
  if (!in.module) {
    c.scene = c.mutated = write_file(scenes.string(), tag + "-" + in.name + ".yaml", m.text);
    return c;
  }
  const std::string module_file = "modules/" + tag + "-" + in.name + ".yaml";
  c.mutated = (scenes / module_file).string();
  if (!m.drop_file) write_file(scenes.string(), module_file, m.text);
  c.scene = write_file(scenes.string(), tag + "-uses-" + in.name + ".yaml",
                       "name: uses-" + in.name + "\nchain:\n  - {type: " + in.name + "}\nmodule_types: {" + in.name +
                           ": " + module_file + "}\n");
  return c;
}

struct Ended {
  int exit_code = -1;
  int signal = 0;
  bool hung = false;
  std::string err;
  double wall_s = 0;
};

Ended run_bounded(const std::vector<std::string>& args, const std::string& err_path) {
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = start_chainsim(args, err_path);
  Ended r;
  int st = 0;
  const auto deadline = start + std::chrono::duration<double>(kTimeoutS);
  while (waitpid(pid, &st, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > deadline) {
      r.hung = true;
      kill(pid, SIGKILL);
      waitpid(pid, &st, 0);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  if (WIFEXITED(st)) r.exit_code = WEXITSTATUS(st);
  if (WIFSIGNALED(st)) r.signal = WTERMSIG(st);
  r.err = read_file(err_path);
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

// how a refusal names its culprit
enum class Named { Position, Path, Option, Endpoint, Divergence, Nothing };

// stderr must be one line "chainsim: ..."; what it names. A message with no
// position must name a file of the case: one in its directory (a scene, a
// module file, a mesh or program it refers to)
Named culprit(const std::string& err, const Case& c, const std::string& case_dir) {
  if (err.empty() || err.find('\n') != err.size() - 1 || err.rfind("chainsim: ", 0) != 0) return Named::Nothing;
  for (const std::string& f : {c.mutated, c.scene}) {
    const size_t at = err.find(f + ":");
    if (at == std::string::npos) continue;
    static const std::regex kPos("^:[0-9]+:[0-9]+: ");
    if (f == c.mutated && std::regex_search(err.substr(at + f.size()), kPos)) return Named::Position;
  }
  if (err.find(case_dir + "/") != std::string::npos) return Named::Path;
  if (err.rfind("chainsim: --duration ", 0) == 0) return Named::Option;
  static const std::regex kEndpoint("(module [0-9]+|central control) \\(");
  if (std::regex_search(err, kEndpoint)) return Named::Endpoint;
  if (err.find("physics diverged: ") != std::string::npos) return Named::Divergence;
  return Named::Nothing;
}

// one case of the suite and how it ended
struct Job {
  Case c;
  std::string about;
  std::string kind;
  bool control = false;  // a shipped file, unmutated
  Ended check, run;
};

// job(i) for every i in [0, n), on `workers` threads
void for_each_parallel(int n, int workers, const std::function<void(int)>& job) {
  std::atomic<int> next{0};
  std::vector<std::thread> threads;
  for (int w = 0; w < workers; ++w)
    threads.emplace_back([&] {
      for (int i = next++; i < n; i = next++) job(i);
    });
  for (auto& t : threads) t.join();
}

struct Tally {
  int cases = 0, check0 = 0, check1 = 0, at_position = 0, at_path = 0;
  std::map<int, int> run_exits;  // exit code of the runs of accepted cases
  std::map<std::string, std::pair<int, int>> by_kind;  // accepted, refused
};

}  // namespace

// the generator itself: seeded, and every kind changes the file
TEST(FaultInjection, MutatorIsSeededAndChangesTheFile) {
  const std::string text = read_file(scene_path("mesh-pipe"));
  for (int k = 0; k < kMutationKinds; ++k) {
    for (uint64_t seed = 1; seed <= 20; ++seed) {
      const Mutation a = mutate(text, static_cast<MutationKind>(k), seed);
      const Mutation b = mutate(text, static_cast<MutationKind>(k), seed);
      EXPECT_EQ(a.text, b.text) << mutation_name(static_cast<MutationKind>(k)) << " seed " << seed;
      EXPECT_NE(a.text, text) << mutation_name(static_cast<MutationKind>(k)) << " seed " << seed << ": " << a.what;
      EXPECT_EQ(a.what.find("found nothing"), std::string::npos) << a.what;
    }
  }
}

TEST(FaultInjection, MutatedScenesAndModuleFilesEndInExit0Or1NamingTheFile) {
  const auto t0 = std::chrono::steady_clock::now();
  const fs::path work = temp_dir("mutated");
  const fs::path scenes = work / "scenes";
  const fs::path repo_scenes = fs::path(scene_path("default")).parent_path();
  fs::create_directories(scenes / "modules");
  fs::copy(repo_scenes / "meshes", scenes / "meshes", fs::copy_options::recursive);
  fs::create_directory(work / "tmp");
  TmpDirForChildren tmp((work / "tmp").string());
  const std::vector<Input> inputs = shipped_inputs(repo_scenes);
  ASSERT_GE(inputs.size(), 25u);
  const bool verbose = std::getenv("CHAINSIM_FUZZ_VERBOSE") != nullptr;

  // the cases: the shipped files unmutated (the control), then the mutations
  std::vector<Job> jobs;
  for (const Input& in : inputs)
    jobs.push_back({write_case(scenes, "control", in, Mutation{in.text, "unmutated"}), "control " + in.name, "", true, {},
                    {}});
  SplitMix pick(kSeed);
  for (int i = 0; i < kCases; ++i) {
    const Input& in = inputs[pick.below(inputs.size())];
    const auto kind = static_cast<MutationKind>(i % kMutationKinds);
    const Mutation m = mutate(in.text, kind, pick.next());
    const Case c = write_case(scenes, "m" + std::to_string(i), in, m);
    jobs.push_back({c, "case " + std::to_string(i) + " (" + mutation_name(kind) + " of " + in.name + ": " + m.what +
                           ", " + c.mutated + ")",
                    mutation_name(kind), false, {}, {}});
  }
  // each: --check, and a short run when it passed; two at a time (this test runs alone)
  for_each_parallel(static_cast<int>(jobs.size()), 2, [&](int i) {
    Job& j = jobs[i];
    const std::string tag = (work / std::to_string(i)).string();
    j.check = run_bounded({"run", j.c.scene, "--check", "-q"}, tag + ".err");
    if (j.check.exit_code != 0 || j.check.hung || j.check.signal) return;
    j.run = run_bounded({"run", j.c.scene, "--duration", std::to_string(kRunDurationS), "-q", "--out", tag + "-run"},
                        tag + ".err");
    fs::remove_all(tag + "-run");
  });

  for (const Job& j : jobs) {
    if (!j.control) continue;
    ASSERT_EQ(j.check.exit_code, 0) << j.about << " (the harness, not the file): " << j.check.err;
    ASSERT_EQ(j.run.exit_code, 0) << j.about << " run (the harness, not the file): " << j.run.err;
  }
  Tally t;
  for (const Job& j : jobs) {
    if (j.control) continue;
    const Ended& e = j.check;
    const std::string& about = j.about;
    if (verbose)
      std::printf("%s: --check exit %d in %.2f s%s%s", about.c_str(), e.exit_code, e.wall_s, e.err.empty() ? "\n" : ": ",
                  e.err.c_str());
    ++t.cases;
    EXPECT_FALSE(e.hung) << about << ": --check did not end within " << kTimeoutS << " s";
    EXPECT_EQ(e.signal, 0) << about << ": killed by signal " << e.signal << "\n" << e.err;
    auto& kind_tally = t.by_kind[j.kind];
    if (e.exit_code == 1) {
      ++t.check1;
      ++kind_tally.second;
      const Named n = culprit(e.err, j.c, scenes.string());
      EXPECT_TRUE(n == Named::Position || n == Named::Path) << about << ": the refusal names no file:\n" << e.err;
      ++(n == Named::Position ? t.at_position : t.at_path);
      continue;
    }
    if (e.exit_code != 0) {
      ADD_FAILURE() << about << ": --check ended with exit " << e.exit_code << "\n" << e.err;
      continue;
    }
    ++t.check0;
    ++kind_tally.first;
    // accepted: a few ticks of the real run, its processes and files
    const Ended& r = j.run;
    if (verbose) std::printf("  run exit %d in %.2f s%s%s", r.exit_code, r.wall_s, r.err.empty() ? "\n" : ": ", r.err.c_str());
    EXPECT_FALSE(r.hung) << about << ": the run did not end within " << kTimeoutS << " s";
    EXPECT_EQ(r.signal, 0) << about << ": the run was killed by signal " << r.signal << "\n" << r.err;
    ++t.run_exits[r.exit_code];
    const Named n = culprit(r.err, j.c, scenes.string());
    switch (r.exit_code) {
      case 0: EXPECT_EQ(r.err, "") << about; break;
      case 1: EXPECT_TRUE(n == Named::Path || n == Named::Position || n == Named::Option) << about << "\n" << r.err; break;
      case 2: EXPECT_EQ(n, Named::Endpoint) << about << "\n" << r.err; break;  // a program that is no such module
      case 4: EXPECT_EQ(n, Named::Divergence) << about << "\n" << r.err; break;  // a start inside the floor
      default: ADD_FAILURE() << about << ": the run ended with exit " << r.exit_code << "\n" << r.err;
    }
  }
  EXPECT_TRUE(processes_with_env("CHAINSIM_SOCKET=" + (work / "tmp").string()).empty()) << "orphans";
  EXPECT_TRUE(socket_dirs_in((work / "tmp").string()).empty());

  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("mutated inputs: %d cases (seed %llu) from %zu shipped files, which passed unmutated first\n", t.cases,
              static_cast<unsigned long long>(kSeed), inputs.size());
  std::printf("  --check: %d ended 0, %d ended 1 (%d at file:line:column of the mutated file, %d naming a file)\n",
              t.check0, t.check1, t.at_position, t.at_path);
  std::printf("  the %d accepted, run for %.2f s:", t.check0, kRunDurationS);
  for (const auto& [code, n] : t.run_exits) std::printf(" exit %d: %d", code, n);
  std::printf("\n");
  for (const auto& [kind, n] : t.by_kind) std::printf("  %-15s accepted %3d, refused %3d\n", kind.c_str(), n.first, n.second);
  std::printf("  wall time %.1f s\n", wall);
}
