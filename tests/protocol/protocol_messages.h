// Messages and helpers shared by the protocol tests: encoding, decoding,
// the largest and smallest message of every type, field-by-field comparison.
#pragma once

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

namespace protocol_test {


using Bytes = std::vector<uint8_t>;

// ---------------------------------------------------------------------------
// helpers
// ---------------------------------------------------------------------------

inline void set_str(char *dst, size_t size, const std::string &s) {
    ASSERT_LT(s.size(), size);
    std::memset(dst, 0, size);
    std::memcpy(dst, s.data(), s.size());
}

// Encodes m, failing the test if the encoder refuses it.
inline Bytes encode(const cs_msg &m) {
    Bytes buf(4 + CS_BODY_MAX);
    const char *reason = nullptr;
    size_t n = cs_encode(&m, buf.data(), buf.size(), &reason);
    EXPECT_NE(n, 0u) << "encoder refused: " << (reason ? reason : "(no reason)");
    buf.resize(n);
    return buf;
}

inline Bytes body_of(const Bytes &frame) { return Bytes(frame.begin() + 4, frame.end()); }

inline Bytes prefix_of(size_t body_len) {
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
inline Decoded decode(const Bytes &body) {
    Decoded d;
    std::unique_ptr<uint8_t[]> copy(new uint8_t[body.size()]);
    if (!body.empty()) std::memcpy(copy.get(), body.data(), body.size());
    const char *reason = nullptr;
    d.ok = cs_decode(copy.get(), body.size(), &d.msg, &reason) == CS_OK;
    if (!d.ok) d.reason = reason ? reason : "";
    return d;
}

// The decoder refuses body with a reason that names `field`.
inline ::testing::AssertionResult Rejected(const Bytes &body, std::string_view field) {
    Decoded d = decode(body);
    if (d.ok) return ::testing::AssertionFailure() << "decoder accepted the body";
    if (d.reason.empty()) return ::testing::AssertionFailure() << "empty reason";
    if (d.reason.find(field) == std::string::npos)
        return ::testing::AssertionFailure()
               << "reason \"" << d.reason << "\" does not mention \"" << field << "\"";
    return ::testing::AssertionSuccess();
}

inline ::testing::AssertionResult Accepted(const Bytes &body) {
    Decoded d = decode(body);
    if (!d.ok) return ::testing::AssertionFailure() << "rejected: " << d.reason;
    return ::testing::AssertionSuccess();
}

// The encoder refuses m with a reason that names `field`.
inline ::testing::AssertionResult EncodeRejected(const cs_msg &m, std::string_view field) {
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

inline void put_i2c(Wire &w, const std::vector<I2cWire> &frames) {
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
    unsigned i2c_tx_queued = 0x0123;
    std::vector<int32_t> servo_pos{90000, -45000};
    std::vector<unsigned> adc{0, 512, 1023};
    std::vector<int32_t> counter{-1};
    std::vector<I2cWire> i2c{{0x10, {1, 2, 3}}};
    Bytes body() const {
        Wire w;
        w.u16(CS_MSG_TICK_BEGIN).u64(time_us).u8(wake_reason).u8(sin_level).u16(digital_in).u16(i2c_tx_queued);
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

inline std::string filled(size_t n, char first) {
    std::string s;
    for (size_t i = 0; i < n; i++) s.push_back(char(first + int(i % 26)));
    return s;
}

inline cs_i2c_frame max_frame(uint8_t addr, uint8_t seed) {
    cs_i2c_frame f{};
    f.addr = addr;
    f.len = CS_I2C_DATA_MAX;
    for (unsigned j = 0; j < CS_I2C_DATA_MAX; j++) f.data[j] = uint8_t(seed * 31 + j * 7 + 0x80);
    return f;
}

inline cs_msg max_hello() {
    cs_msg m{};
    m.type = CS_MSG_HELLO;
    m.u.hello.magic = CS_MAGIC;
    m.u.hello.version = CS_VERSION;
    m.u.hello.module_index = 0xFFFF;
    m.u.hello.pid = 0xFFFFFFFFu;
    set_str(m.u.hello.type, CS_TYPE_NAME_MAX, filled(CS_TYPE_NAME_MAX - 1, 'a'));
    return m;
}

inline cs_msg max_welcome() {
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

inline cs_msg max_reason(uint16_t type) {
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

inline cs_msg max_tick_begin() {
    cs_msg m{};
    m.type = CS_MSG_TICK_BEGIN;
    auto &t = m.u.tick_begin;
    t.time_us = std::numeric_limits<uint64_t>::max();
    t.wake_reason = CS_WAKE_ALL;
    t.sin_level = 1;
    t.digital_in = 0xFFFF;
    t.i2c_tx_queued = 0xFFFF;
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

inline cs_msg max_tick_end() {
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

inline std::vector<cs_msg> max_messages() {
    return {max_hello(), max_welcome(), max_reason(CS_MSG_REJECT), max_tick_begin(),
            max_tick_end(), max_reason(CS_MSG_SHUTDOWN)};
}

// smallest legal content of every type
inline std::vector<cs_msg> min_messages() {
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

inline void expect_same_frames(uint8_t na, const cs_i2c_frame *a, uint8_t nb, const cs_i2c_frame *b) {
    ASSERT_EQ(na, nb);
    for (unsigned i = 0; i < na; i++) {
        EXPECT_EQ(a[i].addr, b[i].addr) << "frame " << i;
        ASSERT_EQ(a[i].len, b[i].len) << "frame " << i;
        EXPECT_EQ(0, std::memcmp(a[i].data, b[i].data, a[i].len)) << "frame " << i;
    }
}

// every field that travels on the wire is equal
inline void expect_same(const cs_msg &a, const cs_msg &b) {
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
        EXPECT_EQ(x.i2c_tx_queued, y.i2c_tx_queued);
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
inline void expect_round_trip(const cs_msg &m, size_t expected_frame_size) {
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

constexpr size_t kHelloMax = 4 + 30;
constexpr size_t kWelcomeMax = 4 + 339;
constexpr size_t kReasonMax = 4 + 98;
constexpr size_t kTickBeginMax = 4 + 340;
constexpr size_t kTickEndMax = 4 + 689;
static_assert(kTickEndMax - 4 <= CS_BODY_MAX, "largest message must fit");

}  // namespace protocol_test
