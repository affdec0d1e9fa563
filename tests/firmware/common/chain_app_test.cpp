// chain_app (firmware/common/chain_app.c) on the real simulated HAL: the test
// is the physics server on a real Unix socket (tests/hal_sim_peer.h), the
// module-side code runs in a forked child linked with hal-sim. Discovery's
// answer and address take-over, the frame filter, STATUS, the replies, the
// servo flag and the control-step timer, as the central control and the
// server see them.
#include <cinttypes>
#include <string>
#include <utility>
#include <vector>

#include "hal_sim_peer.h"

extern "C" {
#include "chain_app.h"
#include "chain_commands.h"
}

using namespace chainsim_test;

// this test program's parameters: control_ms as a module program declares it
extern "C" const hal_param_decl hal_param_table[] = {
    CHAIN_APP_PARAM_CONTROL_MS(10),
    HAL_PARAM_END,
};

namespace {

using Frame = std::pair<uint8_t, std::vector<uint8_t>>; // to address, bytes
constexpr uint8_t kGC = HAL_I2C_GENERAL_CALL;
constexpr uint8_t kAddr = 0x21; // the address the tests offer

std::vector<uint8_t> set_gait(uint8_t gait, size_t len = CC_SET_GAIT_LEN)
{
    std::vector<uint8_t> f(len, 0);
    f[0] = CC_SET_GAIT;
    if (len > CC_GAIT_OFF_GAIT)
        f[CC_GAIT_OFF_GAIT] = gait;
    return f;
}

std::vector<uint8_t> frame_bytes(const cs_i2c_frame &f)
{
    return std::vector<uint8_t>(f.data, f.data + f.len);
}

// A module program reduced to chain_app: every frame goes through the
// filter; SET_GAIT is taken as a support module's (gait 8); START runs the
// gait clock; READ_SENSORS makes the next step due. One log line per batch
// of frames: "code/flags" of each frame (the flags cleared after each, so
// that every frame's flag shows alone) and, on a control step, "step t=...".
void filter_program(uint8_t keep_flags)
{
    hal_init();
    chain_app_init(MT_SUPPORT);
    tlog("addr=%u pos=%u type=%u control_ms=%u", ca_addr, ca_pos, ca_type, ca_control_ms);
    for (;;) {
        uint8_t buf[HAL_I2C_DATA_MAX], len, to;
        std::string line;
        while (hal_i2c_receive(buf, sizeof buf, &len, &to) == HAL_OK) {
            uint8_t code = chain_app_filter(buf, len, to);
            if (code == CC_SET_GAIT)
                (void)chain_app_take_gait(buf, GAIT_INCHWORM);
            else if (code == CC_START) {
                ca_running = 1;
                chain_app_clock_start();
            } else if (code == CC_READ_SENSORS)
                chain_app_step_now();
            char b[16];
            std::snprintf(b, sizeof b, "%s%02x/%02x", line.empty() ? "" : " ", code, ca_flags);
            line += b;
            if (!keep_flags)
                ca_flags = 0;
        }
        if (!line.empty())
            hal_log(line.c_str());
        if (chain_app_wait(ca_running) && ca_running)
            tlog("step t=%" PRIu32 " clock=%" PRIu32, hal_millis(), chain_app_clock_ms());
    }
}

class ChainApp : public HalSimPeer {
protected:
    // start body in a child, answer its handshake, raise its Sin (at 1 ms)
    // and offer it kAddr; te is then the TICK_END that carries the
    // ENUM_REPLY (at 2 ms)
    void start_module(const std::function<void()> &body,
                      const std::vector<std::pair<std::string, int32_t>> &params = {})
    {
        spawn(body, 0, "support");
        handshake(make_welcome(0, 1000, params), make_tick(0));
        tick_end(te_);
        // discovery sleeps until an offer or a Sin edge
        ASSERT_EQ(te_.u.tick_end.wake_events, CS_WAKE_I2C | CS_WAKE_SIN_EDGE);
        ASSERT_EQ(te_.u.tick_end.i2c_address, 0);
        ASSERT_EQ(te_.u.tick_end.sout_level, 0);
        ASSERT_NO_FATAL_FAILURE(exchange(1000, {}, 1, CS_WAKE_SIN_EDGE));
        ASSERT_EQ(te_.u.tick_end.i2c_address, 0);
        ASSERT_NO_FATAL_FAILURE(exchange(2000, {{kGC, {CC_ENUM_OFFER, kAddr}}}, 1, CS_WAKE_I2C));
    }

    // one TICK_BEGIN at t_us with frames, and the TICK_END that follows into te_
    void exchange(uint64_t t_us, const std::vector<Frame> &frames, uint8_t sin = 1,
                  uint8_t wake = CS_WAKE_I2C, uint8_t n_servos = 2)
    {
        cs_msg tb = make_tick(t_us, wake, sin, n_servos);
        for (const Frame &f : frames)
            add_frame(tb, f.first, f.second);
        ASSERT_TRUE(conn_.send(tb));
        tick_end(te_);
    }

    std::vector<std::vector<uint8_t>> sent() const
    {
        std::vector<std::vector<uint8_t>> v;
        for (unsigned i = 0; i < te_.u.tick_end.n_i2c; i++) {
            EXPECT_EQ(te_.u.tick_end.i2c[i].addr, CHAIN_CENTRAL_ADDR) << "replies go to 0x10";
            v.push_back(frame_bytes(te_.u.tick_end.i2c[i]));
        }
        return v;
    }

    std::vector<uint8_t> status_reply(uint8_t state, uint8_t gait, uint8_t flags) const
    {
        return {CC_STATUS_REPLY, kAddr, MT_SUPPORT, state, gait, flags};
    }

    cs_msg te_{};
};

} // namespace

TEST_F(ChainApp, DiscoveryTakesTheOfferedAddressOnlyWhileSinIsHigh)
{
    spawn([] { filter_program(0); }, 0, "support");
    handshake(make_welcome(0), make_tick(0));
    tick_end(te_);
    EXPECT_EQ(te_.u.tick_end.wake_time_us, 60000000u) << "discovery sleeps up to 60 s";
    // Sin low: the offer is for a module upstream
    ASSERT_NO_FATAL_FAILURE(exchange(1000, {{kGC, {CC_ENUM_OFFER, 0x20}}}, 0));
    EXPECT_EQ(te_.u.tick_end.i2c_address, 0);
    EXPECT_EQ(te_.u.tick_end.sout_level, 0);
    EXPECT_EQ(te_.u.tick_end.n_i2c, 0);
    // Sin rose with an offer waiting: it may be the upstream module's, which
    // took it and passed the baton meanwhile (a module on the board reads
    // its frames at its own tick): passed over
    ASSERT_NO_FATAL_FAILURE(exchange(1500, {{kGC, {CC_ENUM_OFFER, kAddr}}}, 1, CS_WAKE_I2C | CS_WAKE_SIN_EDGE));
    EXPECT_EQ(te_.u.tick_end.i2c_address, 0);
    EXPECT_EQ(te_.u.tick_end.sout_level, 0);
    // Sin high before they came: offers that are not by general call, out of
    // 0x20..0x3F, of the wrong length, or other frames are passed over; the
    // good one (the central control offers again) taken
    ASSERT_NO_FATAL_FAILURE(exchange(2000,
                                     {{0x25, {CC_ENUM_OFFER, 0x25}},
                                      {kGC, {CC_ENUM_OFFER, 0x40}},
                                      {kGC, {CC_ENUM_OFFER, 0x1F}},
                                      {kGC, {CC_ENUM_OFFER, 0x22, 0}},
                                      {kGC, {CC_STATUS}},
                                      {kGC, {CC_ENUM_OFFER, kAddr}}},
                                     1, CS_WAKE_I2C));
    EXPECT_EQ(te_.u.tick_end.i2c_address, kAddr);
    EXPECT_EQ(te_.u.tick_end.sout_level, 1) << "the baton passes on";
    EXPECT_EQ(sent(), (std::vector<std::vector<uint8_t>>{{CC_ENUM_REPLY, kAddr, MT_SUPPORT}}));
    EXPECT_EQ(logs_of(te_), std::vector<std::string>{"addr=33 pos=1 type=3 control_ms=10"});
    // a later offer (for the next module) changes nothing
    ASSERT_NO_FATAL_FAILURE(exchange(3000, {{kGC, {CC_ENUM_OFFER, 0x22}}}));
    EXPECT_EQ(te_.u.tick_end.i2c_address, kAddr);
    EXPECT_EQ(te_.u.tick_end.n_i2c, 0);
    EXPECT_EQ(logs_of(te_), std::vector<std::string>{"00/00"});
    EXPECT_EQ(shutdown_and_wait(), 0);
}

TEST_F(ChainApp, ControlMsParameterIsKeptWithin1To1000)
{
    const std::pair<std::vector<std::pair<std::string, int32_t>>, int> cases[] = {
        {{}, 10}, // the declared default (the server refuses the others; hal-sim clamps them anyway)
        {{{"control_ms", 25}}, 25},   {{{"control_ms", 1}}, 1},       {{{"control_ms", 0}}, 1},
        {{{"control_ms", -5}}, 1},    {{{"control_ms", 1000}}, 1000}, {{{"control_ms", 1001}}, 1000},
        {{{"control_ms", 70000}}, 1000},
    };
    for (const auto &c : cases) {
        ASSERT_NO_FATAL_FAILURE(start_module([] { filter_program(0); }, c.first));
        EXPECT_EQ(logs_of(te_), std::vector<std::string>{"addr=33 pos=1 type=3 control_ms=" +
                                                         std::to_string(c.second)});
        EXPECT_EQ(shutdown_and_wait(), 0);
        conn_.close_fd();
        close(err_fd_);
        err_fd_ = -1;
        reaped_ = false;
    }
    reaped_ = true;
}

TEST_F(ChainApp, StatusReportsTypeStateGaitAndStickyFlags)
{
    ASSERT_NO_FATAL_FAILURE(start_module([] { filter_program(1); }));
    ASSERT_NO_FATAL_FAILURE(exchange(2000, {{kAddr, {CC_STATUS}}}));
    EXPECT_EQ(sent(), std::vector<std::vector<uint8_t>>{status_reply(CC_STATE_IDLE, 0, 0)});

    // a gait the support can't do: flag 0x01 until a STATUS has read it
    ASSERT_NO_FATAL_FAILURE(
        exchange(3000, {{kAddr, set_gait(GAIT_HELICOIDAL)}, {kAddr, {CC_STATUS}}}));
    EXPECT_EQ(sent(), std::vector<std::vector<uint8_t>>{
                          status_reply(CC_STATE_IDLE, GAIT_HELICOIDAL, CC_FLAG_BAD_GAIT)});
    ASSERT_NO_FATAL_FAILURE(exchange(4000, {{kAddr, {CC_STATUS}}}));
    EXPECT_EQ(sent(), std::vector<std::vector<uint8_t>>{
                          status_reply(CC_STATE_IDLE, GAIT_HELICOIDAL, 0)});

    // its own gait, started: running, no flag
    ASSERT_NO_FATAL_FAILURE(exchange(
        5000, {{kAddr, set_gait(GAIT_INCHWORM)}, {kGC, {CC_START}}, {kAddr, {CC_STATUS}}}));
    EXPECT_EQ(sent(), std::vector<std::vector<uint8_t>>{
                          status_reply(CC_STATE_RUNNING, GAIT_INCHWORM, 0)});

    // an unknown code: flag 0x02, reported once
    ASSERT_NO_FATAL_FAILURE(
        exchange(6000, {{kAddr, {0x77}}, {kAddr, {CC_STATUS}}, {kAddr, {CC_STATUS}}}));
    EXPECT_EQ(sent(), (std::vector<std::vector<uint8_t>>{
                          status_reply(CC_STATE_RUNNING, GAIT_INCHWORM, CC_FLAG_BAD_FRAME),
                          status_reply(CC_STATE_RUNNING, GAIT_INCHWORM, 0)}));
    EXPECT_EQ(shutdown_and_wait(), 0);
}

TEST_F(ChainApp, FilterPassesTheProgramsCommandsAndRefusesTheRest)
{
    ASSERT_NO_FATAL_FAILURE(start_module([] { filter_program(0); }));
    // the program's commands, addressed or (START, STOP) by general call
    ASSERT_NO_FATAL_FAILURE(exchange(2000, {{kAddr, set_gait(GAIT_INCHWORM)},
                                            {kGC, {CC_START}},
                                            {kAddr, {CC_START}},
                                            {kGC, {CC_STOP}},
                                            {kAddr, {CC_STOP}},
                                            {kAddr, {CC_READ_SENSORS}}}));
    EXPECT_EQ(logs_of(te_).at(0), "10/00 11/00 11/00 12/00 12/00 20/00");
    EXPECT_EQ(te_.u.tick_end.n_i2c, 0);

    // not for this module, or discovery traffic: ignored, no flag, no reply
    ASSERT_NO_FATAL_FAILURE(exchange(3000, {{0x22, {CC_STATUS}},
                                            {0x22, set_gait(GAIT_INCHWORM)},
                                            {0x22, {0x77}},
                                            {kGC, {CC_ENUM_OFFER, 0x22}}}));
    EXPECT_EQ(logs_of(te_).at(0), "00/00 00/00 00/00 00/00");
    EXPECT_EQ(te_.u.tick_end.n_i2c, 0);

    // refused with flag 0x02: READ_SENSORS and STATUS by general call, wrong
    // lengths, unknown codes (a reply code sent to a module among them)
    ASSERT_NO_FATAL_FAILURE(exchange(4000, {{kGC, {CC_READ_SENSORS}},
                                            {kGC, {CC_STATUS}},
                                            {kAddr, set_gait(GAIT_INCHWORM, CC_SET_GAIT_LEN - 1)},
                                            {kAddr, set_gait(GAIT_INCHWORM, CC_SET_GAIT_LEN + 1)},
                                            {kGC, {CC_START, 0}},
                                            {kAddr, {CC_READ_SENSORS, 1}},
                                            {kAddr, {CC_STATUS, 0}},
                                            {kAddr, {CC_STATUS_REPLY}}}));
    EXPECT_EQ(logs_of(te_).at(0), "00/02 00/02 00/02 00/02 00/02 00/02 00/02 00/02");
    EXPECT_EQ(te_.u.tick_end.n_i2c, 0) << "a refused STATUS is not answered";
    EXPECT_EQ(shutdown_and_wait(), 0);
}

TEST_F(ChainApp, TakeGaitFlagsOnlyForeignGaits)
{
    ASSERT_NO_FATAL_FAILURE(start_module([] {
        hal_init();
        chain_app_init(MT_SUPPORT);
        std::string line;
        for (uint8_t g : {0, 8, 1, 9, 10, 255}) {
            std::vector<uint8_t> f = set_gait(g);
            ca_flags = 0;
            uint8_t r = chain_app_take_gait(f.data(), GAIT_INCHWORM);
            line += std::to_string(r) + "/" + std::to_string(ca_gait) + "/" +
                    std::to_string(ca_flags) + " ";
        }
        hal_log(line.c_str());
        tick_forever();
    }));
    EXPECT_EQ(logs_of(te_), std::vector<std::string>{"0/0/0 8/8/0 1/1/1 9/9/1 10/10/1 255/255/1 "});
    EXPECT_EQ(shutdown_and_wait(), 0);
}

TEST_F(ChainApp, SensorsReplyCarriesAtMostSixValues)
{
    ASSERT_NO_FATAL_FAILURE(start_module([] {
        hal_init();
        chain_app_init(MT_SUPPORT);
        const int16_t v[8] = {1, -2, 300, -32768, 32767, 5, 6, 7};
        chain_app_sensors(v, 3);
        chain_app_sensors(v, 8);
        chain_app_sensors(v, 0);
        tick_forever();
    }));
    EXPECT_EQ(sent(), (std::vector<std::vector<uint8_t>>{
                          {CC_ENUM_REPLY, kAddr, MT_SUPPORT},
                          {CC_SENSORS, kAddr, 3, 1, 0, 0xFE, 0xFF, 0x2C, 0x01},
                          {CC_SENSORS, kAddr, 6, 1, 0, 0xFE, 0xFF, 0x2C, 0x01, 0x00, 0x80, 0xFF,
                           0x7F, 5, 0},
                          {CC_SENSORS, kAddr, 0},
                      }));
    EXPECT_EQ(shutdown_and_wait(), 0);
}

TEST_F(ChainApp, RefusedSetPointSetsTheServoFlag)
{
    spawn([] {
        hal_init();
        std::string line;
        for (auto sp : std::vector<std::pair<uint8_t, int16_t>>{
                 {0, HAL_SERVO_CDEG_MAX}, {0, -HAL_SERVO_CDEG_MAX}, {1, 100},
                 {0, HAL_SERVO_CDEG_MAX + 1}, {0, -HAL_SERVO_CDEG_MAX - 1}}) {
            ca_flags = 0;
            chain_app_servo(sp.first, sp.second);
            line += std::to_string(ca_flags) + " ";
        }
        hal_log(line.c_str());
        tick_forever();
    });
    // one servo: servo 1 is missing and quietly ignored
    handshake(make_welcome(0), make_tick(0, CS_WAKE_TIMER, 0, 1));
    tick_end(te_);
    EXPECT_EQ(logs_of(te_), std::vector<std::string>{"0 0 0 4 4 "});
    EXPECT_EQ(te_.u.tick_end.servo_enable, 0x1);
    EXPECT_EQ(te_.u.tick_end.servo_setpoint[0], -HAL_SERVO_CDEG_MAX * 10) << "the last accepted";
    EXPECT_EQ(shutdown_and_wait(), 0);
}

// control_ms 20: idle, the module sleeps 60 s on I2C; from START a control
// step every 20 ms of the gait clock; late, it resynchronises; step_now
// makes a step due at once
TEST_F(ChainApp, ControlStepsFollowTheGaitClock)
{
    ASSERT_NO_FATAL_FAILURE(start_module([] { filter_program(0); }, {{"control_ms", 20}}));
    EXPECT_EQ(te_.u.tick_end.wake_time_us, 2000u + 60000000u) << "idle: a long sleep";
    EXPECT_EQ(te_.u.tick_end.wake_events, CS_WAKE_I2C);

    ASSERT_NO_FATAL_FAILURE(exchange(7000, {{kGC, {CC_START}}}));
    EXPECT_EQ(logs_of(te_), (std::vector<std::string>{"11/00", "step t=7 clock=0"}));
    EXPECT_EQ(te_.u.tick_end.wake_time_us, 27000u);
    EXPECT_EQ(te_.u.tick_end.wake_events, CS_WAKE_I2C) << "a frame still wakes it";

    ASSERT_NO_FATAL_FAILURE(exchange(27000, {}, 1, CS_WAKE_TIMER));
    EXPECT_EQ(logs_of(te_), std::vector<std::string>{"step t=27 clock=20"});
    EXPECT_EQ(te_.u.tick_end.wake_time_us, 47000u);

    // woken late (at 100 instead of 47): one step, the next control_ms later
    ASSERT_NO_FATAL_FAILURE(exchange(100000, {}, 1, CS_WAKE_TIMER));
    EXPECT_EQ(logs_of(te_), std::vector<std::string>{"step t=100 clock=93"});
    EXPECT_EQ(te_.u.tick_end.wake_time_us, 120000u);

    // a frame between steps: no step; READ_SENSORS calls step_now: a step at once
    ASSERT_NO_FATAL_FAILURE(exchange(105000, {{kAddr, {0x77}}}));
    EXPECT_EQ(logs_of(te_), std::vector<std::string>{"00/02"});
    EXPECT_EQ(te_.u.tick_end.wake_time_us, 120000u);
    ASSERT_NO_FATAL_FAILURE(exchange(110000, {{kAddr, {CC_READ_SENSORS}}}));
    EXPECT_EQ(logs_of(te_), (std::vector<std::string>{"20/00", "step t=110 clock=103"}));
    EXPECT_EQ(te_.u.tick_end.wake_time_us, 130000u);

    // START again restarts the gait clock
    ASSERT_NO_FATAL_FAILURE(exchange(115000, {{kGC, {CC_START}}}));
    EXPECT_EQ(logs_of(te_), (std::vector<std::string>{"11/00", "step t=115 clock=0"}));
    EXPECT_EQ(te_.u.tick_end.wake_time_us, 135000u);
    EXPECT_EQ(shutdown_and_wait(), 0);
}
