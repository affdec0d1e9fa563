// The socket to the physics server. See server_link.h.
#include "pic-module/server_link.h"

#include <errno.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <time.h>
#include <unistd.h>

#include <cstring>

namespace chainsim::pic {

ServerLink::~ServerLink() {
  if (fd_ >= 0) close(fd_);
}

void ServerLink::connect(const std::string& path) {
  sockaddr_un sa{};
  if (path.empty() || path.size() >= sizeof sa.sun_path)
    throw LinkError("CHAINSIM_SOCKET: path length " + std::to_string(path.size()) + " not in 1.." +
                    std::to_string(sizeof sa.sun_path - 1));
  sa.sun_family = AF_UNIX;
  std::memcpy(sa.sun_path, path.c_str(), path.size() + 1);
  for (int waited_ms = 0;; waited_ms += 10) {
    const int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) throw LinkError(std::string("socket(): ") + std::strerror(errno));
    if (::connect(fd, reinterpret_cast<const sockaddr*>(&sa), sizeof sa) == 0) {
      fd_ = fd;
      return;
    }
    const int e = errno;
    close(fd);
    if ((e != ENOENT && e != ECONNREFUSED && e != EINTR && e != EAGAIN) || waited_ms >= 3000)
      throw LinkError("cannot connect to " + path + " (CHAINSIM_SOCKET): " + std::strerror(e));
    const timespec ts{0, 10 * 1000 * 1000};
    nanosleep(&ts, nullptr);
  }
}

void ServerLink::send(const cs_msg& m) {
  uint8_t buf[4 + CS_BODY_MAX];
  const char* reason = "?";
  const size_t n = cs_encode(&m, buf, sizeof buf, &reason);
  if (n == 0) throw LinkError(std::string("cannot encode ") + cs_msg_name(m.type) + ": " + reason);
  for (size_t off = 0; off < n;) {
    const ssize_t w = ::send(fd_, buf + off, n - off, MSG_NOSIGNAL);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) throw LinkError("the server closed the connection");
    off += static_cast<size_t>(w);
  }
}

const cs_msg& ServerLink::receive() {
  auto fill = [&](size_t need) {
    while (rx_.size() < need) {
      pollfd p{fd_, POLLIN, 0};
      if (poll(&p, 1, -1) < 0) {
        if (errno == EINTR) continue;
        throw LinkError(std::string("poll(): ") + std::strerror(errno));
      }
      uint8_t b[4096];
      const ssize_t r = read(fd_, b, sizeof b);
      if (r == 0) throw LinkError("the server closed the connection");
      if (r < 0) {
        if (errno == EINTR) continue;
        throw LinkError(std::string("read(): ") + std::strerror(errno));
      }
      rx_.insert(rx_.end(), b, b + r);
    }
  };
  fill(4);
  uint32_t len = 0;
  const char* reason = "?";
  if (cs_body_length(rx_.data(), &len, &reason) != CS_OK) throw LinkError(std::string("bad frame length: ") + reason);
  fill(4 + len);
  if (cs_decode(rx_.data() + 4, len, &msg_, &reason) != CS_OK)
    throw LinkError(std::string("undecodable frame from the server: ") + reason);
  rx_.erase(rx_.begin(), rx_.begin() + 4 + len);
  return msg_;
}

cs_welcome ServerLink::hello(uint16_t index, const std::string& type) {
  cs_msg m{};
  m.type = CS_MSG_HELLO;
  m.u.hello.magic = static_cast<uint32_t>(CS_MAGIC);
  m.u.hello.version = CS_VERSION;
  m.u.hello.module_index = index;
  m.u.hello.pid = static_cast<uint32_t>(getpid());
  std::strncpy(m.u.hello.type, type.c_str(), CS_TYPE_NAME_MAX - 1);
  send(m);
  const cs_msg& r = receive();
  if (r.type == CS_MSG_REJECT) throw LinkError(std::string("the server rejected this module: ") + r.u.reject.reason);
  if (r.type != CS_MSG_WELCOME)
    throw LinkError(std::string("expected WELCOME after HELLO, got ") + cs_msg_name(r.type));
  if (r.u.welcome.module_index != index || r.u.welcome.tick_us == 0)
    throw LinkError("a WELCOME for module " + std::to_string(r.u.welcome.module_index) + " with tick " +
                    std::to_string(r.u.welcome.tick_us) + " us");
  return r.u.welcome;
}

bool ServerLink::next_tick(cs_tick_begin* tb) {
  const cs_msg& r = receive();
  if (r.type == CS_MSG_SHUTDOWN) return false;
  if (r.type != CS_MSG_TICK_BEGIN) throw LinkError(std::string("expected TICK_BEGIN, got ") + cs_msg_name(r.type));
  *tb = r.u.tick_begin;
  return true;
}

void ServerLink::send_tick_end(const cs_tick_end& te) {
  cs_msg m{};
  m.type = CS_MSG_TICK_END;
  m.u.tick_end = te;
  send(m);
}

}  // namespace chainsim::pic
