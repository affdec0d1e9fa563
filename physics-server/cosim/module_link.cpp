#include "cosim/module_link.h"

#include <poll.h>
#include <sys/socket.h>

#include <cerrno>
#include <cstring>

namespace chainsim {

namespace asio = boost::asio;

ModuleLink::ModuleLink(Socket socket) : socket_(std::move(socket)) {}

std::string ModuleLink::send(const cs_msg& m) {
  const char* reason = nullptr;
  const size_t n = cs_encode(&m, wbuf_.data(), wbuf_.size(), &reason);
  if (n == 0) return std::string("server could not encode ") + cs_msg_name(m.type) + ": " + (reason ? reason : "?");
  boost::system::error_code ec;
  asio::write(socket_, asio::buffer(wbuf_.data(), n), ec);
  if (ec) return io_error(ec);
  return {};
}

void ModuleLink::async_receive(Handler handler) {
  handler_ = std::move(handler);
  asio::async_read(socket_, asio::buffer(rbuf_.data(), 4),
                   [this](const boost::system::error_code& ec, size_t) { on_prefix(ec); });
}

ModuleLink::Receive ModuleLink::receive(int timeout_ms) {
  const int fd = socket_.native_handle();
  for (;;) {
    // a whole frame in the buffer: decode it and keep what follows it
    if (sfill_ >= 4) {
      uint32_t len = 0;
      const char* reason = nullptr;
      if (cs_body_length(sbuf_.data(), &len, &reason) != CS_OK) {
        error_ = std::string("sent a malformed frame: ") + (reason ? reason : "bad length");
        return Receive::Failed;
      }
      if (sfill_ >= 4 + len) {
        const int st = cs_decode(sbuf_.data() + 4, len, &in_, &reason);
        sfill_ -= 4 + len;
        std::memmove(sbuf_.data(), sbuf_.data() + 4 + len, sfill_);
        if (st != CS_OK) {
          error_ = std::string("sent a malformed frame: ") + (reason ? reason : "?");
          return Receive::Failed;
        }
        return Receive::Ready;
      }
    }
    // read what is there (usually the whole frame in one call); the buffer
    // holds two frames of the largest size, so a frame always fits after a
    // part of one
    const ssize_t n = ::recv(fd, sbuf_.data() + sfill_, sbuf_.size() - sfill_, MSG_DONTWAIT);
    if (n > 0) {
      sfill_ += static_cast<size_t>(n);
      continue;
    }
    if (n == 0) {
      error_ = "closed its socket";
      return Receive::Failed;
    }
    if (errno == EINTR) continue;
    if (errno != EAGAIN && errno != EWOULDBLOCK) {
      error_ = errno == ECONNRESET ? "closed its socket" : std::string("socket error: ") + std::strerror(errno);
      return Receive::Failed;
    }
    pollfd p{fd, POLLIN, 0};
    const int r = ::poll(&p, 1, timeout_ms);
    if (r == 0) return Receive::Pending;
    if (r < 0 && errno == EINTR) return Receive::Pending;
  }
}

void ModuleLink::finish(const std::string& error) {
  // the handler may own this link (a shared_ptr in its captures): it is let
  // go after it ran, so no link keeps itself alive, and nothing here is
  // touched after it
  const Handler handler = std::move(handler_);
  handler_ = nullptr;
  handler(error);
}

void ModuleLink::on_prefix(const boost::system::error_code& ec) {
  if (ec) return finish(io_error(ec));
  const char* reason = nullptr;
  if (cs_body_length(rbuf_.data(), &body_len_, &reason) != CS_OK)
    return finish(std::string("sent a malformed frame: ") + (reason ? reason : "bad length"));
  asio::async_read(socket_, asio::buffer(rbuf_.data() + 4, body_len_),
                   [this](const boost::system::error_code& e, size_t) { on_body(e); });
}

void ModuleLink::on_body(const boost::system::error_code& ec) {
  if (ec) return finish(io_error(ec));
  const char* reason = nullptr;
  if (cs_decode(rbuf_.data() + 4, body_len_, &in_, &reason) != CS_OK)
    return finish(std::string("sent a malformed frame: ") + (reason ? reason : "?"));
  finish({});
}

std::string ModuleLink::io_error(const boost::system::error_code& ec) const {
  if (ec == asio::error::eof || ec == asio::error::connection_reset || ec == asio::error::broken_pipe)
    return "closed its socket";
  if (ec == asio::error::operation_aborted) return "operation aborted";
  return "socket error: " + ec.message();
}

void ModuleLink::cancel() {
  boost::system::error_code ec;
  socket_.cancel(ec);
}

void ModuleLink::close() {
  boost::system::error_code ec;
  socket_.shutdown(Socket::shutdown_both, ec);
  socket_.close(ec);
}

}  // namespace chainsim
