// Reliability end to end: a process that dies while asleep is noticed at
// once, module processes see none of the server's files, and scene numbers
// that ODE cannot take are refused with the file, line, column and key.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>

#include <set>
#include <sstream>

#include "scenario_util.h"

using namespace scenario;

namespace {

// the process among kids whose environment says CHAINSIM_MODULE_TYPE=type
pid_t child_of_type(const std::vector<pid_t>& kids, const std::string& type) {
  const std::string want = "CHAINSIM_MODULE_TYPE=" + type + std::string(1, '\0');
  for (pid_t k : kids)
    if (read_file("/proc/" + std::to_string(k) + "/environ").find(want) != std::string::npos) return k;
  return 0;
}

}  // namespace

// the central control of the default scene sleeps between its commands: no
// exchange would notice it gone, only its exit (SIGCHLD) does
TEST(Reliability, CentralControlKilledWhileAsleepIsAModuleFault) {
  const std::string dir = temp_dir("kill-central");
  const std::string err = dir + "/stderr.txt";
  const pid_t server = start_chainsim({"run", "--duration", "40", "--out", dir + "/run"}, err);
  std::vector<pid_t> kids;
  ASSERT_TRUE(wait_until([&] { return (kids = children_of(server)).size() == 9; }, 30));
  ASSERT_TRUE(wait_until([&] { return read_file(dir + "/run/trace.csv").size() > 100000; }, 60));
  const pid_t central = child_of_type(kids, "central");
  ASSERT_GT(central, 0);
  ASSERT_EQ(kill(central, SIGKILL), 0);
  const Outcome o = wait_chainsim(server, dir + "/run", err);
  EXPECT_EQ(o.exit_code, 2) << o.stderr_text;
  ASSERT_TRUE(o.summary.is_object());
  const auto& fault = o.summary["modules"][8]["fault"];
  ASSERT_TRUE(fault.is_string()) << o.summary.dump(2);
  const std::string f = fault.get<std::string>();
  EXPECT_NE(f.find("central control (central, pid " + std::to_string(central) + ")"), std::string::npos) << f;
  EXPECT_NE(f.find("signal 9"), std::string::npos) << f;
  // noticed in the tick it was seen: the run stopped at the fault's time
  std::ostringstream at;
  at.precision(6);
  at << std::fixed << "at t=" << o.summary["sim_time_s"].get<double>() << " s";
  EXPECT_NE(f.find(at.str()), std::string::npos) << f;
  EXPECT_LT(o.summary["sim_time_s"].get<double>(), 40.0);
  EXPECT_EQ(o.summary["stopped_by"], fault);
  for (pid_t k : kids) EXPECT_FALSE(alive(k)) << "orphan " << k;
}

// the central control is a script that lists its open descriptors: it is
// started last, when trace.csv, bus.log and the listening socket are open
TEST(Reliability, ModuleProcessesInheritOnlyStdinStdoutAndStderr) {
  const std::string dir = temp_dir("fds");
  // ls is the shell's child and lists the shell's descriptors with their targets
  const std::string prog = write_file(dir, "list-fds.sh", "#!/bin/sh\nls -l /proc/$$/fd\nexit 7\n");
  ASSERT_EQ(chmod(prog.c_str(), 0755), 0);
  const std::string scene = write_file(
      dir, "s.yaml", "chain:\n  - {type: rotation}\ncentral: {program: " + prog + "}\n");
  const Outcome o = run({scene, "--duration", "1"}, dir);
  EXPECT_EQ(o.exit_code, 2) << o.stderr_text;  // it never connects: a fault naming its exit
  EXPECT_NE(o.stderr_text.find("exit code 7"), std::string::npos) << o.stderr_text;
  const std::string listing = read_file(o.dir + "/modules/01-central.out");
  std::istringstream in(listing);
  std::set<std::string> fds;
  for (std::string line; std::getline(in, line);) {
    const auto arrow = line.find(" -> ");
    if (arrow == std::string::npos) continue;  // "total 0"
    const std::string fd = line.substr(line.rfind(' ', arrow - 1) + 1, arrow - line.rfind(' ', arrow - 1) - 1);
    const std::string target = line.substr(arrow + 4);
    if (target == prog) continue;  // the shell reading its own script
    fds.insert(fd);
  }
  EXPECT_EQ(fds, (std::set<std::string>{"0", "1", "2"})) << listing;
}

// a module program running as the user who runs the server cannot open the
// server's files through /proc/SERVER/fd: the server is not dumpable
// (PR_SET_DUMPABLE 0), so /proc/SERVER/* belongs to root. Root may read any
// process's /proc: run as root, the test runs the server and its modules as
// nobody (setpriv), where the protection applies.
TEST(Reliability, AModuleCannotOpenTheServersFilesThroughProc) {
  const std::string dir = temp_dir("proc-fd");
  const std::string prog = write_file(dir, "peek.sh", "#!/bin/sh\nls -l /proc/$PPID/fd 2>&1\nexit 7\n");
  ASSERT_EQ(chmod(prog.c_str(), 0755), 0);
  const std::string scene = write_file(dir, "s.yaml", "chain:\n  - {type: rotation}\ncentral: {program: " + prog + "}\n");
  std::string as_user;
  if (geteuid() == 0) {
    if (std::system("command -v setpriv >/dev/null 2>&1") != 0) GTEST_SKIP() << "root without setpriv(1): cannot run as another user";
    ASSERT_EQ(std::system(("chown -R 65534:65534 " + dir).c_str()), 0);
    as_user = "setpriv --reuid=65534 --regid=65534 --clear-groups env TMPDIR=" + dir + " ";
  }
  const std::string cmd = "cd " + dir + " && " + as_user + CHAINSIM_EXE + " run s.yaml --duration 1 --out " + dir +
                          "/run >" + dir + "/err.txt 2>&1";
  const int st = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(st)) << cmd;
  EXPECT_EQ(WEXITSTATUS(st), 2) << read_file(dir + "/err.txt");  // the central control never connects
  const std::string listing = read_file(dir + "/run/modules/01-central.out");
  EXPECT_NE(listing.find("Permission denied"), std::string::npos) << listing;
  EXPECT_EQ(listing.find(" -> "), std::string::npos) << "the module listed the server's descriptors:\n" << listing;
}

// ODE aborts on a NaN position (dxNormalize4): the reader refuses it first,
// naming the key, with exit 1 and no signal
TEST(Reliability, NonFiniteStartPositionIsRefusedBeforeODE) {
  const std::string dir = temp_dir("nan-pos");
  const std::string scene =
      write_file(dir, "s.yaml", "chain: RR\nplacement:\n  position_m: [0, .nan, 0.02]\n");
  const Outcome o = run({scene, "--duration", "1"}, dir);
  EXPECT_EQ(o.signal, 0);
  EXPECT_EQ(o.exit_code, 1) << o.stderr_text;
  EXPECT_NE(o.stderr_text.find(scene + ":3:19: 'placement.position_m[1]' must be a finite number"),
            std::string::npos)
      << o.stderr_text;
}

// a device read without end and a FIFO that blocks the reader are refused
// before they are opened
TEST(Reliability, InputFilesMustBeRegularFiles) {
  const std::string dir = temp_dir("special-files");
  const std::string types = write_file(dir, "t.yaml", "chain:\n  - {type: x}\nmodule_types: {x: /dev/zero}\n");
  const Outcome a = run({types, "--duration", "1"}, temp_dir("special-a"));
  EXPECT_EQ(a.exit_code, 1) << a.stderr_text;
  EXPECT_NE(a.stderr_text.find("/dev/zero: cannot read module definition file: not a regular file"),
            std::string::npos)
      << a.stderr_text;
  const std::string fifo = dir + "/pipe.stl";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  const std::string mesh =
      write_file(dir, "m.yaml", "chain: R\nenvironment:\n  type: mesh\n  mesh: {file: pipe.stl}\n");
  const Outcome b = run({mesh, "--duration", "1"}, temp_dir("special-b"));
  EXPECT_EQ(b.exit_code, 1) << b.stderr_text;
  EXPECT_NE(b.stderr_text.find("pipe.stl': not a regular file"), std::string::npos) << b.stderr_text;
}
