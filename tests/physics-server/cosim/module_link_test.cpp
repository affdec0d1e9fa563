// ModuleLink over a real Unix socket pair: frames that arrive in pieces or
// two at once, a garbage frame, a closed peer, the handshake's async path.
#include <gtest/gtest.h>

#include <signal.h>

#include <cstring>
#include <string>
#include <vector>

#include "cosim/module_link.h"

namespace chainsim {
namespace {

namespace asio = boost::asio;
using Socket = asio::local::stream_protocol::socket;

struct Pair {
  asio::io_context io;
  Socket ours{io}, theirs{io};
  Pair() { asio::local::connect_pair(ours, theirs); }
  // raw bytes from the module's side
  void write(const std::vector<uint8_t>& bytes) { asio::write(theirs, asio::buffer(bytes)); }
  void write(const std::vector<uint8_t>& bytes, size_t from, size_t to) {
    asio::write(theirs, asio::buffer(bytes.data() + from, to - from));
  }
};

std::vector<uint8_t> frame(const cs_msg& m) {
  std::vector<uint8_t> buf(4 + CS_BODY_MAX);
  const char* reason = nullptr;
  const size_t n = cs_encode(&m, buf.data(), buf.size(), &reason);
  EXPECT_GT(n, 0u) << (reason ? reason : "");
  buf.resize(n);
  return buf;
}

cs_msg tick_end(uint64_t wake_us, int32_t setpoint, const char* log) {
  cs_msg m{};
  m.type = CS_MSG_TICK_END;
  cs_tick_end& te = m.u.tick_end;
  te.wake_time_us = wake_us;
  te.n_servos = 2;
  te.servo_enable = 0x3;
  te.servo_setpoint[0] = setpoint;
  te.servo_setpoint[1] = -setpoint;
  te.n_log = 1;
  std::snprintf(te.log[0], CS_LOG_LINE_MAX, "%s", log);
  return m;
}

// a TickEnd split over three writes, the cut inside the length prefix and
// inside the body: Pending until the last byte, then the whole message
TEST(ModuleLink, TickEndSplitAcrossReadsIsDecodedWhole) {
  Pair p;
  ModuleLink link(std::move(p.ours));
  const std::vector<uint8_t> f = frame(tick_end(123456, 45000, "split in three"));
  ASSERT_GT(f.size(), 20u);
  EXPECT_EQ(link.receive(0), ModuleLink::Receive::Pending);  // nothing yet
  p.write(f, 0, 2);
  EXPECT_EQ(link.receive(10), ModuleLink::Receive::Pending);
  p.write(f, 2, 15);
  EXPECT_EQ(link.receive(10), ModuleLink::Receive::Pending);
  p.write(f, 15, f.size());
  ASSERT_EQ(link.receive(1000), ModuleLink::Receive::Ready) << link.error();
  const cs_msg& m = link.received();
  ASSERT_EQ(m.type, CS_MSG_TICK_END);
  EXPECT_EQ(m.u.tick_end.wake_time_us, 123456u);
  EXPECT_EQ(m.u.tick_end.servo_setpoint[0], 45000);
  EXPECT_EQ(m.u.tick_end.servo_setpoint[1], -45000);
  EXPECT_STREQ(m.u.tick_end.log[0], "split in three");
}

// two frames in one write: the second is kept for the next receive
TEST(ModuleLink, TwoFramesInOneReadAreBothDelivered) {
  Pair p;
  ModuleLink link(std::move(p.ours));
  std::vector<uint8_t> both = frame(tick_end(1000, 1, "first"));
  const std::vector<uint8_t> second = frame(tick_end(2000, 2, "second"));
  both.insert(both.end(), second.begin(), second.end());
  p.write(both);
  ASSERT_EQ(link.receive(1000), ModuleLink::Receive::Ready);
  EXPECT_EQ(link.received().u.tick_end.wake_time_us, 1000u);
  ASSERT_EQ(link.receive(0), ModuleLink::Receive::Ready);  // no new bytes needed
  EXPECT_EQ(link.received().u.tick_end.wake_time_us, 2000u);
  EXPECT_STREQ(link.received().u.tick_end.log[0], "second");
  EXPECT_EQ(link.receive(0), ModuleLink::Receive::Pending);
}

TEST(ModuleLink, GarbageLengthPrefixFailsNamingTheFrame) {
  Pair p;
  ModuleLink link(std::move(p.ours));
  p.write({0xff, 0xff, 0xff, 0x7f, 1, 2, 3});  // a body far over CS_BODY_MAX
  ASSERT_EQ(link.receive(1000), ModuleLink::Receive::Failed);
  EXPECT_EQ(link.error().rfind("sent a malformed frame: ", 0), 0u) << link.error();
}

TEST(ModuleLink, UndecodableBodyFailsNamingTheFrame) {
  Pair p;
  ModuleLink link(std::move(p.ours));
  // a well-formed length (4) and a body of an unknown message type
  p.write({4, 0, 0, 0, 0x77, 0x00, 0, 0});
  ASSERT_EQ(link.receive(1000), ModuleLink::Receive::Failed);
  EXPECT_EQ(link.error().rfind("sent a malformed frame: ", 0), 0u) << link.error();
}

TEST(ModuleLink, ClosedPeerIsReportedAsSuch) {
  Pair p;
  ModuleLink link(std::move(p.ours));
  const std::vector<uint8_t> f = frame(tick_end(1000, 0, "cut"));
  p.write(f, 0, 6);  // half a frame, then the module dies
  p.theirs.close();
  ASSERT_EQ(link.receive(1000), ModuleLink::Receive::Failed);
  EXPECT_EQ(link.error(), "closed its socket");
}

TEST(ModuleLink, SendWritesOneWholeFrame) {
  Pair p;
  ModuleLink link(std::move(p.ours));
  cs_msg m{};
  m.type = CS_MSG_SHUTDOWN;
  std::snprintf(m.u.shutdown.reason, CS_REASON_MAX, "run finished");
  ASSERT_EQ(link.send(m), "");
  const std::vector<uint8_t> want = frame(m);
  std::vector<uint8_t> got(want.size());
  asio::read(p.theirs, asio::buffer(got));
  EXPECT_EQ(got, want);
  // a peer that has gone: send says so instead of throwing (the server
  // ignores SIGPIPE, as here)
  signal(SIGPIPE, SIG_IGN);
  p.theirs.close();
  std::string err;
  for (int k = 0; k < 100 && err.empty(); ++k) err = link.send(m);  // the first may still be buffered
  EXPECT_EQ(err, "closed its socket");
}

// the handshake path: a HELLO read with async_receive in the io_context
TEST(ModuleLink, AsyncReceiveDeliversAHello) {
  Pair p;
  auto link = std::make_shared<ModuleLink>(std::move(p.ours));
  cs_msg h{};
  h.type = CS_MSG_HELLO;
  h.u.hello.magic = CS_MAGIC;
  h.u.hello.version = CS_VERSION;
  h.u.hello.module_index = 3;
  h.u.hello.pid = 4242;
  std::snprintf(h.u.hello.type, CS_TYPE_NAME_MAX, "rotation");
  std::string error = "not called";
  link->async_receive([&](const std::string& e) { error = e; });
  const std::vector<uint8_t> f = frame(h);
  p.write(f, 0, 3);
  p.io.poll();
  EXPECT_EQ(error, "not called");  // waits for the rest
  p.write(f, 3, f.size());
  p.io.run_for(std::chrono::seconds(5));
  EXPECT_EQ(error, "");
  EXPECT_EQ(link->received().type, CS_MSG_HELLO);
  EXPECT_EQ(link->received().u.hello.module_index, 3u);
  EXPECT_STREQ(link->received().u.hello.type, "rotation");
}

}  // namespace
}  // namespace chainsim
