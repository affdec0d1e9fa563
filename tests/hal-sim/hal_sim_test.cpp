// hal-sim against a scripted peer: the test is the physics server on a real
// Unix socket; the firmware-side HAL calls run in a forked child, which
// reports what it saw through hal_log lines (checked in its TICK_END) and its
// exit status.
#include <cinttypes>
#include <climits>
#include <cstdio>
#include <optional>

#include "hal_sim_peer.h"

extern "C" {
#include "hal.h"
}

using namespace chainsim_test;

// this test program's parameters
extern "C" const hal_param_decl hal_param_table[] = {
    HAL_PARAM("gait", HAL_PARAM_I16, -5, 5, -1, "a parameter the scene gives"),
    HAL_PARAM("nope", HAL_PARAM_I16, -10, 10, -7, "a parameter the scene does not give"),
    HAL_PARAM("clamped", HAL_PARAM_U8, 0, 9, 3, "given out of its range by a server that did not check"),
    HAL_PARAM_END,
};

namespace {

class HalSim : public HalSimPeer {};

} // namespace

TEST_F(HalSim, HandshakeSendsHelloAndWaitsForFirstTick)
{
    spawn(
        [] {
            hal_init();
            tlog("millis=%" PRIu32, hal_millis());
            tlog("servos=%u", hal_servo_count());
            tlog("gait=%" PRId32 " missing=%" PRId32 " clamped=%" PRId32 " given=%u%u%u",
                 hal_param("gait"), hal_param("nope"), hal_param("clamped"), hal_param_given("gait"),
                 hal_param_given("nope"), hal_param_given("clamped"));
            tlog("sin=%u adc1=%u gpio3=%u cnt0=%" PRId32, hal_sync_read_sin(), hal_adc_read(1),
                 hal_gpio_read(3), hal_counter_read(0));
            tick_forever();
        },
        3, "rotation");
    accept_conn();
    cs_msg m{};
    ASSERT_TRUE(conn_.expect(m, CS_MSG_HELLO));
    EXPECT_EQ(m.u.hello.magic, CS_MAGIC);
    EXPECT_EQ(m.u.hello.version, CS_VERSION);
    EXPECT_EQ(m.u.hello.module_index, 3);
    EXPECT_EQ(m.u.hello.pid, uint32_t(pid_));
    EXPECT_STREQ(m.u.hello.type, "rotation");

    ASSERT_TRUE(conn_.send(make_welcome(3, 1000, {{"gait", 2}, {"clamped", 70}, {"omega_mrad_s", 6000}})));
    // hal_init() must not return (and the firmware must not run) before the first tick
    EXPECT_FALSE(conn_.readable(100));

    cs_msg tb = make_tick(5000, 0, 1, 2);
    tb.u.tick_begin.n_adc = 2;
    tb.u.tick_begin.adc[1] = 1023;
    tb.u.tick_begin.digital_in = 1u << 3;
    tb.u.tick_begin.n_counters = 1;
    tb.u.tick_begin.counter[0] = -77;
    ASSERT_TRUE(conn_.send(tb));

    cs_msg te{};
    tick_end(te);
    EXPECT_EQ(te.u.tick_end.wake_time_us, 6000u);
    EXPECT_EQ(te.u.tick_end.wake_events, 0);
    EXPECT_EQ(te.u.tick_end.n_servos, 2);
    EXPECT_EQ(te.u.tick_end.servo_enable, 0) << "no servo is driven before setspangle";
    EXPECT_EQ(te.u.tick_end.sout_level, 0);
    EXPECT_EQ(te.u.tick_end.i2c_address, 0);
    EXPECT_EQ(logs_of(te), (std::vector<std::string>{"millis=5", "servos=2",
                                                      "gait=2 missing=-7 clamped=9 given=101",
                                                      "sin=1 adc1=1023 gpio3=1 cnt0=-77"}));
    EXPECT_EQ(shutdown_and_wait(), 0);
    // omega_mrad_s is not declared: hal-sim says so (the server never sends one)
    EXPECT_EQ(child_stderr(), "chainsim hal: warning: the scene sets parameter \"omega_mrad_s\", which this "
                              "program does not declare\n");
}

TEST_F(HalSim, ParameterNotDeclaredStopsTheProgramNamingIt)
{
    spawn([] {
        hal_init();
        tlog("before");
        (void)hal_param("gaitt");
        tlog("not reached");
        tick_forever();
    });
    handshake();
    EXPECT_EQ(child_exit(), 2);
    EXPECT_NE(child_stderr().find("hal_param(\"gaitt\"): the program's hal_param_table does not declare it"),
              std::string::npos)
        << child_stderr();
}

TEST_F(HalSim, OutputsAreBatchedIntoTheNextTickEnd)
{
    spawn([] {
        hal_init();
        tlog("rc=%d %d %d %d %d", setspangle(0, 1234), setspangle(1, -18000), setspangle(2, 0),
             setspangle(0, 18001), setspangle(1, -18001));
        hal_sync_write_sout(1);
        tlog("addr rc=%d %d", hal_i2c_set_address(0x21), hal_i2c_set_address(128));
        usleep(150 * 1000); // nothing may reach the server before the wait
        hal_tick_wait();
        tlog("angle=%d %d %d", hal_servo_angle_cdeg(0), hal_servo_angle_cdeg(1),
             hal_servo_angle_cdeg(2));
        tlog("release rc=%d %d", hal_servo_release(1), hal_servo_release(2));
        hal_tick_wait();
        hal_sync_write_sout(0);
        setspangle(1, 5);
        tick_forever();
    });
    handshake();
    EXPECT_FALSE(conn_.readable(80)) << "HAL sent something before a wait";

    cs_msg te{};
    tick_end(te);
    EXPECT_EQ(te.u.tick_end.wake_time_us, 1000u);
    EXPECT_EQ(te.u.tick_end.n_servos, 2);
    EXPECT_EQ(te.u.tick_end.servo_enable, 0x3);
    EXPECT_EQ(te.u.tick_end.servo_setpoint[0], 12340); // millidegrees
    EXPECT_EQ(te.u.tick_end.servo_setpoint[1], -180000);
    EXPECT_EQ(te.u.tick_end.sout_level, 1);
    EXPECT_EQ(te.u.tick_end.i2c_address, 0x21);
    EXPECT_EQ(logs_of(te), (std::vector<std::string>{"rc=0 0 -1 -1 -1", "addr rc=0 -1"}));

    cs_msg tb = make_tick(1000);
    tb.u.tick_begin.servo_pos[0] = 12345; // measured, millidegrees
    tb.u.tick_begin.servo_pos[1] = -12345;
    ASSERT_TRUE(conn_.send(tb));
    tick_end(te);
    EXPECT_EQ(te.u.tick_end.wake_time_us, 2000u);
    EXPECT_EQ(te.u.tick_end.servo_enable, 0x1);
    EXPECT_EQ(te.u.tick_end.servo_setpoint[0], 12340) << "set-points persist";
    EXPECT_EQ(logs_of(te), (std::vector<std::string>{"angle=1235 -1235 0", "release rc=0 -1"}));

    ASSERT_TRUE(conn_.send(make_tick(2000)));
    tick_end(te);
    EXPECT_EQ(te.u.tick_end.servo_enable, 0x3);
    EXPECT_EQ(te.u.tick_end.servo_setpoint[1], 50);
    EXPECT_EQ(te.u.tick_end.sout_level, 0);
    EXPECT_EQ(te.u.tick_end.n_log, 0);
    EXPECT_EQ(shutdown_and_wait(), 0);
}

TEST_F(HalSim, DelayAndTickWaitSetWakeTime)
{
    spawn([] {
        hal_init();
        hal_delay_ms(25);
        tlog("t=%" PRIu32, hal_millis());
        hal_delay_ms(0); // one tick
        hal_tick_wait();
        hal_delay_ms(60000);
        tick_forever();
    });
    handshake(500); // tick_us = 500
    cs_msg te{};
    tick_end(te);
    EXPECT_EQ(te.u.tick_end.wake_time_us, 25000u);
    EXPECT_EQ(te.u.tick_end.wake_events, 0);
    ASSERT_TRUE(conn_.send(make_tick(25000)));
    tick_end(te);
    EXPECT_EQ(te.u.tick_end.wake_time_us, 25500u);
    EXPECT_EQ(te.u.tick_end.wake_events, 0);
    EXPECT_EQ(logs_of(te), std::vector<std::string>{"t=25"});
    ASSERT_TRUE(conn_.send(make_tick(25500)));
    tick_end(te);
    EXPECT_EQ(te.u.tick_end.wake_time_us, 26000u);
    ASSERT_TRUE(conn_.send(make_tick(26000)));
    tick_end(te);
    EXPECT_EQ(te.u.tick_end.wake_time_us, 26000u + 60000000u);
    EXPECT_EQ(te.u.tick_end.wake_events, 0);
    EXPECT_EQ(shutdown_and_wait(), 0);
}

TEST_F(HalSim, WaitEventMaskAndReturnValue)
{
    spawn([] {
        hal_init();
        uint8_t r1 = hal_wait_event_ms(100, HAL_EV_I2C | HAL_EV_SIN_EDGE);
        uint8_t r2 = hal_wait_event_ms(50, HAL_EV_I2C); // frame waiting: immediate
        uint8_t buf[8] = {0}, len = 0, to = 0;
        int rc = hal_i2c_receive(buf, sizeof buf, &len, &to);
        tlog("r1=%u r2=%u rc=%d len=%u to=%u d=%u,%u,%u", r1, r2, rc, len, to, buf[0], buf[1],
             buf[2]);
        uint8_t r3 = hal_wait_event_ms(50, HAL_EV_I2C);   // timeout
        uint8_t r4 = hal_wait_event_ms(10, HAL_EV_SIN_EDGE); // Sin edge
        uint8_t r5 = hal_wait_event_ms(10, HAL_EV_SIN_EDGE); // woken by I2C: not in mask
        uint8_t r6 = hal_wait_event_ms(10, HAL_EV_I2C);   // the frame from r5's tick: immediate
        tlog("r3=%u r4=%u r5=%u r6=%u t=%" PRIu32, r3, r4, r5, r6, hal_millis());
        tick_forever();
    });
    handshake();
    cs_msg te{};
    tick_end(te);
    EXPECT_EQ(te.u.tick_end.wake_time_us, 100000u);
    EXPECT_EQ(te.u.tick_end.wake_events, CS_WAKE_I2C | CS_WAKE_SIN_EDGE);

    cs_msg tb = make_tick(40000, CS_WAKE_I2C);
    add_frame(tb, 0x21, {7, 8, 9});
    ASSERT_TRUE(conn_.send(tb));
    tick_end(te); // r3's wait: r2 did not exchange
    EXPECT_EQ(te.u.tick_end.wake_time_us, 90000u);
    EXPECT_EQ(te.u.tick_end.wake_events, CS_WAKE_I2C);
    EXPECT_EQ(logs_of(te), std::vector<std::string>{"r1=2 r2=2 rc=0 len=3 to=33 d=7,8,9"});

    ASSERT_TRUE(conn_.send(make_tick(90000, CS_WAKE_TIMER)));
    tick_end(te); // r4
    EXPECT_EQ(te.u.tick_end.wake_time_us, 100000u);
    EXPECT_EQ(te.u.tick_end.wake_events, CS_WAKE_SIN_EDGE);
    ASSERT_TRUE(conn_.send(make_tick(95000, CS_WAKE_SIN_EDGE, 1)));
    tick_end(te); // r5
    EXPECT_EQ(te.u.tick_end.wake_time_us, 105000u);
    tb = make_tick(97000, CS_WAKE_I2C, 1);
    add_frame(tb, 0, {1});
    ASSERT_TRUE(conn_.send(tb));
    tick_end(te); // the tick after r6
    EXPECT_EQ(te.u.tick_end.wake_time_us, 98000u);
    EXPECT_EQ(logs_of(te), std::vector<std::string>{"r3=0 r4=4 r5=0 r6=2 t=97"});
    EXPECT_EQ(shutdown_and_wait(), 0);
}

TEST_F(HalSim, I2cSendQueueAndFull)
{
    spawn([] {
        hal_init();
        std::string rc;
        for (uint8_t i = 0; i < 9; i++) {
            uint8_t d[2] = {i, uint8_t(i + 1)};
            rc += std::to_string(hal_i2c_send(uint8_t(0x20 + i), d, 2)) + " ";
        }
        uint8_t big[33] = {0};
        tlog("%sbad=%d %d %d %d", rc.c_str(), hal_i2c_send(0x20, big, 0),
             hal_i2c_send(0x20, big, 33), hal_i2c_send(128, big, 1),
             hal_i2c_send(0x20, nullptr, 1));
        hal_tick_wait();
        tlog("after=%d", hal_i2c_send(0, big, 32)); // the queue was emptied by the wait
        tick_forever();
    });
    handshake();
    cs_msg te{};
    tick_end(te);
    ASSERT_EQ(te.u.tick_end.n_i2c, CS_I2C_FRAMES_MAX);
    for (unsigned i = 0; i < CS_I2C_FRAMES_MAX; i++) {
        EXPECT_EQ(te.u.tick_end.i2c[i].addr, 0x20 + i);
        EXPECT_EQ(te.u.tick_end.i2c[i].len, 2);
        EXPECT_EQ(te.u.tick_end.i2c[i].data[0], i);
        EXPECT_EQ(te.u.tick_end.i2c[i].data[1], i + 1);
    }
    EXPECT_EQ(logs_of(te), std::vector<std::string>{"0 0 0 0 0 0 0 0 -2 bad=-1 -1 -1 -1"});
    ASSERT_TRUE(conn_.send(make_tick(1000)));
    tick_end(te); // the queue was emptied by the first wait
    ASSERT_EQ(te.u.tick_end.n_i2c, 1);
    EXPECT_EQ(te.u.tick_end.i2c[0].addr, 0);
    EXPECT_EQ(te.u.tick_end.i2c[0].len, 32);
    EXPECT_EQ(logs_of(te), std::vector<std::string>{"after=0"});
    ASSERT_TRUE(conn_.send(make_tick(2000)));
    tick_end(te);
    EXPECT_EQ(te.u.tick_end.n_i2c, 0) << "frames are sent once";
    EXPECT_EQ(shutdown_and_wait(), 0);
}

// the send queue counts what the server says is still on the bus: 400
// bytes there leave room for 3 frames of 33 bytes (address and 32 data)
TEST_F(HalSim, I2cSendIsRefusedWhileTheBusStillCarriesTheModulesOwnFrames)
{
    spawn([] {
        hal_init();
        hal_tick_wait(); /* the tick that says 400 bytes are waiting */
        uint8_t big[32] = {0};
        std::string rc;
        for (int i = 0; i < 4; i++) rc += std::to_string(hal_i2c_send(0x20, big, 32)) + " ";
        tlog("%s", rc.c_str());
        tick_forever();
    });
    handshake();
    cs_msg te{};
    tick_end(te);
    cs_msg tb = make_tick(1000);
    tb.u.tick_begin.i2c_tx_queued = 400;
    ASSERT_TRUE(conn_.send(tb));
    tick_end(te);
    EXPECT_EQ(te.u.tick_end.n_i2c, 3);
    EXPECT_EQ(logs_of(te), std::vector<std::string>{"0 0 0 -2 "});
    EXPECT_EQ(shutdown_and_wait(), 0);
}

TEST_F(HalSim, I2cReceiveRingKeepsOrderAndDropsOldest)
{
    spawn([] {
        hal_init(); // the first tick brought frames 0..7
        hal_tick_wait(); // 8..15: ring full (16)
        hal_tick_wait(); // 16..23: 0..7 dropped
        uint8_t buf[4], len = 0, to = 0;
        int n = 0, first = -1, last = -1, ordered = 1, prev = -1, tos_ok = 1;
        while (hal_i2c_receive(buf, 2, &len, &to) == HAL_OK) {
            if (len != 2)
                ordered = 0;
            if (to != ((buf[0] & 1) ? 0x21 : 0))
                tos_ok = 0;
            if (first < 0)
                first = buf[0];
            if (prev >= 0 && buf[0] != prev + 1)
                ordered = 0;
            prev = last = buf[0];
            n++;
        }
        tlog("n=%d first=%d last=%d ordered=%d to_ok=%d empty=%d", n, first, last, ordered,
             tos_ok, hal_i2c_receive(buf, 2, &len, &to));
        tick_forever();
    });
    int next = 0;
    auto tick_with_frames = [&](uint64_t t) {
        cs_msg tb = make_tick(t, CS_WAKE_TIMER | CS_WAKE_I2C);
        for (int i = 0; i < 8; i++, next++)
            add_frame(tb, (next & 1) ? 0x21 : 0, {uint8_t(next), 0xAA, 0xBB});
        return tb;
    };
    handshake(make_welcome(0), tick_with_frames(0));
    cs_msg te{};
    tick_end(te);
    ASSERT_TRUE(conn_.send(tick_with_frames(1000)));
    tick_end(te);
    EXPECT_EQ(te.u.tick_end.n_log, 0);
    ASSERT_TRUE(conn_.send(tick_with_frames(2000)));
    ASSERT_TRUE(conn_.send(make_tick(3000)));
    tick_end(te);
    EXPECT_EQ(logs_of(te), (std::vector<std::string>{
                               "n=16 first=8 last=23 ordered=1 to_ok=1 empty=1",
                               "i2c: 8 received frames dropped (ring full)"}));
    EXPECT_EQ(shutdown_and_wait(), 0);
}

TEST_F(HalSim, ExtraLogLinesAreDroppedWithOneNotice)
{
    spawn([] {
        hal_init();
        for (int i = 1; i <= 6; i++)
            tlog("line %d", i);
        hal_tick_wait();
        for (int i = 1; i <= 4; i++)
            tlog("ok %d", i);
        hal_tick_wait();
        std::string longline(200, 'x');
        hal_log(longline.c_str());
        hal_log_int("v=", INT32_MIN);
        hal_log_int("", 0);
        hal_log_int("neg ", -5);
        hal_tick_wait();
        // a prefix too long for the line is cut so that the whole number fits
        hal_log_int(std::string(200, 'p').c_str(), INT32_MIN);
        hal_log_int(std::string(HAL_LOG_LINE_MAX - HAL_LOG_INT_CHARS_MAX, 'q').c_str(), 7);
        hal_tick_wait();
        tick_forever();
    });
    handshake();
    cs_msg te{};
    tick_end(te);
    EXPECT_EQ(logs_of(te), (std::vector<std::string>{"line 1", "line 2", "line 3",
                                                      "log: 3 lines dropped"}));
    ASSERT_TRUE(conn_.send(make_tick(1000)));
    tick_end(te);
    EXPECT_EQ(logs_of(te), (std::vector<std::string>{"ok 1", "ok 2", "ok 3", "ok 4"}));
    ASSERT_TRUE(conn_.send(make_tick(2000)));
    tick_end(te);
    EXPECT_EQ(logs_of(te), (std::vector<std::string>{std::string(CS_LOG_LINE_MAX - 1, 'x'),
                                                      "v=-2147483648", "0", "neg -5"}));
    ASSERT_TRUE(conn_.send(make_tick(3000)));
    tick_end(te);
    EXPECT_EQ(logs_of(te),
              (std::vector<std::string>{std::string(84, 'p') + "-2147483648",
                                        std::string(84, 'q') + "7"}));
    EXPECT_EQ(logs_of(te)[0].size(), size_t(HAL_LOG_LINE_MAX));
    EXPECT_EQ(shutdown_and_wait(), 0);
}

TEST_F(HalSim, RejectExitsWith2AndPrintsReason)
{
    spawn([] { hal_init(); }, 1, "warpdrive");
    accept_conn();
    cs_msg m{};
    ASSERT_TRUE(conn_.expect(m, CS_MSG_HELLO));
    EXPECT_STREQ(m.u.hello.type, "warpdrive");
    ASSERT_TRUE(conn_.send(make_reason(CS_MSG_REJECT, "unknown module type warpdrive")));
    EXPECT_EQ(child_exit(), 2);
    EXPECT_NE(child_stderr().find("unknown module type warpdrive"), std::string::npos);
}

TEST_F(HalSim, ShutdownExitsWith0Quietly)
{
    spawn([] {
        hal_init();
        hal_wait_event_ms(1000, HAL_EV_I2C);
        _exit(98); // not reached
    });
    handshake();
    cs_msg te{};
    tick_end(te);
    EXPECT_EQ(shutdown_and_wait(), 0);
    EXPECT_EQ(child_stderr(), "");
}

TEST_F(HalSim, ShutdownDuringHandshakeExitsWith0)
{
    spawn([] { hal_init(); });
    accept_conn();
    cs_msg m{};
    ASSERT_TRUE(conn_.expect(m, CS_MSG_HELLO));
    ASSERT_TRUE(conn_.send(make_welcome(0)));
    EXPECT_EQ(shutdown_and_wait(), 0);
}

TEST_F(HalSim, ServerEofExitsWith3)
{
    spawn([] {
        hal_init();
        tick_forever();
    });
    handshake();
    cs_msg te{};
    tick_end(te);
    conn_.close_fd();
    EXPECT_EQ(child_exit(), 3);
    EXPECT_NE(child_stderr().find("closed the connection"), std::string::npos);
}

TEST_F(HalSim, UndecodableFrameExitsWith3WithReason)
{
    spawn([] {
        hal_init();
        tick_forever();
    });
    handshake();
    cs_msg te{};
    tick_end(te);
    const uint8_t bad[] = {2, 0, 0, 0, 99, 0}; // body of 2 bytes: message type 99
    ASSERT_TRUE(conn_.send_raw(bad, sizeof bad));
    EXPECT_EQ(child_exit(), 3);
    std::string err = child_stderr();
    EXPECT_NE(err.find("undecodable frame"), std::string::npos) << err;
}

TEST_F(HalSim, UnexpectedMessageExitsWith3)
{
    spawn([] {
        hal_init();
        tick_forever();
    });
    handshake();
    cs_msg te{};
    tick_end(te);
    ASSERT_TRUE(conn_.send(make_welcome(0)));
    EXPECT_EQ(child_exit(), 3);
    EXPECT_NE(child_stderr().find("expected TICK_BEGIN"), std::string::npos);
}

TEST_F(HalSim, MissingOrBadEnvironmentExitsWith2NamingTheVariable)
{
    struct Case {
        std::string var;
        std::optional<std::string> value;
    };
    const Case cases[] = {
        {"CHAINSIM_SOCKET", std::nullopt},
        {"CHAINSIM_MODULE_INDEX", std::nullopt},
        {"CHAINSIM_MODULE_INDEX", std::string("abc")},
        {"CHAINSIM_MODULE_INDEX", std::string("70000")},
        {"CHAINSIM_MODULE_TYPE", std::string("")},
        {"CHAINSIM_MODULE_TYPE", std::string("a-type-name-too-long")},
    };
    for (const Case &c : cases) {
        spawn([] { hal_init(); }, 0, "rotation", {{c.var, c.value}});
        EXPECT_EQ(child_exit(), 2) << c.var;
        EXPECT_NE(child_stderr().find(c.var), std::string::npos) << c.var;
        close(err_fd_);
        err_fd_ = -1;
        reaped_ = false;
    }
    reaped_ = true;
}

TEST_F(HalSim, ConnectRetriesUntilTheSocketExists)
{
    close(lfd_);
    unlink(dir_.path().c_str());
    spawn([] {
        hal_init();
        tick_forever();
    });
    usleep(200 * 1000);
    lfd_ = listen_unix(dir_.path());
    ASSERT_GE(lfd_, 0);
    handshake();
    cs_msg te{};
    tick_end(te);
    EXPECT_EQ(shutdown_and_wait(), 0);
}

TEST_F(HalSim, SocketIsCloseOnExec)
{
    spawn([] {
        hal_init();
        int cloexec = 0;
        for (int fd = 3; fd < 64; fd++) {
            int fl = fcntl(fd, F_GETFD);
            struct sockaddr_un sa;
            socklen_t sl = sizeof sa;
            if (fl >= 0 && getpeername(fd, reinterpret_cast<sockaddr *>(&sa), &sl) == 0 &&
                sa.sun_family == AF_UNIX)
                cloexec += (fl & FD_CLOEXEC) ? 1 : 100;
        }
        tlog("cloexec=%d", cloexec);
        tick_forever();
    });
    handshake();
    cs_msg te{};
    tick_end(te);
    EXPECT_EQ(logs_of(te), std::vector<std::string>{"cloexec=1"});
    EXPECT_EQ(shutdown_and_wait(), 0);
}

// twenty thousand exchanges stay in lockstep: each wake time is the next tick
// (the time it took is printed for information, never asserted)
TEST_F(HalSim, ManyTicksStayInLockstep)
{
    constexpr int kTicks = 20000;
    spawn([] {
        hal_init();
        for (;;) {
            setspangle(0, 100);
            hal_tick_wait();
        }
    });
    handshake();
    cs_msg te{};
    int64_t t0 = now_ms();
    for (int i = 1; i <= kTicks; i++) {
        tick_end(te);
        ASSERT_EQ(te.u.tick_end.wake_time_us, uint64_t(i) * 1000u);
        ASSERT_TRUE(conn_.send(make_tick(uint64_t(i) * 1000u)));
    }
    int64_t dt = now_ms() - t0;
    std::printf("[          ] %d lockstep exchanges in %" PRId64 " ms (%.1f us each)\n", kTicks,
                dt, 1000.0 * double(dt) / kTicks);
    EXPECT_EQ(shutdown_and_wait(), 0);
}
