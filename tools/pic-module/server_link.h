// The module process's end of the socket to the physics server: the same
// protocol a native module's hal-sim speaks (protocol/, docs/protocol.md).
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "chainsim_protocol.h"

namespace chainsim::pic {

class LinkError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class ServerLink {
 public:
  ServerLink() = default;
  ~ServerLink();
  ServerLink(const ServerLink&) = delete;
  ServerLink& operator=(const ServerLink&) = delete;

  // connect to the Unix socket at path, retrying for 3 s while it is not there yet
  void connect(const std::string& path);
  // HELLO, then WELCOME (returned); a REJECT throws with the server's reason
  cs_welcome hello(uint16_t index, const std::string& type);
  // the next TICK_BEGIN; false when the server says SHUTDOWN
  bool next_tick(cs_tick_begin* tb);
  void send_tick_end(const cs_tick_end& te);

 private:
  void send(const cs_msg& m);
  const cs_msg& receive();
  int fd_ = -1;
  std::vector<uint8_t> rx_;
  cs_msg msg_{};
};

}  // namespace chainsim::pic
