// Specification tests for the chainsim wire protocol (protocol/chainsim_protocol.h).
//
// Frame = u32 body_len LE | body, body = u16 type LE | payload. Payload fields
// go in struct order, little-endian; arrays are count-prefixed and only the
// counted entries travel; strings are u8 length + bytes without NUL.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "chainsim_protocol.h"

namespace {

using Bytes = std::vector<uint8_t>;

// ---------------------------------------------------------------------------
// helpers
// ---------------------------------------------------------------------------

void set_str(char *dst, size_t size, const std::string &s) {
    ASSERT_LT(s.size(), size);
    std::memset(dst, 0, size);
    std::memcpy(dst, s.data(), s.size());
}

// Encodes m, failing the test if the encoder refuses it.
Bytes encode(const cs_msg &m) {
    Bytes buf(4 + CS_BODY_MAX);
    const char *reason = nullptr;
    size_t n = cs_encode(&m, buf.data(), buf.size(), &reason);
    EXPECT_NE(n, 0u) << "encoder refused: " << (reason ? reason : "(no reason)");
    buf.resize(n);
    return buf;
}

Bytes body_of(const Bytes &frame) { return Bytes(frame.begin() + 4, frame.end()); }

Bytes prefix_of(size_t body_len) {
    return Bytes{uint8_t(body_len), uint8_t(body_len >> 8), uint8_t(body_len >> 16),
                 uint8_t(body_len >> 24)};
}

struct Decoded {
    bool ok = false;
    cs_msg msg{};
    std::string reason;
};

// Decodes from an exactly-sized heap copy, so that AddressSanitizer catches
// any read past the end of the body.
Decoded decode(const Bytes &body) {
    Decoded d;
    std::unique_ptr<uint8_t[]> copy(new uint8_t[body.size()]);
    if (!body.empty()) std::memcpy(copy.get(), body.data(), body.size());
    const char *reason = nullptr;
    d.ok = cs_decode(copy.get(), body.size(), &d.msg, &reason) == CS_OK;
    if (!d.ok) d.reason = reason ? reason : "";
    return d;
}

// The decoder refuses body with a reason that names `field`.
::testing::AssertionResult Rejected(const Bytes &body, std::string_view field) {
    Decoded d = decode(body);
    if (d.ok) return ::testing::AssertionFailure() << "decoder accepted the body";
    if (d.reason.empty()) return ::testing::AssertionFailure() << "empty reason";
    if (d.reason.find(field) == std::string::npos)
        return ::testing::AssertionFailure()
               << "reason \"" << d.reason << "\" does not mention \"" << field << "\"";
    return ::testing::AssertionSuccess();
}

::testing::AssertionResult Accepted(const Bytes &body) {
    Decoded d = decode(body);
    if (!d.ok) return ::testing::AssertionFailure() << "rejected: " << d.reason;
    return ::testing::AssertionSuccess();
}

// The encoder refuses m with a reason that names `field`.
::testing::AssertionResult EncodeRejected(const cs_msg &m, std::string_view field) {
    Bytes buf(4 + CS_BODY_MAX, 0xAA);
    const char *reason = nullptr;
    size_t n = cs_encode(&m, buf.data(), buf.size(), &reason);
    if (n != 0) return ::testing::AssertionFailure() << "encoder wrote " << n << " bytes";
    if (!reason || !*reason) return ::testing::AssertionFailure() << "no reason";
    if (std::string_view(reason).find(field) == std::string_view::npos)
        return ::testing::AssertionFailure()
               << "reason \"" << reason << "\" does not mention \"" << field << "\"";
    return ::testing::AssertionSuccess();
}

// ---------------------------------------------------------------------------
// hand-written wire bodies (field by field, independent of the encoder)
// ---------------------------------------------------------------------------

struct Wire {
    Bytes b;
    Wire &u8(unsigned v) { b.push_back(uint8_t(v)); return *this; }
    Wire &u16(unsigned v) { u8(v & 0xFF); return u8((v >> 8) & 0xFF); }
    Wire &u32(uint32_t v) { u16(v & 0xFFFF); return u16(v >> 16); }
    Wire &u64(uint64_t v) { u32(uint32_t(v)); return u32(uint32_t(v >> 32)); }
    Wire &i32(int32_t v) { return u32(uint32_t(v)); }
    Wire &str(const std::string &s) {
        u8(unsigned(s.size()));
        b.insert(b.end(), s.begin(), s.end());
        return *this;
    }
};

struct I2cWire {
    unsigned addr;
    Bytes data;  // len on the wire = data.size()
};

void put_i2c(Wire &w, const std::vector<I2cWire> &frames) {
    w.u8(unsigned(frames.size()));
    for (const auto &f : frames) {
        w.u8(f.addr).u8(unsigned(f.data.size()));
        w.b.insert(w.b.end(), f.data.begin(), f.data.end());
    }
}

struct HelloWire {
    uint32_t magic = CS_MAGIC;
    unsigned version = CS_VERSION;
    unsigned module_index = 3;
    uint32_t pid = 4242;
    std::string type = "arm";
    Bytes body() const {
        Wire w;
        w.u16(CS_MSG_HELLO).u32(magic).u16(version).u16(module_index).u32(pid).str(type);
        return w.b;
    }
};

struct WelcomeWire {
    unsigned version = CS_VERSION;
    unsigned module_index = 3;
    uint32_t tick_us = 1000;
    uint64_t seed = 7;
    std::vector<std::pair<std::string, int32_t>> params{{"gain", -5}};
    Bytes body() const {
        Wire w;
        w.u16(CS_MSG_WELCOME).u16(version).u16(module_index).u32(tick_us).u64(seed);
        w.u8(unsigned(params.size()));
        for (const auto &p : params) w.str(p.first).i32(p.second);
        return w.b;
    }
};

struct ReasonWire {
    unsigned type = CS_MSG_REJECT;
    std::string reason = "no such module";
    Bytes body() const {
        Wire w;
        w.u16(type).str(reason);
        return w.b;
    }
};

struct TickBeginWire {
    uint64_t time_us = 20000;
    unsigned wake_reason = CS_WAKE_TIMER;
    unsigned sin_level = 1;
    unsigned digital_in = 0x0003;
    std::vector<int32_t> servo_pos{90000, -45000};
    std::vector<unsigned> adc{0, 512, 1023};
    std::vector<int32_t> counter{-1};
    std::vector<I2cWire> i2c{{0x10, {1, 2, 3}}};
    Bytes body() const {
        Wire w;
        w.u16(CS_MSG_TICK_BEGIN).u64(time_us).u8(wake_reason).u8(sin_level).u16(digital_in);
        w.u8(unsigned(servo_pos.size()));
        for (auto v : servo_pos) w.i32(v);
        w.u8(unsigned(adc.size()));
        for (auto v : adc) w.u16(v);
        w.u8(unsigned(counter.size()));
        for (auto v : counter) w.i32(v);
        put_i2c(w, i2c);
        return w.b;
    }
};

struct TickEndWire {
    uint64_t wake_time_us = 21000;
    unsigned wake_events = CS_WAKE_I2C | CS_WAKE_SIN_EDGE;
    unsigned sout_level = 0;
    unsigned i2c_address = 0x11;
    unsigned servo_enable = 0x3;
    std::vector<int32_t> servo_setpoint{1000, -2000};  // n_servos = size()
    std::vector<I2cWire> i2c{{0x00, {0xAB}}};
    std::vector<std::string> log{"booted", ""};
    Bytes body() const {
        Wire w;
        w.u16(CS_MSG_TICK_END).u64(wake_time_us).u8(wake_events).u8(sout_level).u8(i2c_address);
        w.u8(unsigned(servo_setpoint.size())).u8(servo_enable);
        for (auto v : servo_setpoint) w.i32(v);
        put_i2c(w, i2c);
        w.u8(unsigned(log.size()));
        for (const auto &s : log) w.str(s);
        return w.b;
    }
};

// ---------------------------------------------------------------------------
// messages with maximal contents
// ---------------------------------------------------------------------------

std::string filled(size_t n, char first) {
    std::string s;
    for (size_t i = 0; i < n; i++) s.push_back(char(first + int(i % 26)));
    return s;
}

cs_i2c_frame max_frame(uint8_t addr, uint8_t seed) {
    cs_i2c_frame f{};
    f.addr = addr;
    f.len = CS_I2C_DATA_MAX;
    for (unsigned j = 0; j < CS_I2C_DATA_MAX; j++) f.data[j] = uint8_t(seed * 31 + j * 7 + 0x80);
    return f;
}

cs_msg max_hello() {
    cs_msg m{};
    m.type = CS_MSG_HELLO;
    m.u.hello.magic = CS_MAGIC;
    m.u.hello.version = CS_VERSION;
    m.u.hello.module_index = 0xFFFF;
    m.u.hello.pid = 0xFFFFFFFFu;
    set_str(m.u.hello.type, CS_TYPE_NAME_MAX, filled(CS_TYPE_NAME_MAX - 1, 'a'));
    return m;
}

cs_msg max_welcome() {
    cs_msg m{};
    m.type = CS_MSG_WELCOME;
    auto &w = m.u.welcome;
    w.version = CS_VERSION;
    w.module_index = 0xFFFF;
    w.tick_us = 0xFFFFFFFFu;
    w.seed = std::numeric_limits<uint64_t>::max();
    w.n_params = CS_PARAMS_MAX;
    for (unsigned i = 0; i < CS_PARAMS_MAX; i++) {
        set_str(w.params[i].name, CS_PARAM_NAME_MAX, filled(CS_PARAM_NAME_MAX - 1, char('A' + i)));
        w.params[i].value = (i % 2) ? std::numeric_limits<int32_t>::min()
                                    : std::numeric_limits<int32_t>::max() - int32_t(i);
    }
    return m;
}

cs_msg max_reason(uint16_t type) {
    cs_msg m{};
    m.type = type;
    cs_reason &r = type == CS_MSG_REJECT ? m.u.reject : m.u.shutdown;
    std::string s = filled(CS_REASON_MAX - 1, 'a');
    s[3] = '\t';  // texts may hold any byte but NUL
    s[4] = char(0xC3);
    s[5] = char(0xA9);
    set_str(r.reason, CS_REASON_MAX, s);
    return m;
}

cs_msg max_tick_begin() {
    cs_msg m{};
    m.type = CS_MSG_TICK_BEGIN;
    auto &t = m.u.tick_begin;
    t.time_us = std::numeric_limits<uint64_t>::max();
    t.wake_reason = CS_WAKE_ALL;
    t.sin_level = 1;
    t.digital_in = 0xFFFF;
    t.n_servos = CS_SERVOS_MAX;
    for (unsigned i = 0; i < CS_SERVOS_MAX; i++)
        t.servo_pos[i] = (i % 2) ? std::numeric_limits<int32_t>::min() : 359999 - int32_t(i);
    t.n_adc = CS_ADC_MAX;
    for (unsigned i = 0; i < CS_ADC_MAX; i++) t.adc[i] = uint16_t(CS_ADC_COUNTS_MAX - i);
    t.n_counters = CS_COUNTERS_MAX;
    for (unsigned i = 0; i < CS_COUNTERS_MAX; i++)
        t.counter[i] = (i % 2) ? std::numeric_limits<int32_t>::max() : -int32_t(i) - 1;
    t.n_i2c = CS_I2C_FRAMES_MAX;
    for (unsigned i = 0; i < CS_I2C_FRAMES_MAX; i++) t.i2c[i] = max_frame(uint8_t(127 - i), uint8_t(i));
    return m;
}

cs_msg max_tick_end() {
    cs_msg m{};
    m.type = CS_MSG_TICK_END;
    auto &t = m.u.tick_end;
    t.wake_time_us = std::numeric_limits<uint64_t>::max();
    t.wake_events = CS_WAKE_I2C | CS_WAKE_SIN_EDGE;
    t.sout_level = 1;
    t.i2c_address = 127;
    t.n_servos = CS_SERVOS_MAX;
    t.servo_enable = uint8_t((1u << CS_SERVOS_MAX) - 1u);
    for (unsigned i = 0; i < CS_SERVOS_MAX; i++)
        t.servo_setpoint[i] = (i % 2) ? std::numeric_limits<int32_t>::max() : -90000 - int32_t(i);
    t.n_i2c = CS_I2C_FRAMES_MAX;
    for (unsigned i = 0; i < CS_I2C_FRAMES_MAX; i++) t.i2c[i] = max_frame(uint8_t(i), uint8_t(i + 9));
    t.n_log = CS_LOG_LINES_MAX;
    for (unsigned i = 0; i < CS_LOG_LINES_MAX; i++)
        set_str(t.log[i], CS_LOG_LINE_MAX, filled(CS_LOG_LINE_MAX - 1, char('a' + i)));
    return m;
}

std::vector<cs_msg> max_messages() {
    return {max_hello(), max_welcome(), max_reason(CS_MSG_REJECT), max_tick_begin(),
            max_tick_end(), max_reason(CS_MSG_SHUTDOWN)};
}

// smallest legal content of every type
std::vector<cs_msg> min_messages() {
    std::vector<cs_msg> v;
    cs_msg m{};
    m.type = CS_MSG_HELLO;
    m.u.hello.magic = CS_MAGIC;
    m.u.hello.version = CS_VERSION;
    set_str(m.u.hello.type, CS_TYPE_NAME_MAX, "x");
    v.push_back(m);
    m = cs_msg{};
    m.type = CS_MSG_WELCOME;
    m.u.welcome.version = CS_VERSION;
    v.push_back(m);
    m = cs_msg{};
    m.type = CS_MSG_REJECT;  // empty reason is legal
    v.push_back(m);
    m = cs_msg{};
    m.type = CS_MSG_TICK_BEGIN;
    v.push_back(m);
    m = cs_msg{};
    m.type = CS_MSG_TICK_END;
    m.u.tick_end.n_log = 1;  // one empty log line
    v.push_back(m);
    m = cs_msg{};
    m.type = CS_MSG_SHUTDOWN;
    v.push_back(m);
    return v;
}

void expect_same_frames(uint8_t na, const cs_i2c_frame *a, uint8_t nb, const cs_i2c_frame *b) {
    ASSERT_EQ(na, nb);
    for (unsigned i = 0; i < na; i++) {
        EXPECT_EQ(a[i].addr, b[i].addr) << "frame " << i;
        ASSERT_EQ(a[i].len, b[i].len) << "frame " << i;
        EXPECT_EQ(0, std::memcmp(a[i].data, b[i].data, a[i].len)) << "frame " << i;
    }
}

// every field that travels on the wire is equal
void expect_same(const cs_msg &a, const cs_msg &b) {
    ASSERT_EQ(a.type, b.type);
    switch (a.type) {
    case CS_MSG_HELLO:
        EXPECT_EQ(a.u.hello.magic, b.u.hello.magic);
        EXPECT_EQ(a.u.hello.version, b.u.hello.version);
        EXPECT_EQ(a.u.hello.module_index, b.u.hello.module_index);
        EXPECT_EQ(a.u.hello.pid, b.u.hello.pid);
        EXPECT_STREQ(a.u.hello.type, b.u.hello.type);
        break;
    case CS_MSG_WELCOME: {
        const auto &x = a.u.welcome, &y = b.u.welcome;
        EXPECT_EQ(x.version, y.version);
        EXPECT_EQ(x.module_index, y.module_index);
        EXPECT_EQ(x.tick_us, y.tick_us);
        EXPECT_EQ(x.seed, y.seed);
        ASSERT_EQ(x.n_params, y.n_params);
        for (unsigned i = 0; i < x.n_params; i++) {
            EXPECT_STREQ(x.params[i].name, y.params[i].name);
            EXPECT_EQ(x.params[i].value, y.params[i].value);
        }
        break;
    }
    case CS_MSG_REJECT:
        EXPECT_STREQ(a.u.reject.reason, b.u.reject.reason);
        break;
    case CS_MSG_SHUTDOWN:
        EXPECT_STREQ(a.u.shutdown.reason, b.u.shutdown.reason);
        break;
    case CS_MSG_TICK_BEGIN: {
        const auto &x = a.u.tick_begin, &y = b.u.tick_begin;
        EXPECT_EQ(x.time_us, y.time_us);
        EXPECT_EQ(x.wake_reason, y.wake_reason);
        EXPECT_EQ(x.sin_level, y.sin_level);
        EXPECT_EQ(x.digital_in, y.digital_in);
        ASSERT_EQ(x.n_servos, y.n_servos);
        for (unsigned i = 0; i < x.n_servos; i++) EXPECT_EQ(x.servo_pos[i], y.servo_pos[i]);
        ASSERT_EQ(x.n_adc, y.n_adc);
        for (unsigned i = 0; i < x.n_adc; i++) EXPECT_EQ(x.adc[i], y.adc[i]);
        ASSERT_EQ(x.n_counters, y.n_counters);
        for (unsigned i = 0; i < x.n_counters; i++) EXPECT_EQ(x.counter[i], y.counter[i]);
        expect_same_frames(x.n_i2c, x.i2c, y.n_i2c, y.i2c);
        break;
    }
    case CS_MSG_TICK_END: {
        const auto &x = a.u.tick_end, &y = b.u.tick_end;
        EXPECT_EQ(x.wake_time_us, y.wake_time_us);
        EXPECT_EQ(x.wake_events, y.wake_events);
        EXPECT_EQ(x.sout_level, y.sout_level);
        EXPECT_EQ(x.i2c_address, y.i2c_address);
        ASSERT_EQ(x.n_servos, y.n_servos);
        EXPECT_EQ(x.servo_enable, y.servo_enable);
        for (unsigned i = 0; i < x.n_servos; i++) EXPECT_EQ(x.servo_setpoint[i], y.servo_setpoint[i]);
        expect_same_frames(x.n_i2c, x.i2c, y.n_i2c, y.i2c);
        ASSERT_EQ(x.n_log, y.n_log);
        for (unsigned i = 0; i < x.n_log; i++) EXPECT_STREQ(x.log[i], y.log[i]);
        break;
    }
    default:
        FAIL() << "unexpected type " << a.type;
    }
}

// encode -> prefix check -> decode -> same fields -> re-encode to same bytes
void expect_round_trip(const cs_msg &m, size_t expected_frame_size) {
    SCOPED_TRACE(cs_msg_name(m.type));
    Bytes frame = encode(m);
    ASSERT_EQ(frame.size(), expected_frame_size);
    uint32_t body_len = 0;
    const char *reason = nullptr;
    ASSERT_EQ(cs_body_length(frame.data(), &body_len, &reason), CS_OK);
    ASSERT_EQ(body_len, frame.size() - 4);
    Decoded d = decode(body_of(frame));
    ASSERT_TRUE(d.ok) << d.reason;
    expect_same(m, d.msg);
    EXPECT_EQ(encode(d.msg), frame);
}

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
        0x01, 0x00,              // version 1
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
constexpr size_t kHelloMax = 4 + 30;
constexpr size_t kWelcomeMax = 4 + 339;
constexpr size_t kReasonMax = 4 + 98;
constexpr size_t kTickBeginMax = 4 + 338;
constexpr size_t kTickEndMax = 4 + 689;
static_assert(kTickEndMax - 4 <= CS_BODY_MAX, "largest message must fit");

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
    // REJECT, TICK_BEGIN with all counts 0, TICK_END with one empty log line,
    // empty SHUTDOWN
    const size_t sizes[] = {4 + 16, 4 + 19, 4 + 3, 4 + 18, 4 + 18, 4 + 3};
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
    b.resize(2 + 8 + 1 + 1 + 2);
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
