// Specification tests for the chainsim wire protocol: every malformed case the
// decoder and encoder reject, every truncation, and random mutations.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "chainsim_protocol.h"
#include "protocol_messages.h"

namespace {

using namespace protocol_test;


// ---------------------------------------------------------------------------
// decoder rejections (one broken field at a time, everything else valid)
// ---------------------------------------------------------------------------

TEST(DecodeRejects, UnknownType) {
    for (unsigned type : {0u, 7u, 0x0100u, 0xFFFFu}) {
        Bytes body = ReasonWire{}.body();
        body[0] = uint8_t(type);
        body[1] = uint8_t(type >> 8);
        EXPECT_TRUE(Rejected(body, "type")) << type;
    }
}

TEST(DecodeRejects, BodyShorterThanTypeOrOverBodyMax) {
    EXPECT_TRUE(Rejected({}, "truncated"));
    EXPECT_TRUE(Rejected({0x01}, "truncated"));
    Bytes big = ReasonWire{}.body();
    big.resize(CS_BODY_MAX + 1, 'x');
    EXPECT_TRUE(Rejected(big, "CS_BODY_MAX"));
}

TEST(DecodeRejects, TruncatedBody) {
    Bytes b = TickEndWire{}.body();
    b.pop_back();
    EXPECT_TRUE(Rejected(b, "truncated"));
    b = HelloWire{}.body();
    b.resize(2 + 4);  // type and magic only
    EXPECT_TRUE(Rejected(b, "truncated"));
}

TEST(DecodeRejects, TrailingBytesAfterEveryType) {
    for (Bytes b : {HelloWire{}.body(), WelcomeWire{}.body(), ReasonWire{}.body(),
                    ReasonWire{CS_MSG_SHUTDOWN, "x"}.body(), TickBeginWire{}.body(),
                    TickEndWire{}.body()}) {
        b.push_back(0);
        EXPECT_TRUE(Rejected(b, "trailing"));
    }
}

TEST(DecodeRejects, CountsOverTheirLimits) {
    TickBeginWire tb;
    tb.servo_pos.assign(CS_SERVOS_MAX + 1, 0);
    EXPECT_TRUE(Rejected(tb.body(), "n_servos"));
    tb = {};
    tb.adc.assign(CS_ADC_MAX + 1, 0);
    EXPECT_TRUE(Rejected(tb.body(), "n_adc"));
    tb = {};
    tb.counter.assign(CS_COUNTERS_MAX + 1, 0);
    EXPECT_TRUE(Rejected(tb.body(), "n_counters"));
    tb = {};
    tb.i2c.assign(CS_I2C_FRAMES_MAX + 1, I2cWire{0x10, {1}});
    EXPECT_TRUE(Rejected(tb.body(), "n_i2c"));

    TickEndWire te;
    te.servo_setpoint.assign(CS_SERVOS_MAX + 1, 0);
    te.servo_enable = 0;
    EXPECT_TRUE(Rejected(te.body(), "n_servos"));
    te = {};
    te.i2c.assign(CS_I2C_FRAMES_MAX + 1, I2cWire{0x10, {1}});
    EXPECT_TRUE(Rejected(te.body(), "n_i2c"));
    te = {};
    te.log.assign(CS_LOG_LINES_MAX + 1, "x");
    EXPECT_TRUE(Rejected(te.body(), "n_log"));

    WelcomeWire w;
    w.params.assign(CS_PARAMS_MAX + 1, {"p", 1});
    EXPECT_TRUE(Rejected(w.body(), "n_params"));

    // a huge count is refused before it is used, even with no data behind it
    Bytes b = TickBeginWire{}.body();
    b.resize(2 + 8 + 1 + 1 + 2 + 2);  // type, time, wake, sin, digital_in, i2c_tx_queued
    b.push_back(0xFF);
    EXPECT_TRUE(Rejected(b, "n_servos"));
}

TEST(DecodeRejects, I2cFrameWithLenZeroOrOverDataMax) {
    for (bool begin : {true, false}) {
        SCOPED_TRACE(begin ? "TICK_BEGIN" : "TICK_END");
        auto body = [&](I2cWire f) {
            if (begin) {
                TickBeginWire w;
                w.i2c = {{0x10, {1}}, f};
                return w.body();
            }
            TickEndWire w;
            w.i2c = {{0x10, {1}}, f};
            return w.body();
        };
        EXPECT_TRUE(Rejected(body({0x10, {}}), "len"));
        EXPECT_TRUE(Rejected(body({0x10, Bytes(CS_I2C_DATA_MAX + 1, 7)}), "len"));
        EXPECT_TRUE(Rejected(body({128, {1}}), "addr"));
        EXPECT_TRUE(Rejected(body({0xFF, {1}}), "addr"));
        EXPECT_TRUE(Accepted(body({127, Bytes(CS_I2C_DATA_MAX, 7)})));
        EXPECT_TRUE(Accepted(body({0, {1}})));  // general call
    }
}

TEST(DecodeRejects, OwnI2cAddressOver127) {
    TickEndWire te;
    te.i2c_address = 128;
    EXPECT_TRUE(Rejected(te.body(), "i2c_address"));
    te.i2c_address = 127;
    EXPECT_TRUE(Accepted(te.body()));
}

TEST(DecodeRejects, LevelsOtherThanZeroOrOne) {
    for (unsigned level : {2u, 0x80u, 0xFFu}) {
        TickBeginWire tb;
        tb.sin_level = level;
        EXPECT_TRUE(Rejected(tb.body(), "sin_level"));
        TickEndWire te;
        te.sout_level = level;
        EXPECT_TRUE(Rejected(te.body(), "sout_level"));
    }
}

TEST(DecodeRejects, AdcCountsOver1023) {
    for (unsigned v : {CS_ADC_COUNTS_MAX + 1u, 0x8000u, 0xFFFFu}) {
        TickBeginWire tb;
        tb.adc = {0, v};
        EXPECT_TRUE(Rejected(tb.body(), "adc"));
    }
}

TEST(DecodeRejects, HelloWithBadMagicOrVersion) {
    HelloWire h;
    h.magic = 0x4D534844;
    EXPECT_TRUE(Rejected(h.body(), "magic"));
    h.magic = 0x4348534D;  // "CHSM" sent big-endian
    EXPECT_TRUE(Rejected(h.body(), "magic"));
    for (unsigned v : {0u, CS_VERSION + 1u, 0x0100u}) {
        h = {};
        h.version = v;
        EXPECT_TRUE(Rejected(h.body(), "version"));
    }
}

TEST(DecodeRejects, WelcomeWithBadVersion) {
    WelcomeWire w;
    w.version = CS_VERSION + 1;
    EXPECT_TRUE(Rejected(w.body(), "version"));
}

TEST(DecodeRejects, ServoEnableBitsAtOrBeyondNServos) {
    TickEndWire te;
    te.servo_setpoint = {1, 2};
    te.servo_enable = 0x04;
    EXPECT_TRUE(Rejected(te.body(), "servo_enable"));
    te.servo_enable = 0x80;
    EXPECT_TRUE(Rejected(te.body(), "servo_enable"));
    te.servo_setpoint = {};
    te.servo_enable = 0x01;
    EXPECT_TRUE(Rejected(te.body(), "servo_enable"));
    te.servo_setpoint = {1, 2, 3, 4};
    te.servo_enable = 0x0F;
    EXPECT_TRUE(Accepted(te.body()));
}

TEST(DecodeRejects, WakeEventsOutsideI2cAndSinEdge) {
    for (unsigned ev : {unsigned(CS_WAKE_TIMER), 0x08u, 0x07u, 0x80u}) {
        TickEndWire te;
        te.wake_events = ev;
        EXPECT_TRUE(Rejected(te.body(), "wake_events")) << ev;
    }
    for (unsigned ev : {0u, unsigned(CS_WAKE_I2C), unsigned(CS_WAKE_SIN_EDGE)}) {
        TickEndWire te;
        te.wake_events = ev;
        EXPECT_TRUE(Accepted(te.body())) << ev;
    }
}

TEST(DecodeRejects, WakeReasonOutsideWakeAll) {
    for (unsigned why : {0x08u, 0x0Fu, 0xFFu}) {
        TickBeginWire tb;
        tb.wake_reason = why;
        EXPECT_TRUE(Rejected(tb.body(), "wake_reason")) << why;
    }
    TickBeginWire tb;
    tb.wake_reason = 0;  // e.g. the very first tick
    EXPECT_TRUE(Accepted(tb.body()));
}

TEST(DecodeRejects, NamesEmptyTooLongOrWithControlChars) {
    HelloWire h;
    h.type = "";
    EXPECT_TRUE(Rejected(h.body(), "type name"));
    h.type = std::string(CS_TYPE_NAME_MAX, 'a');  // needs CS_TYPE_NAME_MAX + 1 with NUL
    EXPECT_TRUE(Rejected(h.body(), "type name"));
    for (char c : {'\0', '\n', '\x1f', '\x7f'}) {
        h.type = std::string("ab") + c + "c";
        EXPECT_TRUE(Rejected(h.body(), "type name")) << int(c);
    }

    WelcomeWire w;
    w.params = {{"ok", 1}, {"", 2}};
    EXPECT_TRUE(Rejected(w.body(), "param name"));
    w.params = {{std::string(CS_PARAM_NAME_MAX, 'p'), 2}};
    EXPECT_TRUE(Rejected(w.body(), "param name"));
    w.params = {{std::string("a\0b", 3), 2}};
    EXPECT_TRUE(Rejected(w.body(), "param name"));
    w.params = {{"tab\there", 2}};
    EXPECT_TRUE(Rejected(w.body(), "param name"));
}

TEST(DecodeRejects, TextsTooLongOrWithNul) {
    TickEndWire te;
    te.log = {std::string(CS_LOG_LINE_MAX, 'l')};
    EXPECT_TRUE(Rejected(te.body(), "log line"));
    te.log = {std::string("a\0b", 3)};
    EXPECT_TRUE(Rejected(te.body(), "log line"));
    te.log = {std::string(CS_LOG_LINE_MAX - 1, 'l'), "", "\ttabs and \x1b[1mescapes\x1b[0m are text"};
    EXPECT_TRUE(Accepted(te.body()));

    for (unsigned type : {unsigned(CS_MSG_REJECT), unsigned(CS_MSG_SHUTDOWN)}) {
        EXPECT_TRUE(Rejected(ReasonWire{type, std::string(CS_REASON_MAX, 'r')}.body(), "reason"));
        EXPECT_TRUE(Rejected(ReasonWire{type, std::string("a\0b", 3)}.body(), "reason"));
        EXPECT_TRUE(Accepted(ReasonWire{type, ""}.body()));
    }
}

TEST(DecodeRejects, NullArguments) {
    cs_msg m;
    const char *reason = nullptr;
    EXPECT_EQ(cs_decode(nullptr, 4, &m, &reason), CS_ERR);
    EXPECT_NE(reason, nullptr);
    Bytes b = ReasonWire{}.body();
    EXPECT_EQ(cs_decode(b.data(), b.size(), nullptr, nullptr), CS_ERR);
}

// ---------------------------------------------------------------------------
// encoder enforces the same limits
// ---------------------------------------------------------------------------

TEST(EncodeRejects, SameLimitsAsTheDecoder) {
    cs_msg m = max_hello();
    m.u.hello.magic ^= 1;
    EXPECT_TRUE(EncodeRejected(m, "magic"));
    m = max_hello();
    m.u.hello.version = CS_VERSION + 1;
    EXPECT_TRUE(EncodeRejected(m, "version"));
    m = max_hello();
    m.u.hello.type[0] = '\0';
    EXPECT_TRUE(EncodeRejected(m, "type name"));
    m = max_hello();
    m.u.hello.type[1] = '\n';
    EXPECT_TRUE(EncodeRejected(m, "type name"));

    m = max_welcome();
    m.u.welcome.version = 0;
    EXPECT_TRUE(EncodeRejected(m, "version"));
    m = max_welcome();
    m.u.welcome.n_params = CS_PARAMS_MAX + 1;
    EXPECT_TRUE(EncodeRejected(m, "n_params"));
    m = max_welcome();
    m.u.welcome.params[5].name[0] = '\0';
    EXPECT_TRUE(EncodeRejected(m, "param name"));

    m = max_tick_begin();
    m.u.tick_begin.wake_reason = 0x08;
    EXPECT_TRUE(EncodeRejected(m, "wake_reason"));
    m = max_tick_begin();
    m.u.tick_begin.sin_level = 2;
    EXPECT_TRUE(EncodeRejected(m, "sin_level"));
    m = max_tick_begin();
    m.u.tick_begin.n_servos = CS_SERVOS_MAX + 1;
    EXPECT_TRUE(EncodeRejected(m, "n_servos"));
    m = max_tick_begin();
    m.u.tick_begin.n_adc = CS_ADC_MAX + 1;
    EXPECT_TRUE(EncodeRejected(m, "n_adc"));
    m = max_tick_begin();
    m.u.tick_begin.adc[CS_ADC_MAX - 1] = CS_ADC_COUNTS_MAX + 1;
    EXPECT_TRUE(EncodeRejected(m, "adc"));
    m = max_tick_begin();
    m.u.tick_begin.n_counters = CS_COUNTERS_MAX + 1;
    EXPECT_TRUE(EncodeRejected(m, "n_counters"));
    m = max_tick_begin();
    m.u.tick_begin.n_i2c = CS_I2C_FRAMES_MAX + 1;
    EXPECT_TRUE(EncodeRejected(m, "n_i2c"));
    m = max_tick_begin();
    m.u.tick_begin.i2c[7].len = 0;
    EXPECT_TRUE(EncodeRejected(m, "len"));
    m = max_tick_begin();
    m.u.tick_begin.i2c[7].len = CS_I2C_DATA_MAX + 1;
    EXPECT_TRUE(EncodeRejected(m, "len"));
    m = max_tick_begin();
    m.u.tick_begin.i2c[0].addr = 128;
    EXPECT_TRUE(EncodeRejected(m, "addr"));

    m = max_tick_end();
    m.u.tick_end.wake_events = CS_WAKE_TIMER;
    EXPECT_TRUE(EncodeRejected(m, "wake_events"));
    m = max_tick_end();
    m.u.tick_end.sout_level = 3;
    EXPECT_TRUE(EncodeRejected(m, "sout_level"));
    m = max_tick_end();
    m.u.tick_end.i2c_address = 200;
    EXPECT_TRUE(EncodeRejected(m, "i2c_address"));
    m = max_tick_end();
    m.u.tick_end.n_servos = CS_SERVOS_MAX + 1;
    EXPECT_TRUE(EncodeRejected(m, "n_servos"));
    m = max_tick_end();
    m.u.tick_end.n_servos = 2;  // servo_enable still has bits 2 and 3 set
    EXPECT_TRUE(EncodeRejected(m, "servo_enable"));
    m = max_tick_end();
    m.u.tick_end.n_i2c = CS_I2C_FRAMES_MAX + 1;
    EXPECT_TRUE(EncodeRejected(m, "n_i2c"));
    m = max_tick_end();
    m.u.tick_end.i2c[3].addr = 0x80;
    EXPECT_TRUE(EncodeRejected(m, "addr"));
    m = max_tick_end();
    m.u.tick_end.n_log = CS_LOG_LINES_MAX + 1;
    EXPECT_TRUE(EncodeRejected(m, "n_log"));
}

TEST(EncodeRejects, StringsWithoutNulInsideTheirBuffer) {
    cs_msg m = max_hello();
    std::memset(m.u.hello.type, 'a', CS_TYPE_NAME_MAX);
    EXPECT_TRUE(EncodeRejected(m, "type name"));
    m = max_welcome();
    std::memset(m.u.welcome.params[2].name, 'a', CS_PARAM_NAME_MAX);
    EXPECT_TRUE(EncodeRejected(m, "param name"));
    m = max_tick_end();
    std::memset(m.u.tick_end.log[3], 'a', CS_LOG_LINE_MAX);
    EXPECT_TRUE(EncodeRejected(m, "log line"));
    m = max_reason(CS_MSG_SHUTDOWN);
    std::memset(m.u.shutdown.reason, 'a', CS_REASON_MAX);
    EXPECT_TRUE(EncodeRejected(m, "reason"));
}

TEST(EncodeRejects, UnknownTypeAndNullArguments) {
    cs_msg m = max_tick_end();
    m.type = 9;
    EXPECT_TRUE(EncodeRejected(m, "type"));
    uint8_t buf[16];
    const char *reason = nullptr;
    EXPECT_EQ(cs_encode(nullptr, buf, sizeof buf, &reason), 0u);
    EXPECT_NE(reason, nullptr);
    m = max_hello();
    EXPECT_EQ(cs_encode(&m, nullptr, 100, nullptr), 0u);
}

TEST(EncodeRejects, BufferOneByteTooSmallButFitsExactly) {
    for (const cs_msg &m : max_messages()) {
        SCOPED_TRACE(cs_msg_name(m.type));
        const size_t need = encode(m).size();
        for (size_t cap : {size_t(0), size_t(3), size_t(4), need - 1}) {
            std::unique_ptr<uint8_t[]> buf(new uint8_t[cap + 1]);  // never written beyond cap
            const char *reason = nullptr;
            EXPECT_EQ(cs_encode(&m, buf.get(), cap, &reason), 0u) << cap;
            ASSERT_NE(reason, nullptr);
            EXPECT_NE(std::string(reason).find("buffer"), std::string::npos) << reason;
        }
        std::unique_ptr<uint8_t[]> buf(new uint8_t[need]);
        EXPECT_EQ(cs_encode(&m, buf.get(), need, nullptr), need);
    }
}

// ---------------------------------------------------------------------------
// robustness
// ---------------------------------------------------------------------------

TEST(Robustness, EveryTruncationOfEveryValidBodyIsRejected) {
    std::vector<cs_msg> msgs = max_messages();
    for (const cs_msg &m : min_messages()) msgs.push_back(m);
    for (const cs_msg &m : msgs) {
        SCOPED_TRACE(cs_msg_name(m.type));
        const Bytes body = body_of(encode(m));
        ASSERT_TRUE(Accepted(body));
        for (size_t len = 0; len < body.size(); len++) {
            Bytes cut(body.begin(), body.begin() + std::ptrdiff_t(len));
            EXPECT_TRUE(Rejected(cut, "truncated")) << "length " << len;
        }
    }
}

// Random mutations of valid bodies: the decoder never crashes, and whatever
// it accepts re-encodes to exactly the same bytes (the encoding is canonical).
TEST(Robustness, RandomMutationsNeverCrashAndAcceptedBodiesReencodeIdentically) {
    std::vector<Bytes> seeds;
    for (const cs_msg &m : max_messages()) seeds.push_back(body_of(encode(m)));
    for (const cs_msg &m : min_messages()) seeds.push_back(body_of(encode(m)));
    for (Bytes b : {HelloWire{}.body(), WelcomeWire{}.body(), TickBeginWire{}.body(),
                    TickEndWire{}.body()})
        seeds.push_back(b);

    std::mt19937 rng(20240611u);
    auto pick = [&](size_t n) { return std::uniform_int_distribution<size_t>(0, n - 1)(rng); };
    const uint8_t interesting[] = {0, 1, 2, 3, 4, 5, 7, 8, 9, 15, 16, 17, 31, 32, 33,
                                   95, 96, 127, 128, 0xFE, 0xFF};
    int accepted = 0, rejected = 0;
    for (int iter = 0; iter < 5000; iter++) {
        Bytes b = seeds[pick(seeds.size())];
        const size_t n_mut = 1 + pick(3);
        for (size_t k = 0; k < n_mut; k++) {
            switch (pick(6)) {
            case 0:
                if (!b.empty()) b[pick(b.size())] ^= uint8_t(1u << pick(8));
                break;
            case 1:
                if (!b.empty()) b[pick(b.size())] = uint8_t(rng());
                break;
            case 2:
                if (!b.empty()) b[pick(b.size())] = interesting[pick(sizeof interesting)];
                break;
            case 3:
                b.insert(b.begin() + std::ptrdiff_t(pick(b.size() + 1)), uint8_t(rng()));
                break;
            case 4:
                if (!b.empty()) b.erase(b.begin() + std::ptrdiff_t(pick(b.size())));
                break;
            case 5:
                b.resize(pick(b.size() + 1));
                break;
            }
        }
        Bytes frame = prefix_of(b.size());
        frame.insert(frame.end(), b.begin(), b.end());
        uint32_t body_len = 0;
        const bool prefix_ok = cs_body_length(frame.data(), &body_len, nullptr) == CS_OK;
        EXPECT_EQ(prefix_ok, b.size() >= 2 && b.size() <= CS_BODY_MAX);

        Decoded d = decode(b);
        if (!d.ok) {
            rejected++;
            EXPECT_FALSE(d.reason.empty());
            continue;
        }
        accepted++;
        EXPECT_TRUE(prefix_ok);
        ASSERT_EQ(encode(d.msg), frame) << "iteration " << iter;
    }
    // both outcomes are exercised
    EXPECT_GT(accepted, 100);
    EXPECT_GT(rejected, 100);
}

}  // namespace
