// `chainsim run --watch`'s sources and builds. See source_watch.h.
#include "chainsim/source_watch.h"

#include <poll.h>
#include <signal.h>
#include <sys/inotify.h>
#include <sys/signalfd.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace chainsim {
namespace fs = std::filesystem;
namespace {

// CMAKE_HOME_DIRECTORY of a build folder's cache, or ""
std::string home_of(const fs::path& build) {
  std::ifstream in(build / "CMakeCache.txt");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("CMAKE_HOME_DIRECTORY:", 0) == 0) return line.substr(line.find('=') + 1);
  return "";
}

bool is_source(const std::string& name) {
  static const char* const kExt[] = {".c", ".h", ".cpp", ".hpp", ".cc", ".cmake", ".S", ".s"};
  if (name == "CMakeLists.txt") return true;
  const auto dot = name.rfind('.');
  if (dot == std::string::npos) return false;
  const std::string ext = name.substr(dot);
  return std::any_of(std::begin(kExt), std::end(kExt), [&](const char* e) { return ext == e; });
}

}  // namespace

std::vector<WatchedBuild> watched_builds(const std::string& firmware_dirs, const std::string& exe_dir) {
  std::vector<WatchedBuild> out;
  // chainsim's own tree first: a project built against the build tree links its hal-sim
  const fs::path own = fs::path(exe_dir).parent_path();
  if (fs::exists(own / "CMakeCache.txt")) {
    const std::string home = home_of(own);
    if (!home.empty() && fs::is_directory(fs::path(home) / "firmware"))
      out.push_back({own.string(),
                     {"fw-rotation", "fw-central", "fw-helicoidal", "fw-support", "fw-extension", "fw-touch",
                      "fw-traveller", "fw-passive"},
                     home,
                     {"firmware", "hal", "hal-sim"}});
  }
  for (size_t b = 0; b < firmware_dirs.size();) {
    const size_t e = std::min(firmware_dirs.find(':', b), firmware_dirs.size());
    const fs::path d = firmware_dirs.substr(b, e - b);
    b = e + 1;
    if (d.empty() || !fs::exists(d / "CMakeCache.txt")) continue;  // a folder of built programs only
    const std::string home = home_of(d);
    if (home.empty() || !fs::is_directory(home))
      throw std::runtime_error("--watch: " + d.string() + "/CMakeCache.txt names no source folder");
    out.push_back({fs::absolute(d).lexically_normal().string(), {}, home, {}});
  }
  return out;
}

std::vector<std::string> build_command(const WatchedBuild& b) {
  std::vector<std::string> argv{"cmake", "--build", b.build_dir};
  if (!b.targets.empty()) {
    argv.push_back("--target");
    argv.insert(argv.end(), b.targets.begin(), b.targets.end());
  }
  return argv;
}

SourceWatch::SourceWatch(const std::vector<WatchedBuild>& builds, const std::string& scene_file) {
  fd_ = inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
  if (fd_ < 0) throw std::runtime_error("--watch: inotify is not available");
  for (const WatchedBuild& b : builds) add_tree(b.source_dir, b.only);
  if (!scene_file.empty()) {
    const fs::path p = fs::absolute(scene_file).lexically_normal();
    scene_dir_ = p.parent_path().string();
    scene_name_ = p.filename().string();
    scene_dir_is_source_ = std::find(dirs_.begin(), dirs_.end(), scene_dir_) != dirs_.end();
    if (!scene_dir_is_source_) {
      const int wd = inotify_add_watch(fd_, scene_dir_.c_str(), IN_CLOSE_WRITE | IN_MOVED_TO | IN_CREATE);
      if (wd >= 0) {
        wds_.push_back(wd);
        dirs_.push_back(scene_dir_);
      }
    }
  }
  const sigset_t s = stop_signal_set();
  sig_fd_ = signalfd(-1, &s, SFD_NONBLOCK | SFD_CLOEXEC);
  if (sig_fd_ < 0) throw std::runtime_error("--watch: cannot read SIGINT and SIGTERM (signalfd)");
}

bool SourceWatch::take_signal() {
  signalfd_siginfo si;
  bool any = false;
  while (read(sig_fd_, &si, sizeof si) == sizeof si) any = true;
  return any;
}

SourceWatch::~SourceWatch() {
  if (fd_ >= 0) close(fd_);
  if (sig_fd_ >= 0) close(sig_fd_);
}

void SourceWatch::add_tree(const std::string& dir, const std::vector<std::string>& only) {
  std::vector<fs::path> roots;
  if (only.empty()) roots.push_back(dir);
  for (const std::string& o : only) roots.push_back(fs::path(dir) / o);
  const uint32_t mask = IN_CLOSE_WRITE | IN_MOVED_TO | IN_CREATE | IN_DELETE | IN_MOVED_FROM;
  for (const fs::path& root : roots) {
    std::error_code ec;
    if (!fs::is_directory(root, ec)) continue;
    std::vector<fs::path> todo{root};
    while (!todo.empty()) {
      const fs::path d = todo.back();
      todo.pop_back();
      const int wd = inotify_add_watch(fd_, d.c_str(), mask);
      if (wd < 0) continue;
      wds_.push_back(wd);
      dirs_.push_back(d.string());
      for (fs::directory_iterator it(d, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (!it->is_directory(ec) || it->is_symlink(ec) || name.empty() || name[0] == '.') continue;
        if (fs::exists(it->path() / "CMakeCache.txt", ec)) continue;  // a build folder
        todo.push_back(it->path());
      }
    }
  }
}

sigset_t stop_signal_set() {
  sigset_t s;
  sigemptyset(&s);
  sigaddset(&s, SIGINT);
  sigaddset(&s, SIGTERM);
  return s;
}

SourceWatch::Change SourceWatch::wait(double quiet_s) {
  Change c;
  // SIGINT and SIGTERM are read from the signalfd while waiting, not delivered
  const sigset_t s = stop_signal_set();
  sigset_t old;
  sigprocmask(SIG_BLOCK, &s, &old);
  char buf[8192] __attribute__((aligned(__alignof__(struct inotify_event))));
  auto read_events = [&]() {
    for (;;) {
      const ssize_t n = read(fd_, buf, sizeof buf);
      if (n <= 0) return;
      for (char* p = buf; p < buf + n;) {
        const auto* ev = reinterpret_cast<const inotify_event*>(p);
        p += sizeof(inotify_event) + ev->len;
        if (ev->mask & IN_Q_OVERFLOW) {  // events were lost: build to be sure
          if (!c.any) c.first = "(more changes than inotify could queue)";
          c.any = c.sources = true;
          continue;
        }
        if (!ev->len) continue;
        const std::string name = ev->name;
        const auto at = std::find(wds_.begin(), wds_.end(), ev->wd);
        const std::string dir = at == wds_.end() ? "" : dirs_[static_cast<size_t>(at - wds_.begin())];
        if (name[0] == '.') continue;  // hidden: an editor's lock or swap file
        if ((ev->mask & IN_ISDIR) && (ev->mask & (IN_CREATE | IN_MOVED_TO))) {
          if (dir == scene_dir_ && !scene_dir_is_source_) continue;
          add_tree(dir + "/" + name, {});  // a new folder of sources
          continue;
        }
        if (ev->mask & IN_ISDIR) continue;
        const bool scene = dir == scene_dir_ && name == scene_name_;
        // a source in the scene's folder only when that folder is also a source folder
        const bool source = is_source(name) && std::count(dirs_.begin(), dirs_.end(), dir) > 0 &&
                            !(dir == scene_dir_ && !scene_dir_is_source_);
        if (!scene && !source) continue;
        if (!c.any) c.first = dir + "/" + name;
        c.any = true;
        c.sources |= source;
      }
    }
  };
  pollfd fds[2] = {{fd_, POLLIN, 0}, {sig_fd_, POLLIN, 0}};
  for (;;) {
    const int timeout_ms = c.any ? static_cast<int>(quiet_s * 1000) : -1;
    const int r = poll(fds, sig_fd_ >= 0 ? 2 : 1, timeout_ms);
    if (r > 0 && sig_fd_ >= 0 && (fds[1].revents & POLLIN)) {
      signalfd_siginfo si;
      while (read(sig_fd_, &si, sizeof si) == sizeof si) {
      }
      c.interrupted = true;
      break;
    }
    if (r > 0 && (fds[0].revents & POLLIN)) {
      read_events();
      continue;
    }
    if (r == 0 && c.any) break;  // quiet for quiet_s: the change is whole
    if (r < 0 && errno != EINTR) break;
  }
  sigprocmask(SIG_SETMASK, &old, nullptr);
  return c;
}

}  // namespace chainsim
