// Socket directories and the stale ones of killed servers. See socket_dir.h.
#include "cosim/socket_dir.h"

#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace chainsim {

namespace fs = std::filesystem;

namespace {

constexpr const char* kPrefix = "chainsim-sock-";
constexpr const char* kOldPrefix = "chainsim-";
constexpr const char* kSocketName = "chainsim.sock";

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

// "chainsim-" and the six letters or digits of mkdtemp: the old naming
bool is_old_name(const std::string& name) {
  const size_t n = std::strlen(kOldPrefix);
  if (name.size() != n + 6 || name.compare(0, n, kOldPrefix) != 0) return false;
  for (size_t i = n; i < name.size(); ++i)
    if (!std::isalnum(static_cast<unsigned char>(name[i]))) return false;
  return true;
}

// the paths Unix sockets of this system are bound to; nullopt when unknown
std::optional<std::vector<std::string>> bound_socket_paths() {
  std::ifstream in("/proc/net/unix");
  if (!in) return std::nullopt;
  std::vector<std::string> out;
  std::string line;
  std::getline(in, line);  // the header
  while (std::getline(in, line)) {
    std::istringstream f(line);
    std::string field;
    int i = 0;
    while (i < 7 && f >> field) ++i;  // Num RefCount Protocol Flags Type St Inode
    std::string path;
    if (i == 7 && std::getline(f >> std::ws, path) && !path.empty()) out.push_back(path);
  }
  return out;
}

// dir holds nothing, or only a socket named chainsim.sock; *newest is the
// latest change time of the directory and what it holds
bool holds_only_a_socket(const fs::path& dir, time_t* newest) {
  std::error_code ec;
  for (const auto& de : fs::directory_iterator(dir, ec)) {
    struct stat st;
    if (de.path().filename() != kSocketName || lstat(de.path().c_str(), &st) != 0 || !S_ISSOCK(st.st_mode))
      return false;
    *newest = std::max(*newest, st.st_mtime);
  }
  return !ec;
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
  return removed + remove_stale_old_socket_dirs(tmp_dir);
}

int remove_stale_old_socket_dirs(const std::string& tmp_dir, double min_age_s) {
  std::error_code ec;
  fs::directory_iterator it(tmp_or_system(tmp_dir), ec);
  if (ec) return 0;
  std::optional<std::vector<std::string>> bound;  // read once, when a candidate is found
  int removed = 0;
  for (const auto& de : it) {
    const std::string name = de.path().filename().string();
    if (!is_old_name(name)) continue;
    struct stat st;
    if (lstat(de.path().c_str(), &st) != 0 || !S_ISDIR(st.st_mode) || st.st_uid != geteuid() ||
        (st.st_mode & 0777) != 0700)
      continue;
    time_t newest = st.st_mtime;
    if (!holds_only_a_socket(de.path(), &newest)) continue;
    // a server that has just made its directory may not have bound its socket yet
    if (std::difftime(std::time(nullptr), newest) < min_age_s) continue;
    if (!bound && !(bound = bound_socket_paths())) return removed;
    // any bound path ending so keeps it, whatever comes before (a relative one too)
    const std::string tail = name + "/" + kSocketName;
    bool in_use = false;
    for (const auto& p : *bound)
      in_use |= p.ends_with(tail);
    if (in_use) continue;
    fs::remove_all(de.path(), ec);
    if (!ec) ++removed;
  }
  return removed;
}

}  // namespace chainsim
