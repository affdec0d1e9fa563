// Module processes: spawn with their environment, end them, and say how they ended.
#pragma once

#include <sys/types.h>

#include <optional>
#include <string>
#include <vector>

namespace chainsim {

struct ChildSpec {
  std::string program;                   // path of the executable
  std::vector<std::string> args;         // argv[1..]
  std::vector<std::string> env;          // extra NAME=VALUE entries
  std::string stdout_path;               // where its stdout and stderr go
  int stdout_fd = -1;                    // or an open file of the caller's (then stdout_path is not used)
};

// how a process ended, in words: "exit code 3", "signal 9 (Killed)"
struct ExitStatus {
  bool exited = false;
  int code = 0;       // exit code when exited
  int signal = 0;     // signal number when killed
  std::string text() const;
};

class ChildProcess {
 public:
  ChildProcess() = default;
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  // fork and exec; the child gets its own process group and dies with the
  // server (PR_SET_PDEATHSIG); it inherits only stdin (/dev/null), stdout
  // and stderr, no other file of the server (close_range after fork).
  // Throws std::runtime_error if fork fails; an exec failure shows as exit
  // code 127 with a message in its output file.
  void spawn(const ChildSpec& spec);

  pid_t pid() const { return pid_; }
  bool running() const { return pid_ > 0 && !status_; }

  // non-blocking reap; the status once the process has ended
  const std::optional<ExitStatus>& poll();
  // wait up to timeout_ms for the process to end
  const std::optional<ExitStatus>& wait_for(int timeout_ms);
  // wait for the process to end, however long it takes; throws
  // std::logic_error when nothing was spawned
  const ExitStatus& wait();
  // SIGTERM, then SIGKILL after grace_ms; always reaps
  void terminate(int grace_ms);

 private:
  pid_t pid_ = -1;
  std::optional<ExitStatus> status_;
};

// how many SIGCHLDs this process has had since its first spawn(): a run
// compares it with the count it last saw, so a child that dies while nobody
// talks to it is noticed without a system call when nothing happened
unsigned child_end_count();

// wait until one of the running children has ended; its index (the lowest
// when several have), or -1 when none of them is running
int wait_any(const std::vector<ChildProcess*>& children);

// end all of them: SIGTERM to each, then SIGKILL to those left after grace_ms
void terminate_all(std::vector<ChildProcess*> children, int grace_ms);

// directory of the running executable (/proc/self/exe)
std::string executable_dir();

// makes this process the reaper of its descendants' orphans
// (PR_SET_CHILD_SUBREAPER): a process a module started and left behind, even
// one that called setsid(), becomes this process's child instead of init's
void become_subreaper();

// ends (SIGKILL) and reaps every child of this process that is not in keep:
// after the run's own children have ended, those are the orphans it adopted.
// Returns how many; repeats while killing them leaves new orphans
int end_adopted_orphans(const std::vector<pid_t>& keep = {});

}  // namespace chainsim
