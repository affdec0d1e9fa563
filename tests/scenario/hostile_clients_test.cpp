// The fault-injection suite, hostile clients on a run's socket: while the
// server waits for its modules, clients connect and send garbage, a HELLO of
// another version or magic, a HELLO naming a module that is not theirs, a
// message other than HELLO, a length of 4 GiB or 0, half a frame and then
// nothing; others connect and close again and again. Each is dropped (or
// rejected) with its reason said, and the run then finishes normally.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>

#include "chainsim_protocol.h"
#include "input_mutator.h"  // SplitMix
#include "scenario_util.h"

using namespace scenario;

namespace {

constexpr int kConnectCloseTimes = 200;

int connect_to(const std::string& path) {
  const int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_un sa{};
  sa.sun_family = AF_UNIX;
  std::snprintf(sa.sun_path, sizeof sa.sun_path, "%s", path.c_str());
  if (connect(fd, reinterpret_cast<sockaddr*>(&sa), sizeof sa) != 0) {
    close(fd);
    return -1;
  }
  return fd;
}

void send_all(int fd, const std::string& bytes) {
  ASSERT_EQ(send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL), static_cast<ssize_t>(bytes.size()));
}

// what the server sends until it closes the connection; *closed false when it
// was still open after timeout_ms
std::string read_until_closed(int fd, int timeout_ms, bool* closed) {
  std::string got;
  *closed = false;
  for (;;) {
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, timeout_ms) <= 0) return got;
    char buf[512];
    const ssize_t n = recv(fd, buf, sizeof buf, 0);
    if (n <= 0) {
      *closed = true;
      return got;
    }
    got.append(buf, static_cast<size_t>(n));
  }
}

std::string frame(const cs_msg& m) {
  uint8_t buf[4 + CS_BODY_MAX];
  const char* reason = nullptr;
  const size_t n = cs_encode(&m, buf, sizeof buf, &reason);
  EXPECT_GT(n, 0u) << reason;
  return std::string(reinterpret_cast<char*>(buf), n);
}

std::string hello(uint16_t index, const char* type, uint32_t pid) {
  cs_msg m{};
  m.type = CS_MSG_HELLO;
  m.u.hello.magic = CS_MAGIC;
  m.u.hello.version = CS_VERSION;
  m.u.hello.module_index = index;
  m.u.hello.pid = pid;
  std::snprintf(m.u.hello.type, CS_TYPE_NAME_MAX, "%s", type);
  return frame(m);
}

std::string prefix(uint32_t len) {
  std::string p(4, '\0');
  for (int i = 0; i < 4; ++i) p[i] = static_cast<char>((len >> (8 * i)) & 0xff);
  return p;
}

// the REJECT reason in bytes the server sent, or "" when there is none
std::string reject_reason(const std::string& got) {
  uint32_t len = 0;
  const char* why = nullptr;
  cs_msg m{};
  if (got.size() < 4 || cs_body_length(reinterpret_cast<const uint8_t*>(got.data()), &len, &why) != CS_OK ||
      got.size() < 4 + len ||
      cs_decode(reinterpret_cast<const uint8_t*>(got.data()) + 4, len, &m, &why) != CS_OK ||
      m.type != CS_MSG_REJECT)
    return "";
  return m.u.reject.reason;
}

size_t count_of(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

pid_t start_program(const std::string& program, const std::vector<std::string>& env, const std::string& out) {
  const pid_t pid = fork();
  if (pid == 0) {
    for (const auto& e : env) putenv(const_cast<char*>(e.c_str()));
    const int fd = open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, 1);
    dup2(fd, 2);
    execl(program.c_str(), program.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  return pid;
}

}  // namespace

TEST(FaultInjection, HostileClientsAreDroppedWithAReasonAndTheRunFinishes) {
  const std::string dir = temp_dir("hostile");
  std::filesystem::create_directory(dir + "/tmp");
  TmpDirForChildren tmp(dir + "/tmp");
  const std::string bin = std::filesystem::path(CHAINSIM_EXE).parent_path().string();
  // module 0 connects only when told: until then a HELLO naming it is a stranger's
  const std::string go = dir + "/go";
  const std::string gated = write_file(
      dir, "gated.sh",
      "#!/bin/sh\ni=0\nwhile [ ! -e " + go + " ] && [ $i -lt 3000 ]; do sleep 0.01; i=$((i+1)); done\nexec " + bin +
          "/fw-rotation\n");
  ASSERT_EQ(chmod(gated.c_str(), 0755), 0);
  const std::string scene =
      write_file(dir, "s.yaml", "name: hostile\nchain:\n  - {type: rotation, firmware: " + gated +
                                    "}\n  - {type: rotation}\n");
  const std::string err = dir + "/stderr.txt";
  // the central control (endpoint 2) is started by this test (--attach), so the server waits
  const pid_t server = start_chainsim({"run", scene, "--attach", "2", "--duration", "0.5", "--module-timeout", "60",
                                       "--out", dir + "/run"},
                                      err);
  std::string said;
  ASSERT_TRUE(wait_until([&] { return (said = read_file(err)).find("CHAINSIM_SOCKET=") != std::string::npos; }, 30))
      << said;
  const size_t at = said.find("CHAINSIM_SOCKET=") + std::strlen("CHAINSIM_SOCKET=");
  const std::string sock = said.substr(at, said.find(' ', at) - at);

  // each client: what it sends, and the line the server must say about it
  struct Client {
    const char* what;
    std::string bytes;
    const char* said;    // in "chainsim: dropped/rejected a connection: ..."
    const char* reject;  // the REJECT reason it must get, or null when simply dropped
  };
  SplitMix r(16);
  std::string noise = prefix(40) + std::string("\x77\x77", 2);
  for (int i = 0; i < 38; ++i) noise += static_cast<char>(r.next() & 0xff);
  std::string bad_version = hello(0, "rotation", 1), bad_magic = bad_version;
  bad_version[10] = 99;  // prefix 4, type 2, magic 4: the version's low byte
  bad_magic[6] = 'X';
  cs_msg end{};
  end.type = CS_MSG_TICK_END;
  end.u.tick_end.wake_time_us = 1000;
  const std::vector<Client> clients = {
      {"an HTTP request", "GET / HTTP/1.1\r\nHost: chainsim\r\n\r\n", "dropped a connection: sent a malformed frame",
       nullptr},
      {"random bytes in a frame", noise, "dropped a connection: sent a malformed frame", nullptr},
      {"a HELLO of protocol version 99", bad_version, "dropped a connection: sent a malformed frame", nullptr},
      {"a HELLO with a wrong magic", bad_magic, "dropped a connection: sent a malformed frame", nullptr},
      {"a length of 4 GiB", prefix(0xffffffffu), "dropped a connection: sent a malformed frame", nullptr},
      {"a length of 0", prefix(0), "dropped a connection: sent a malformed frame", nullptr},
      {"a TICK_END instead of HELLO", frame(end), "dropped a connection: it sent TICK_END instead of HELLO", nullptr},
      {"a HELLO naming module 7 of 3", hello(7, "rotation", getpid()),
       "rejected a connection: module index 7 is not in this scene (3 endpoints)",
       "module index 7 is not in this scene (3 endpoints)"},
      {"a HELLO as module 0 with another pid", hello(0, "rotation", 1),
       "rejected a connection: module 0 was not started by this server (pid 1)",
       "module 0 was not started by this server (pid 1)"},
      {"a HELLO as module 0 of another type", hello(0, "helicoidal", 1),
       "rejected a connection: module 0 is a rotation, not a helicoidal", "module 0 is a rotation, not a helicoidal"},
  };
  int dropped = 0, rejected = 0;
  for (const Client& c : clients) {
    const size_t before = count_of(read_file(err), c.said);
    const int fd = connect_to(sock);
    ASSERT_GE(fd, 0) << c.what << ": " << std::strerror(errno);
    send_all(fd, c.bytes);
    bool closed = false;
    const std::string got = read_until_closed(fd, 5000, &closed);
    close(fd);
    EXPECT_TRUE(closed) << c.what << ": the server kept the connection";
    EXPECT_TRUE(wait_until([&] { return count_of(read_file(err), c.said) == before + 1; }, 5))
        << c.what << ": not said\n" << read_file(err);
    if (c.reject) {
      EXPECT_EQ(reject_reason(got), c.reject) << c.what;
    }
    ++(c.reject ? rejected : dropped);
  }
  // connect and close again and again
  const std::string closed_line = "dropped a connection: closed its socket";
  const size_t before = count_of(read_file(err), closed_line);
  for (int i = 0; i < kConnectCloseTimes; ++i) {
    const int fd = connect_to(sock);
    ASSERT_GE(fd, 0) << i << ": " << std::strerror(errno);
    close(fd);
  }
  EXPECT_TRUE(wait_until([&] { return count_of(read_file(err), closed_line) == before + kConnectCloseTimes; }, 10))
      << count_of(read_file(err), closed_line) - before << " of " << kConnectCloseTimes << " said";
  // half a HELLO and then nothing, and nothing at all: dropped once every module is in
  const int half = connect_to(sock);
  ASSERT_GE(half, 0);
  send_all(half, hello(0, "rotation", 1).substr(0, 14));
  const int silent = connect_to(sock);
  ASSERT_GE(silent, 0);
  EXPECT_TRUE(alive(server));

  // the real modules now: module 0 released, the central control started here
  write_file(dir, "go", "");
  const pid_t central = start_program(bin + "/fw-central",
                                      {"CHAINSIM_SOCKET=" + sock, "CHAINSIM_MODULE_INDEX=2",
                                       "CHAINSIM_MODULE_TYPE=central"},
                                      dir + "/central.out");
  for (int fd : {half, silent}) {
    bool closed = false;
    read_until_closed(fd, 30000, &closed);
    close(fd);
    EXPECT_TRUE(closed) << "a connection that sent no HELLO was kept";
  }
  const std::string no_hello = "dropped a connection: it sent no HELLO before every module had connected";
  EXPECT_TRUE(wait_until([&] { return count_of(read_file(err), no_hello) == 2; }, 10)) << read_file(err);
  // after the handshake nobody is let in
  const int late = connect_to(sock);
  EXPECT_LT(late, 0) << "a connection after the handshake was accepted";
  if (late >= 0) close(late);

  const Outcome o = wait_chainsim(server, dir + "/run", err, 120);
  int st = 0;
  const bool central_ended = wait_until([&] { return waitpid(central, &st, WNOHANG) == central; }, 10);
  if (!central_ended) kill(central, SIGKILL), waitpid(central, &st, 0);
  EXPECT_TRUE(central_ended && WIFEXITED(st) && WEXITSTATUS(st) == 0) << read_file(dir + "/central.out");
  EXPECT_EQ(o.signal, 0);
  EXPECT_EQ(o.exit_code, 0) << o.stderr_text;
  ASSERT_TRUE(o.summary.is_object());
  for (const auto& m : o.summary["modules"]) EXPECT_TRUE(m["fault"].is_null()) << m.dump();
  EXPECT_DOUBLE_EQ(o.summary["sim_time_s"].get<double>(), 0.5);
  EXPECT_TRUE(socket_dirs_in(dir + "/tmp").empty());
  // the discovery found both modules: the central control's log says so
  EXPECT_NE(read_file(o.dir + "/modules/02-central.log").find("chain: RR (2 modules)"), std::string::npos);

  if (std::getenv("CHAINSIM_FUZZ_VERBOSE")) std::printf("%s", read_file(err).c_str());
  std::printf("hostile clients: %zu kinds of bad first message (%d dropped, %d rejected with a REJECT), "
              "%d connect-and-close, 2 silent after connecting: every one said and closed; the run then "
              "finished with exit %d\n",
              clients.size(), dropped, rejected, kConnectCloseTimes, o.exit_code);
}
