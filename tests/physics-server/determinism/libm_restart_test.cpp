// use_baseline_libm's restart, on a real process (libm_probe): the same pid,
// glibc's view of the CPU afterwards, the tunable merged into what was
// there, the opt-out, and the starts it cannot restart
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fcntl.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

extern char** environ;

namespace {

struct Probe {
  pid_t pid = -1;
  std::string out, err;
  int status = -1;
};

std::string slurp(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// run argv (libm_probe, or the loader with it) with env added to this
// process's environment, less its GLIBC_TUNABLES and CHAINSIM_LIBM*
Probe probe(std::vector<std::string> argv, const std::vector<std::string>& env) {
  std::vector<std::string> envs;
  for (char** e = environ; *e; ++e) {
    const std::string v = *e;
    if (v.rfind("GLIBC_TUNABLES=", 0) == 0 || v.rfind("CHAINSIM_LIBM", 0) == 0) continue;
    envs.push_back(v);
  }
  envs.insert(envs.end(), env.begin(), env.end());
  std::vector<char*> ep, ap;
  for (auto& e : envs) ep.push_back(e.data());
  ep.push_back(nullptr);
  for (auto& a : argv) ap.push_back(a.data());
  ap.push_back(nullptr);
  const std::string base = ::testing::TempDir() + "libm_probe_" + std::to_string(getpid());
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, (base + ".out").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&fa, 2, (base + ".err").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  Probe p;
  EXPECT_EQ(posix_spawn(&p.pid, ap[0], &fa, nullptr, ap.data(), ep.data()), 0) << argv[0];
  posix_spawn_file_actions_destroy(&fa);
  waitpid(p.pid, &p.status, 0);
  p.out = slurp(base + ".out");
  p.err = slurp(base + ".err");
  std::remove((base + ".out").c_str());
  std::remove((base + ".err").c_str());
  return p;
}

bool cpu_has(const char* f) {
  __builtin_cpu_init();
  return std::string(f) == "fma" ? __builtin_cpu_supports("fma") : __builtin_cpu_supports("avx2");
}

std::string expect_line(pid_t pid, int avx2, int fma, const std::string& tunables) {
  return "pid=" + std::to_string(pid) + " avx2=" + std::to_string(avx2) + " fma=" + std::to_string(fma) +
         " marker=0 tunables=" + tunables + "\n";
}

}  // namespace

TEST(BaselineLibmRestart, TheProcessStartsAgainInPlaceWithAvx2HiddenAndFmaKept) {
  const Probe p = probe({LIBM_PROBE}, {});
  ASSERT_TRUE(WIFEXITED(p.status) && WEXITSTATUS(p.status) == 0) << p.err;
  // the same pid (an exec, not a child), AVX2 hidden, FMA as the CPU has it
  EXPECT_EQ(p.out, expect_line(p.pid, 0, cpu_has("fma"), "glibc.cpu.hwcaps=-AVX2,-FMA4"));
  EXPECT_EQ(p.err, "");
}

TEST(BaselineLibmRestart, TunablesAlreadySetAreKept) {
  const Probe p = probe({LIBM_PROBE}, {"GLIBC_TUNABLES=glibc.malloc.check=0:glibc.cpu.hwcaps=-AVX512F"});
  ASSERT_TRUE(WIFEXITED(p.status) && WEXITSTATUS(p.status) == 0) << p.err;
  EXPECT_EQ(p.out, expect_line(p.pid, 0, cpu_has("fma"), "glibc.malloc.check=0:glibc.cpu.hwcaps=-AVX512F,-AVX2,-FMA4"));
}

TEST(BaselineLibmRestart, MachineKeepsTheCpusOwnVariantsAndAWrongValueIsNamed) {
  const Probe m = probe({LIBM_PROBE}, {"CHAINSIM_LIBM=machine"});
  EXPECT_EQ(m.out, expect_line(m.pid, cpu_has("avx2"), cpu_has("fma"), "(unset)"));
  const Probe w = probe({LIBM_PROBE}, {"CHAINSIM_LIBM=fast"});
  EXPECT_EQ(w.out, expect_line(w.pid, 0, cpu_has("fma"), "glibc.cpu.hwcaps=-AVX2,-FMA4"));
  EXPECT_EQ(w.err, "libm_probe: CHAINSIM_LIBM=fast is neither 'baseline' (the default) nor 'machine': using baseline\n");
}

TEST(BaselineLibmRestart, AStartThroughTheDynamicLoaderSaysItCannotRestart) {
  const std::string loader = "/lib64/ld-linux-x86-64.so.2";
  if (access(loader.c_str(), X_OK) != 0) GTEST_SKIP() << loader << " is not here";
  const Probe p = probe({loader, LIBM_PROBE}, {});
  ASSERT_TRUE(WIFEXITED(p.status) && WEXITSTATUS(p.status) == 0) << p.err;
  EXPECT_EQ(p.out, expect_line(p.pid, cpu_has("avx2"), cpu_has("fma"), "(unset)"));
  EXPECT_NE(p.err.find("libm_probe: started through the dynamic loader"), std::string::npos) << p.err;
  EXPECT_NE(p.err.find("this run uses the machine's libm variants"), std::string::npos) << p.err;
}
