// The physics server's side of the lockstep protocol, scripted by a test:
// a listening Unix socket in a temp dir, frame send/receive with timeouts
// (never hang a test), and HalSimPeer, a fixture that runs code linked with
// hal-sim (the HAL itself, or firmware/common on it) in a forked child.
// Used by tests/hal-sim and tests/firmware.
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <cstdarg>
#include <cstdio>
#include <map>
#include <optional>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "chainsim_protocol.h"

extern "C" {
#include "hal.h"
}

namespace chainsim_test {

constexpr int kTimeoutMs = 5000;

inline int64_t now_ms()
{
    timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return int64_t(ts.tv_sec) * 1000 + ts.tv_nsec / 1000000;
}

// a temp dir holding the server socket; removed on destruction
class SocketDir {
public:
    SocketDir()
    {
        char tmpl[] = "/tmp/chainsim-test-XXXXXX";
        char *d = mkdtemp(tmpl);
        if (d == nullptr)
            throw std::runtime_error("mkdtemp failed");
        dir_ = d;
        path_ = dir_ + "/server.sock";
    }
    ~SocketDir()
    {
        std::error_code ec;
        std::filesystem::remove_all(dir_, ec);
    }
    const std::string &path() const { return path_; }

private:
    std::string dir_, path_;
};

inline int listen_unix(const std::string &path)
{
    int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0)
        return -1;
    sockaddr_un sa{};
    sa.sun_family = AF_UNIX;
    std::strncpy(sa.sun_path, path.c_str(), sizeof sa.sun_path - 1);
    if (bind(fd, reinterpret_cast<sockaddr *>(&sa), sizeof sa) != 0 || listen(fd, 64) != 0) {
        close(fd);
        return -1;
    }
    return fd;
}

// accept one connection within kTimeoutMs; -1 on timeout
inline int accept_timeout(int lfd, int timeout_ms = kTimeoutMs)
{
    pollfd p{lfd, POLLIN, 0};
    if (poll(&p, 1, timeout_ms) != 1)
        return -1;
    return accept4(lfd, nullptr, nullptr, SOCK_CLOEXEC);
}

// one connection to a module process
class Conn {
public:
    explicit Conn(int fd = -1) : fd_(fd) {}
    ~Conn() { close_fd(); }
    Conn(const Conn &) = delete;
    Conn &operator=(const Conn &) = delete;
    Conn(Conn &&o) noexcept : fd_(o.fd_), buf_(std::move(o.buf_)) { o.fd_ = -1; }
    Conn &operator=(Conn &&o) noexcept
    {
        if (this != &o) {
            close_fd();
            fd_ = o.fd_;
            buf_ = std::move(o.buf_);
            o.fd_ = -1;
        }
        return *this;
    }

    int fd() const { return fd_; }
    void close_fd()
    {
        if (fd_ >= 0)
            close(fd_);
        fd_ = -1;
    }

    bool send(const cs_msg &m)
    {
        uint8_t out[4 + CS_BODY_MAX];
        const char *reason = nullptr;
        size_t n = cs_encode(&m, out, sizeof out, &reason);
        if (n == 0) {
            ADD_FAILURE() << "cs_encode: " << (reason ? reason : "?");
            return false;
        }
        return send_raw(out, n);
    }

    bool send_raw(const uint8_t *p, size_t n)
    {
        size_t off = 0;
        while (off < n) {
            ssize_t w = ::send(fd_, p + off, n - off, MSG_NOSIGNAL);
            if (w < 0 && errno == EINTR)
                continue;
            if (w <= 0)
                return false;
            off += size_t(w);
        }
        return true;
    }

    // true when something (data or EOF) is readable within timeout_ms
    bool readable(int timeout_ms)
    {
        if (!buf_.empty())
            return true;
        pollfd p{fd_, POLLIN, 0};
        return poll(&p, 1, timeout_ms) == 1;
    }

    // receive and decode one frame; false (with a gtest failure unless EOF is
    // expected) on timeout, EOF or a decode error
    bool recv(cs_msg &m, int timeout_ms = kTimeoutMs, bool eof_ok = false)
    {
        if (!fill(4, timeout_ms)) {
            if (!eof_ok)
                ADD_FAILURE() << "no frame from module (timeout or EOF)";
            return false;
        }
        uint32_t len = 0;
        const char *reason = nullptr;
        if (cs_body_length(buf_.data(), &len, &reason) != CS_OK) {
            ADD_FAILURE() << "bad length prefix: " << reason;
            return false;
        }
        if (!fill(4 + len, timeout_ms)) {
            ADD_FAILURE() << "truncated frame";
            return false;
        }
        if (cs_decode(buf_.data() + 4, len, &m, &reason) != CS_OK) {
            ADD_FAILURE() << "cs_decode: " << reason;
            return false;
        }
        buf_.erase(buf_.begin(), buf_.begin() + 4 + len);
        return true;
    }

    // expect a frame of type t
    bool expect(cs_msg &m, uint16_t t, int timeout_ms = kTimeoutMs)
    {
        if (!recv(m, timeout_ms))
            return false;
        if (m.type != t) {
            ADD_FAILURE() << "expected " << cs_msg_name(t) << ", got " << cs_msg_name(m.type);
            return false;
        }
        return true;
    }

private:
    bool fill(size_t need, int timeout_ms)
    {
        int64_t deadline = now_ms() + timeout_ms;
        while (buf_.size() < need) {
            int left = int(deadline - now_ms());
            if (left < 0)
                return false;
            pollfd p{fd_, POLLIN, 0};
            int r = poll(&p, 1, left);
            if (r < 0 && errno == EINTR)
                continue;
            if (r != 1)
                return false;
            uint8_t tmp[4096];
            ssize_t n = read(fd_, tmp, sizeof tmp);
            if (n < 0 && errno == EINTR)
                continue;
            if (n <= 0)
                return false;
            buf_.insert(buf_.end(), tmp, tmp + n);
        }
        return true;
    }

    int fd_;
    std::vector<uint8_t> buf_;
};

// wait for pid to exit within timeout_ms; returns the waitpid status or -1
// (after killing it) on timeout
inline int wait_child(pid_t pid, int timeout_ms = kTimeoutMs)
{
    int64_t deadline = now_ms() + timeout_ms;
    for (;;) {
        int st = 0;
        pid_t r = waitpid(pid, &st, WNOHANG);
        if (r == pid)
            return st;
        if (r < 0)
            return -1;
        if (now_ms() > deadline) {
            kill(pid, SIGKILL);
            waitpid(pid, &st, 0);
            return -1;
        }
        usleep(2000);
    }
}

inline int exit_code(int status)
{
    return (status >= 0 && WIFEXITED(status)) ? WEXITSTATUS(status) : -1;
}

// message builders
inline cs_msg make_welcome(uint16_t index, uint32_t tick_us = 1000,
                           const std::vector<std::pair<std::string, int32_t>> &params = {},
                           uint64_t seed = 42)
{
    cs_msg m{};
    m.type = CS_MSG_WELCOME;
    m.u.welcome.version = CS_VERSION;
    m.u.welcome.module_index = index;
    m.u.welcome.tick_us = tick_us;
    m.u.welcome.seed = seed;
    for (const auto &p : params) {
        cs_param &q = m.u.welcome.params[m.u.welcome.n_params++];
        std::strncpy(q.name, p.first.c_str(), CS_PARAM_NAME_MAX - 1);
        q.value = p.second;
    }
    return m;
}

inline cs_msg make_tick(uint64_t time_us, uint8_t wake_reason = CS_WAKE_TIMER, uint8_t sin = 0,
                        uint8_t n_servos = 2)
{
    cs_msg m{};
    m.type = CS_MSG_TICK_BEGIN;
    m.u.tick_begin.time_us = time_us;
    m.u.tick_begin.wake_reason = wake_reason;
    m.u.tick_begin.sin_level = sin;
    m.u.tick_begin.n_servos = n_servos;
    return m;
}

inline void add_frame(cs_msg &tb, uint8_t addr, std::vector<uint8_t> data)
{
    cs_i2c_frame &f = tb.u.tick_begin.i2c[tb.u.tick_begin.n_i2c++];
    f.addr = addr;
    f.len = uint8_t(data.size());
    std::memcpy(f.data, data.data(), data.size());
}

inline cs_msg make_reason(uint16_t type, const char *reason)
{
    cs_msg m{};
    m.type = type;
    std::strncpy(m.u.reject.reason, reason, CS_REASON_MAX - 1);
    return m;
}

inline std::vector<std::string> logs_of(const cs_msg &te)
{
    std::vector<std::string> v;
    for (unsigned i = 0; i < te.u.tick_end.n_log; i++)
        v.emplace_back(te.u.tick_end.log[i]);
    return v;
}


// A test is the server; the code under test runs in a child forked by
// spawn(), which reports what it saw through hal_log lines (checked in its
// TICK_END) and its exit status.
class HalSimPeer : public ::testing::Test {
protected:
    void SetUp() override
    {
        lfd_ = listen_unix(dir_.path());
        ASSERT_GE(lfd_, 0) << "cannot listen on " << dir_.path();
    }

    void TearDown() override
    {
        conn_.close_fd();
        if (pid_ > 0 && !reaped_) {
            kill(pid_, SIGKILL);
            waitpid(pid_, nullptr, 0);
        }
        if (err_fd_ >= 0)
            close(err_fd_);
        if (lfd_ >= 0)
            close(lfd_);
    }

    using Env = std::map<std::string, std::optional<std::string>>;

    // run body in a forked child (stderr captured); the HAL ends the child
    // (exit 0/2/3); if body returns, the child exits 99
    void spawn(const std::function<void()> &body, uint16_t index = 0,
               const std::string &type = "rotation", const Env &env = {})
    {
        int pfd[2];
        ASSERT_EQ(pipe(pfd), 0);
        fflush(stdout);
        fflush(stderr);
        pid_ = fork();
        ASSERT_GE(pid_, 0);
        if (pid_ == 0) {
            dup2(pfd[1], 2);
            close(pfd[0]);
            close(pfd[1]);
            setenv("CHAINSIM_SOCKET", dir_.path().c_str(), 1);
            setenv("CHAINSIM_MODULE_INDEX", std::to_string(index).c_str(), 1);
            setenv("CHAINSIM_MODULE_TYPE", type.c_str(), 1);
            for (const auto &e : env) {
                if (e.second)
                    setenv(e.first.c_str(), e.second->c_str(), 1);
                else
                    unsetenv(e.first.c_str());
            }
            body();
            _exit(99);
        }
        close(pfd[1]);
        err_fd_ = pfd[0];
    }

    // accept the child's connection, check HELLO, send WELCOME and the first TICK_BEGIN
    void handshake(const cs_msg &welcome, const cs_msg &first_tick)
    {
        accept_conn();
        cs_msg m{};
        ASSERT_TRUE(conn_.expect(m, CS_MSG_HELLO));
        ASSERT_TRUE(conn_.send(welcome));
        ASSERT_TRUE(conn_.send(first_tick));
    }
    void handshake(uint32_t tick_us = 1000) { handshake(make_welcome(0, tick_us), make_tick(0)); }

    void accept_conn()
    {
        int fd = accept_timeout(lfd_);
        ASSERT_GE(fd, 0) << "the child did not connect";
        conn_ = Conn(fd);
    }

    // receive the next TICK_END into te
    void tick_end(cs_msg &te) { ASSERT_TRUE(conn_.expect(te, CS_MSG_TICK_END)); }

    int child_exit()
    {
        int st = wait_child(pid_);
        reaped_ = true;
        return exit_code(st);
    }

    int shutdown_and_wait()
    {
        EXPECT_TRUE(conn_.send(make_reason(CS_MSG_SHUTDOWN, "done")));
        return child_exit();
    }

    std::string child_stderr()
    {
        std::string s;
        char b[512];
        int fl = fcntl(err_fd_, F_GETFL);
        fcntl(err_fd_, F_SETFL, fl | O_NONBLOCK);
        ssize_t n;
        while ((n = read(err_fd_, b, sizeof b)) > 0)
            s.append(b, size_t(n));
        return s;
    }

    SocketDir dir_;
    int lfd_ = -1;
    int err_fd_ = -1;
    pid_t pid_ = -1;
    bool reaped_ = false;
    Conn conn_;
};

// log a printf-formatted line from the child
inline void tlog(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
inline void tlog(const char *fmt, ...)
{
    char b[128];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(b, sizeof b, fmt, ap);
    va_end(ap);
    hal_log(b);
}

[[noreturn]] inline void tick_forever()
{
    for (;;)
        hal_tick_wait();
}

} // namespace chainsim_test
