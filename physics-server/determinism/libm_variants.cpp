#include "determinism/libm_variants.h"

#include <sys/auxv.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace chainsim {

namespace {

constexpr const char* kHwcaps = "glibc.cpu.hwcaps=";
constexpr const char* kRestarted = "CHAINSIM_LIBM_RESTARTED";

// the items of s between the separators, in order, empty ones too
template <typename F>
void for_each_item(const std::string& s, char sep, F&& f) {
  size_t start = 0;
  while (start <= s.size()) {
    const size_t end = std::min(s.find(sep, start), s.size());
    f(s.substr(start, end - start));
    start = end + 1;
  }
}

void append_item(std::string& list, char sep, const std::string& item) {
  list += (list.empty() ? "" : std::string(1, sep)) + item;
}

// item appended unless one of the list's items is it (compared whole)
void add_item(std::string& list, char sep, const std::string& item) {
  bool has = false;
  for_each_item(list, sep, [&](const std::string& x) { has = has || x == item; });
  if (!has) append_item(list, sep, item);
}

}  // namespace

std::string tunables_with_baseline_libm(const char* current) {
  // the tunables are name=value entries separated by ':', a hwcaps value
  // items separated by ','
  std::string out;
  bool found = false;
  for_each_item(current ? current : "", ':', [&](std::string entry) {
    if (entry.rfind(kHwcaps, 0) == 0) {
      found = true;
      std::string value = entry.substr(std::strlen(kHwcaps));
      for_each_item(kBaselineLibmHwcaps, ',', [&](const std::string& item) { add_item(value, ',', item); });
      entry = kHwcaps + value;
    }
    if (!entry.empty()) append_item(out, ':', entry);
  });
  if (!found) append_item(out, ':', kHwcaps + std::string(kBaselineLibmHwcaps));
  return out;
}

void use_baseline_libm(const char* program, char** argv) {
  // the marker says this process is the restarted one; it is not passed on
  const bool restarted = std::getenv(kRestarted) != nullptr;
  if (restarted) unsetenv(kRestarted);
  const char* choice = std::getenv("CHAINSIM_LIBM");
  if (choice && std::strcmp(choice, "machine") == 0) return;
  if (choice && *choice && std::strcmp(choice, "baseline") != 0 && !restarted)
    std::fprintf(stderr, "%s: CHAINSIM_LIBM=%s is neither 'baseline' (the default) nor 'machine': using baseline\n",
                 program, choice);
  // GLIBC_TUNABLES as glibc read it at this start, and as it must be
  const char* before = std::getenv("GLIBC_TUNABLES");
  const std::string t = tunables_with_baseline_libm(before);
  if (before && t == before) return;
  const char* machine = "this run uses the machine's libm variants, whose last bits can differ from another CPU's";
  // a set-user-ID start: glibc erases the tunable, a restart cannot keep it
  if (getauxval(AT_SECURE)) {
    std::fprintf(stderr, "%s: started set-user-ID, glibc ignores GLIBC_TUNABLES: %s\n", program, machine);
    return;
  }
  // restarted and still without the tunable (an environment that drops it):
  // no second restart
  if (restarted) {
    std::fprintf(stderr, "%s: GLIBC_TUNABLES was dropped at the restart: %s\n", program, machine);
    return;
  }
  // the program's own path, not /proc/self/exe: the process keeps its name
  // (ps, pgrep and killall see "chainsim", not "exe")
  char self[4096];
  const ssize_t n = readlink("/proc/self/exe", self, sizeof self);
  if (n <= 0 || n == static_cast<ssize_t>(sizeof self)) {
    const int err = n <= 0 ? errno : ENAMETOOLONG;
    std::fprintf(stderr, "%s: cannot restart with glibc's baseline libm (/proc/self/exe: %s): %s\n", program,
                 std::strerror(err), machine);
    return;
  }
  self[n] = '\0';
  // started through the dynamic loader (ld-linux-x86-64.so.2 PROGRAM ...):
  // /proc/self/exe is the loader, which argv alone does not start again
  const char* base = std::strrchr(self, '/');
  base = base ? base + 1 : self;
  if (std::strncmp(base, "ld-", 3) == 0 || std::strncmp(base, "ld.so", 5) == 0) {
    std::fprintf(stderr,
                 "%s: started through the dynamic loader (%s), which cannot be restarted; set "
                 "GLIBC_TUNABLES=glibc.cpu.hwcaps=%s for the baseline libm: %s\n",
                 program, self, kBaselineLibmHwcaps, machine);
    return;
  }
  const bool had = before != nullptr;
  const std::string old = had ? before : "";
  setenv("GLIBC_TUNABLES", t.c_str(), 1);
  setenv(kRestarted, "1", 1);
  execv(self, argv);
  const int err = errno;
  unsetenv(kRestarted);
  // the processes this one starts use what it uses
  if (had) setenv("GLIBC_TUNABLES", old.c_str(), 1);
  else unsetenv("GLIBC_TUNABLES");
  std::fprintf(stderr, "%s: cannot restart with glibc's baseline libm (%s: %s): %s\n", program, self,
               std::strerror(err), machine);
}

}  // namespace chainsim
