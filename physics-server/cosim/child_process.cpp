#include "cosim/child_process.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

extern char** environ;

namespace chainsim {

std::string ExitStatus::text() const {
  if (exited) return "exit code " + std::to_string(code);
  return "signal " + std::to_string(signal) + " (" + strsignal(signal) + ")";
}

namespace {

std::atomic<unsigned> child_ends{0};
static_assert(std::atomic<unsigned>::is_always_lock_free, "counted in a signal handler");

void on_sigchld(int) { child_ends.fetch_add(1, std::memory_order_relaxed); }

// once, before the first child: SA_RESTART so no blocking call sees EINTR
void count_child_ends() {
  static const bool installed = [] {
    struct sigaction sa {};
    sa.sa_handler = on_sigchld;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART | SA_NOCLDSTOP;
    sigaction(SIGCHLD, &sa, nullptr);
    return true;
  }();
  (void)installed;
}

}  // namespace

unsigned child_end_count() { return child_ends.load(std::memory_order_relaxed); }

ChildProcess::~ChildProcess() {
  if (running()) terminate(200);
}

void ChildProcess::spawn(const ChildSpec& spec) {
  // everything the child needs is prepared before fork: no allocation after
  std::vector<std::string> env_strings;
  for (char** e = environ; *e; ++e) env_strings.emplace_back(*e);
  for (const auto& e : spec.env) env_strings.push_back(e);
  std::vector<char*> envp;
  for (auto& e : env_strings) envp.push_back(e.data());
  envp.push_back(nullptr);
  std::vector<std::string> arg_strings{spec.program};
  arg_strings.insert(arg_strings.end(), spec.args.begin(), spec.args.end());
  std::vector<char*> argv;
  for (auto& a : arg_strings) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t parent = getpid();
  count_child_ends();
  const int max_fd = static_cast<int>(sysconf(_SC_OPEN_MAX));  // for the fallback of close_range

  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error(std::string("fork failed: ") + strerror(errno));
  if (pid == 0) {
    // child: own process group (a terminal's Ctrl-C reaches only the server,
    // which then ends the modules in order), killed if the server dies
    setpgid(0, 0);
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(126);
    if (spec.stdout_fd >= 0) {
      dup2(spec.stdout_fd, 1);
      dup2(spec.stdout_fd, 2);
    } else if (!spec.stdout_path.empty()) {
      const int fd = open(spec.stdout_path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
      if (fd >= 0) {
        dup2(fd, 1);
        dup2(fd, 2);
      }
    }
    const int devnull = open("/dev/null", O_RDONLY);
    if (devnull >= 0) dup2(devnull, 0);
    // only stdin, stdout and stderr go on: not the server's outputs, its
    // listening socket or another module's link, whoever opened them
    if (close_range(3, ~0U, 0) != 0)
      for (int fd = 3; fd < max_fd; ++fd) close(fd);
    signal(SIGPIPE, SIG_DFL);
    signal(SIGXFSZ, SIG_DFL);
    execve(argv[0], argv.data(), envp.data());
    const char* msg = "chainsim: cannot execute ";
    (void)!write(2, msg, strlen(msg));
    (void)!write(2, argv[0], strlen(argv[0]));
    (void)!write(2, ": ", 2);
    const char* why = strerror(errno);
    (void)!write(2, why, strlen(why));
    (void)!write(2, "\n", 1);
    _exit(127);
  }
  setpgid(pid, pid);  // also from the parent, so no race with kill(-pgid)
  pid_ = pid;
  status_.reset();
}

namespace {

ExitStatus decode(int st) {
  ExitStatus s;
  if (WIFEXITED(st)) {
    s.exited = true;
    s.code = WEXITSTATUS(st);
  } else if (WIFSIGNALED(st)) {
    s.signal = WTERMSIG(st);
  }
  return s;
}

}  // namespace

const std::optional<ExitStatus>& ChildProcess::poll() {
  if (pid_ <= 0 || status_) return status_;
  int st = 0;
  const pid_t r = waitpid(pid_, &st, WNOHANG);
  if (r == pid_) status_ = decode(st);
  return status_;
}

const ExitStatus& ChildProcess::wait() {
  if (pid_ <= 0) throw std::logic_error("ChildProcess::wait: no process was spawned");
  while (!status_) {
    int st = 0;
    const pid_t r = waitpid(pid_, &st, 0);
    if (r == pid_) status_ = decode(st);
    else if (r < 0 && errno != EINTR)
      throw std::runtime_error(std::string("waitpid failed: ") + strerror(errno));
  }
  return *status_;
}

int wait_any(const std::vector<ChildProcess*>& children) {
  for (;;) {
    bool any = false;
    for (size_t i = 0; i < children.size(); ++i) {
      if (!children[i]->running()) continue;
      any = true;
      if (children[i]->poll()) return static_cast<int>(i);
    }
    if (!any) return -1;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
}

const std::optional<ExitStatus>& ChildProcess::wait_for(int timeout_ms) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  while (!poll() && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  return status_;
}

void ChildProcess::terminate(int grace_ms) { terminate_all({this}, grace_ms); }

void terminate_all(std::vector<ChildProcess*> children, int grace_ms) {
  for (auto* c : children)
    if (c->running()) kill(-c->pid(), SIGTERM);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(grace_ms);
  for (;;) {
    bool left = false;
    for (auto* c : children) left |= c->running() && !c->poll();
    if (!left || std::chrono::steady_clock::now() >= deadline) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  for (auto* c : children) {
    if (c->running() && !c->poll()) {
      kill(-c->pid(), SIGKILL);
      c->wait_for(5000);
    }
  }
}

void become_subreaper() { prctl(PR_SET_CHILD_SUBREAPER, 1); }

int end_adopted_orphans(const std::vector<pid_t>& keep) {
  const pid_t self = getpid();
  int ended = 0;
  for (int round = 0; round < 100; ++round) {
    std::vector<pid_t> found;
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator("/proc", ec)) {
      const std::string name = e.path().filename().string();
      if (name.empty() || name.find_first_not_of("0123456789") != std::string::npos) continue;
      std::ifstream in(e.path() / "stat");
      std::string line;
      if (!std::getline(in, line)) continue;
      const size_t close = line.rfind(')');  // the name may hold spaces and parentheses
      if (close == std::string::npos) continue;
      std::istringstream rest(line.substr(close + 2));
      char state = 0;
      long ppid = 0;
      rest >> state >> ppid;
      const pid_t pid = static_cast<pid_t>(std::stol(name));
      if (ppid == self && std::find(keep.begin(), keep.end(), pid) == keep.end()) found.push_back(pid);
    }
    if (found.empty()) break;
    for (pid_t pid : found) {
      kill(pid, SIGKILL);
      waitpid(pid, nullptr, 0);
      ++ended;
    }
  }
  return ended;
}

std::string executable_dir() {
  char buf[4096];
  const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
  if (n <= 0) return ".";
  std::string p(buf, static_cast<size_t>(n));
  const auto slash = p.rfind('/');
  return slash == std::string::npos ? "." : p.substr(0, slash);
}

}  // namespace chainsim
