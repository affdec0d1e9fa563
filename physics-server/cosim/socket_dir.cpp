// Socket directories and the stale ones of killed servers. See socket_dir.h.
#include "cosim/socket_dir.h"

#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace chainsim {

namespace fs = std::filesystem;

namespace {

constexpr const char* kPrefix = "chainsim-sock-";

std::string tmp_or_system(const std::string& tmp_dir) {
  return tmp_dir.empty() ? fs::temp_directory_path().string() : tmp_dir;
}

// the pid in "chainsim-sock-<pid>-XXXXXX", or 0 when name is not one
pid_t pid_of(const std::string& name) {
  const size_t n = std::strlen(kPrefix);
  if (name.compare(0, n, kPrefix) != 0) return 0;
  char* end = nullptr;
  const long pid = std::strtol(name.c_str() + n, &end, 10);
  if (end == name.c_str() + n || *end != '-' || std::strlen(end) != 7 || pid <= 0) return 0;
  return static_cast<pid_t>(pid);
}

}  // namespace

std::string make_socket_dir(const std::string& tmp_dir) {
  const std::string dir = tmp_or_system(tmp_dir);
  std::string tmpl = (fs::path(dir) / (kPrefix + std::to_string(getpid()) + "-XXXXXX")).string();
  if (!mkdtemp(tmpl.data()))
    throw std::runtime_error("cannot create a private socket directory in " + dir + ": " + std::strerror(errno));
  chmod(tmpl.c_str(), 0700);
  return tmpl;
}

int remove_stale_socket_dirs(const std::string& tmp_dir) {
  std::error_code ec;
  fs::directory_iterator it(tmp_or_system(tmp_dir), ec);
  if (ec) return 0;
  int removed = 0;
  for (const auto& de : it) {
    const pid_t pid = pid_of(de.path().filename().string());
    if (pid == 0) continue;
    struct stat st;
    // lstat: a symlink of that name is not ours to follow
    if (lstat(de.path().c_str(), &st) != 0 || !S_ISDIR(st.st_mode) || st.st_uid != geteuid()) continue;
    if (kill(pid, 0) == 0 || errno != ESRCH) continue;  // alive (or not ours to signal): left alone
    fs::remove_all(de.path(), ec);
    if (!ec) ++removed;
  }
  return removed;
}

}  // namespace chainsim
