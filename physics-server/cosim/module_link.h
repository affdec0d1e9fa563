// One module process's connection: framed protocol messages over a Unix
// stream socket (Boost.Asio). Errors are returned as text, never thrown.
#pragma once

#include <utility>  // before Asio: Boost 1.74 awaitable.hpp uses std::exchange without it
#include <boost/asio.hpp>

#include <array>
#include <functional>
#include <string>

#include "chainsim_protocol.h"

namespace chainsim {

class ModuleLink {
 public:
  using Socket = boost::asio::local::stream_protocol::socket;
  // called once per receive: error is empty on success (message in received())
  using Handler = std::function<void(const std::string& error)>;

  explicit ModuleLink(Socket socket);

  // encode and write m completely (blocking: frames are small and the peer
  // reads each one); returns an error text, empty on success
  std::string send(const cs_msg& m);

  // read one frame and decode it into received(); handler runs in the io_context
  void async_receive(Handler handler);

  // the lockstep hot path: wait up to timeout_ms for the rest of a frame and
  // decode it into received(). Returns Ready, Pending (not complete yet: call
  // again; bytes read so far are kept) or Failed (then error() says why).
  enum class Receive { Ready, Pending, Failed };
  Receive receive(int timeout_ms);
  const std::string& error() const { return error_; }

  const cs_msg& received() const { return in_; }
  void cancel();
  void close();
  bool open() const { return socket_.is_open(); }

 private:
  // runs the handler of async_receive once with error (empty: a message) and lets it go
  void finish(const std::string& error);
  void on_prefix(const boost::system::error_code& ec);
  void on_body(const boost::system::error_code& ec);
  std::string io_error(const boost::system::error_code& ec) const;

  Socket socket_;
  std::array<uint8_t, 4 + CS_BODY_MAX> rbuf_{};
  std::array<uint8_t, 4 + CS_BODY_MAX> wbuf_{};
  uint32_t body_len_ = 0;
  // the sync path's buffer: bytes received and not yet decoded. It may hold
  // the start of the next frame, which the async path would not see: never
  // call async_receive() after receive() (the server uses async only for HELLO)
  std::array<uint8_t, 2 * (4 + CS_BODY_MAX)> sbuf_{};
  size_t sfill_ = 0;
  std::string error_;
  cs_msg in_{};
  Handler handler_;
};

}  // namespace chainsim
