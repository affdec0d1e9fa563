// Specification tests for the chainsim wire protocol (protocol/chainsim_protocol.h).
//
// Frame = u32 body_len LE | body, body = u16 type LE | payload. Payload fields
// go in struct order, little-endian; arrays are count-prefixed and only the
// counted entries travel; strings are u8 length + bytes without NUL.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "chainsim_protocol.h"
#include "protocol_messages.h"

namespace {

using namespace protocol_test;

// ---------------------------------------------------------------------------
// frame and length prefix
// ---------------------------------------------------------------------------

TEST(LengthPrefix, IsLittleEndianU32) {
    const uint8_t p[4] = {0x01, 0x02, 0x00, 0x00};
    uint32_t n = 0;
    const char *reason = nullptr;
    ASSERT_EQ(cs_body_length(p, &n, &reason), CS_OK);
    EXPECT_EQ(n, 0x0201u);
}

TEST(LengthPrefix, AcceptsTwoUpToBodyMax) {
    uint32_t n = 0;
    for (uint32_t len : {2u, 3u, 100u, CS_BODY_MAX}) {
        Bytes p = prefix_of(len);
        EXPECT_EQ(cs_body_length(p.data(), &n, nullptr), CS_OK) << len;
        EXPECT_EQ(n, len);
    }
}

TEST(LengthPrefix, RejectsZeroShorterThanTypeAndOverBodyMax) {
    for (uint32_t len : {0u, 1u, CS_BODY_MAX + 1u, 0x00010000u, 0xFFFFFFFFu}) {
        Bytes p = prefix_of(len);
        uint32_t n = 12345;
        const char *reason = nullptr;
        EXPECT_EQ(cs_body_length(p.data(), &n, &reason), CS_ERR) << len;
        ASSERT_NE(reason, nullptr);
        EXPECT_NE(std::string(reason).find("body"), std::string::npos) << reason;
        EXPECT_EQ(n, 12345u) << "output untouched on error";
    }
}

// ---------------------------------------------------------------------------
// byte-exact layout
// ---------------------------------------------------------------------------

TEST(ByteExact, HelloFrameMatchesHandWrittenBytes) {
    cs_msg m{};
    m.type = CS_MSG_HELLO;
    m.u.hello.magic = CS_MAGIC;
    m.u.hello.version = CS_VERSION;
    m.u.hello.module_index = 2;
    m.u.hello.pid = 0x01020304;
    set_str(m.u.hello.type, CS_TYPE_NAME_MAX, "arm");
    const Bytes expected = {
        0x12, 0x00, 0x00, 0x00,  // body_len = 18
        0x01, 0x00,              // type HELLO
        'C',  'H',  'S',  'M',   // magic 0x4D534843
        0x02, 0x00,              // version 2
        0x02, 0x00,              // module_index 2
        0x04, 0x03, 0x02, 0x01,  // pid 0x01020304
        0x03, 'a',  'r',  'm',   // type name: length 3, no NUL
    };
    EXPECT_EQ(encode(m), expected);
    EXPECT_EQ(HelloWire({CS_MAGIC, CS_VERSION, 2, 0x01020304, "arm"}).body(), body_of(expected));
}

TEST(ByteExact, TickEndFrameMatchesHandWrittenBytes) {
    cs_msg m{};
    m.type = CS_MSG_TICK_END;
    auto &t = m.u.tick_end;
    t.wake_time_us = 0x0102030405060708ull;
    t.wake_events = CS_WAKE_I2C;
    t.sout_level = 1;
    t.i2c_address = 0x10;
    t.n_servos = 1;
    t.servo_enable = 0x01;
    t.servo_setpoint[0] = -90000;  // -90 degrees in millidegrees
    t.servo_setpoint[1] = 777;     // beyond n_servos: not sent
    t.n_i2c = 1;
    t.i2c[0].addr = 0x11;
    t.i2c[0].len = 2;
    t.i2c[0].data[0] = 0xAA;
    t.i2c[0].data[1] = 0xBB;
    t.n_log = 1;
    set_str(t.log[0], CS_LOG_LINE_MAX, "hi");
    const Bytes expected = {
        0x1C, 0x00, 0x00, 0x00,                          // body_len = 28
        0x05, 0x00,                                      // type TICK_END
        0x08, 0x07, 0x06, 0x05, 0x04, 0x03, 0x02, 0x01,  // wake_time_us
        0x02,                                            // wake_events = CS_WAKE_I2C
        0x01,                                            // sout_level
        0x10,                                            // i2c_address
        0x01,                                            // n_servos
        0x01,                                            // servo_enable
        0x70, 0xA0, 0xFE, 0xFF,                          // setpoint -90000 (two's complement)
        0x01,                                            // n_i2c
        0x11, 0x02, 0xAA, 0xBB,                          // addr, len, data
        0x01,                                            // n_log
        0x02, 'h',  'i',                                 // line: length 2, no NUL
    };
    EXPECT_EQ(encode(m), expected);
}

TEST(ByteExact, HandWrittenBodiesOfEveryTypeDecode) {
    EXPECT_TRUE(Accepted(HelloWire{}.body()));
    EXPECT_TRUE(Accepted(WelcomeWire{}.body()));
    EXPECT_TRUE(Accepted(ReasonWire{}.body()));
    EXPECT_TRUE(Accepted(ReasonWire{CS_MSG_SHUTDOWN, "scene over"}.body()));
    EXPECT_TRUE(Accepted(TickBeginWire{}.body()));
    EXPECT_TRUE(Accepted(TickEndWire{}.body()));

    Decoded d = decode(TickBeginWire{}.body());
    ASSERT_TRUE(d.ok);
    EXPECT_EQ(d.msg.type, CS_MSG_TICK_BEGIN);
    EXPECT_EQ(d.msg.u.tick_begin.time_us, 20000u);
    ASSERT_EQ(d.msg.u.tick_begin.n_servos, 2);
    EXPECT_EQ(d.msg.u.tick_begin.servo_pos[1], -45000);
    EXPECT_EQ(d.msg.u.tick_begin.servo_pos[2], 0) << "entries beyond the count read as zero";
    ASSERT_EQ(d.msg.u.tick_begin.n_adc, 3);
    EXPECT_EQ(d.msg.u.tick_begin.adc[2], 1023);
    ASSERT_EQ(d.msg.u.tick_begin.n_i2c, 1);
    EXPECT_EQ(d.msg.u.tick_begin.i2c[0].len, 3);
    EXPECT_EQ(d.msg.u.tick_begin.i2c[0].data[2], 3);
}

// ---------------------------------------------------------------------------
// round trips
// ---------------------------------------------------------------------------

// Largest frame of each type (length prefix included); all fit in CS_BODY_MAX.

TEST(RoundTrip, HelloWithMaximalContents) { expect_round_trip(max_hello(), kHelloMax); }
TEST(RoundTrip, WelcomeWithMaximalContents) { expect_round_trip(max_welcome(), kWelcomeMax); }
TEST(RoundTrip, RejectWithMaximalContents) {
    expect_round_trip(max_reason(CS_MSG_REJECT), kReasonMax);
}
TEST(RoundTrip, TickBeginWithMaximalContents) {
    expect_round_trip(max_tick_begin(), kTickBeginMax);
}
TEST(RoundTrip, TickEndWithMaximalContents) { expect_round_trip(max_tick_end(), kTickEndMax); }
TEST(RoundTrip, ShutdownWithMaximalContents) {
    expect_round_trip(max_reason(CS_MSG_SHUTDOWN), kReasonMax);
}

TEST(RoundTrip, MinimalMessagesOfEveryType) {
    // body sizes: HELLO with a 1-char name, WELCOME without params, empty
    // REJECT, TICK_BEGIN with all counts 0 (and i2c_tx_queued), TICK_END with
    // one empty log line, empty SHUTDOWN
    const size_t sizes[] = {4 + 16, 4 + 19, 4 + 3, 4 + 20, 4 + 18, 4 + 3};
    auto msgs = min_messages();
    for (size_t i = 0; i < msgs.size(); i++) expect_round_trip(msgs[i], sizes[i]);
}

TEST(RoundTrip, OnlyCountedEntriesTravel) {
    cs_msg a = max_tick_begin();
    a.u.tick_begin.n_servos = 1;
    a.u.tick_begin.n_adc = 0;
    cs_msg b = a;
    b.u.tick_begin.servo_pos[3] = 1;  // beyond the counts: not part of the message
    b.u.tick_begin.adc[0] = 0xFFFF;   // not even checked against CS_ADC_COUNTS_MAX
    EXPECT_EQ(encode(a), encode(b));
}

TEST(MessageNames, NameEveryTypeAndUnknown) {
    EXPECT_STREQ(cs_msg_name(CS_MSG_HELLO), "HELLO");
    EXPECT_STREQ(cs_msg_name(CS_MSG_WELCOME), "WELCOME");
    EXPECT_STREQ(cs_msg_name(CS_MSG_REJECT), "REJECT");
    EXPECT_STREQ(cs_msg_name(CS_MSG_TICK_BEGIN), "TICK_BEGIN");
    EXPECT_STREQ(cs_msg_name(CS_MSG_TICK_END), "TICK_END");
    EXPECT_STREQ(cs_msg_name(CS_MSG_SHUTDOWN), "SHUTDOWN");
    EXPECT_STREQ(cs_msg_name(0), "unknown");
    EXPECT_STREQ(cs_msg_name(7), "unknown");
    EXPECT_STREQ(cs_msg_name(0xFFFF), "unknown");
}
}  // namespace
