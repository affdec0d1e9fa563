#include "viewer/headless_chromium.h"

#include <fcntl.h>
#include <openssl/evp.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <thread>

extern char** environ;

namespace chainsim {

volatile sig_atomic_t HeadlessChromium::interrupted = 0;

namespace {

using Clock = std::chrono::steady_clock;

// a descriptor above Chromium's 3 and 4, closed on exec
int high_fd(int fd) {
  const int h = fcntl(fd, F_DUPFD_CLOEXEC, 10);
  close(fd);
  return h;
}

std::vector<unsigned char> base64_decode(const std::string& text) {
  std::vector<unsigned char> out(text.size() / 4 * 3 + 3);
  const int n = EVP_DecodeBlock(out.data(), reinterpret_cast<const unsigned char*>(text.data()),
                                static_cast<int>(text.size()));
  if (n < 0) throw ChromiumError("Chromium's screenshot is not valid base64");
  size_t pad = 0;  // EVP_DecodeBlock counts the '=' padding as zero bytes
  for (size_t i = text.size(); i > 0 && text[i - 1] == '='; --i) ++pad;
  out.resize(static_cast<size_t>(n) - pad);
  return out;
}

}  // namespace

HeadlessChromium::HeadlessChromium(const std::string& program, const std::filesystem::path& profile_dir,
                                   const std::filesystem::path& log, int width, int height,
                                   Clock::time_point deadline)
    : program_(program), width_(width), height_(height), deadline_(deadline) {
  int sv[2];
  if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0)
    throw ChromiumError(std::string("socketpair: ") + std::strerror(errno));
  const int ours = high_fd(sv[0]), theirs = high_fd(sv[1]);
  const std::vector<std::string> argv = {
      program, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
      "--disable-background-networking", "--disable-component-update", "--disable-sync",
      "--disable-default-apps", "--hide-scrollbars", "--mute-audio", "--remote-debugging-pipe",
      // WebGL in software (SwiftShader): Chromium warns that it will stop
      // falling back to it without this flag
      "--enable-unsafe-swiftshader",
      "--user-data-dir=" + profile_dir.string(),
      "--window-size=" + std::to_string(width) + "," + std::to_string(height), "about:blank"};
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&fa, 1, 2);
  posix_spawn_file_actions_adddup2(&fa, theirs, 3);  // commands in
  posix_spawn_file_actions_adddup2(&fa, theirs, 4);  // replies out
  posix_spawnattr_t at;
  posix_spawnattr_init(&at);
  posix_spawnattr_setflags(&at, POSIX_SPAWN_SETPGROUP);
  posix_spawnattr_setpgroup(&at, 0);
  std::vector<char*> args;
  for (const auto& s : argv) args.push_back(const_cast<char*>(s.c_str()));
  args.push_back(nullptr);
  const int rc = posix_spawn(&pid_, args[0], &fa, &at, args.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  posix_spawnattr_destroy(&at);
  close(theirs);
  if (rc != 0) {
    close(ours);
    pid_ = -1;
    throw ChromiumError("cannot start " + program + ": " + std::strerror(rc));
  }
  to_ = from_ = ours;
}

HeadlessChromium::~HeadlessChromium() {
  if (to_ >= 0) close(to_);  // Chromium ends when its pipe closes
  if (pid_ <= 0) return;
  const auto until = Clock::now() + std::chrono::seconds(5);
  int status = 0;
  while (waitpid(pid_, &status, WNOHANG) == 0) {
    if (Clock::now() > until) {
      kill(-pid_, SIGKILL);
      waitpid(pid_, &status, 0);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  kill(-pid_, SIGKILL);  // helpers Chromium may have left in its group
}

void HeadlessChromium::send(const nlohmann::json& msg) {
  std::string text = msg.dump();
  text.push_back('\0');
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::send(to_, text.data() + done, text.size() - done, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw ChromiumError(ended());
    done += static_cast<size_t>(n);
  }
}

std::string HeadlessChromium::ended() {
  // the pipe closed: Chromium ended, or is ending; say how if it did
  std::string how = "did not say why";
  const auto until = Clock::now() + std::chrono::seconds(1);
  int status = 0;
  while (pid_ > 0 && Clock::now() < until) {
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      kill(-pid_, SIGKILL);  // helpers it may have left in its group
      pid_ = -1;
      how = WIFEXITED(status) ? "exit status " + std::to_string(WEXITSTATUS(status))
                              : std::string("signal ") + strsignal(WTERMSIG(status));
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return program_ + " closed its DevTools pipe (" + how + ")";
}

nlohmann::json HeadlessChromium::receive() {
  size_t scanned = 0;  // bytes of inbox_ known to hold no NUL
  for (;;) {
    if (const size_t end = inbox_.find('\0', scanned); end != std::string::npos) {
      nlohmann::json msg = nlohmann::json::parse(inbox_.begin(), inbox_.begin() + static_cast<long>(end),
                                                 nullptr, false);
      inbox_.erase(0, end + 1);
      if (msg.is_discarded()) throw ChromiumError("Chromium sent a DevTools message that is not JSON");
      return msg;
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline_ - Clock::now()).count();
    if (left <= 0) throw Timeout();
    if (interrupted) throw ChromiumError(std::string("interrupted by ") + strsignal(interrupted));
    pollfd p{from_, POLLIN, 0};
    const int r = poll(&p, 1, static_cast<int>(std::min<long long>(left, 200)));
    if (r < 0 && errno != EINTR) throw ChromiumError(std::string("poll: ") + std::strerror(errno));
    if (r <= 0) continue;
    char buf[65536];
    const ssize_t n = read(from_, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw ChromiumError(ended());
    scanned = inbox_.size();
    inbox_.append(buf, static_cast<size_t>(n));
  }
}

nlohmann::json HeadlessChromium::call(const std::string& method, const nlohmann::json& params, bool in_page) {
  const int id = next_id_++;
  nlohmann::json msg = {{"id", id}, {"method", method}, {"params", params}};
  if (in_page) msg["sessionId"] = session_;
  send(msg);
  for (;;) {
    nlohmann::json reply;
    try {
      reply = receive();
    } catch (const Timeout&) {
      throw ChromiumError(method + ": no answer from Chromium in time");
    }
    // an exception the page did not catch (Runtime.enable is on) ends the wait
    if (reply.value("method", "") == "Runtime.exceptionThrown" && reply.value("sessionId", "") == session_) {
      const nlohmann::json d = reply["params"].value("exceptionDetails", nlohmann::json::object());
      std::string what = d.value("text", "an exception");
      if (d.contains("exception") && d["exception"].is_object())
        what += ": " + d["exception"].value("description", d["exception"].value("value", nlohmann::json()).dump());
      throw ChromiumError("the page threw " + what);
    }
    if (!reply.contains("id") || reply["id"] != id) continue;  // other events, other replies
    if (reply.contains("error"))
      throw ChromiumError(method + ": " + reply["error"].value("message", reply["error"].dump()));
    return reply.value("result", nlohmann::json::object());
  }
}

void HeadlessChromium::open(const std::string& url) {
  std::string target;
  while (target.empty()) {  // the first tab appears shortly after start-up
    const nlohmann::json targets = call("Target.getTargets", nlohmann::json::object(), false);
    for (const auto& t : targets.value("targetInfos", nlohmann::json::array()))
      if (t.value("type", "") == "page") {
        target = t.value("targetId", "");
        break;
      }
    if (target.empty()) {
      if (Clock::now() > deadline_) throw ChromiumError("Chromium opened no page");
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  }
  session_ = call("Target.attachToTarget", {{"targetId", target}, {"flatten", true}}, false).value("sessionId", "");
  call("Runtime.enable", nlohmann::json::object(), true);  // uncaught exceptions are reported
  // the window size is not the page's: set the viewport itself
  call("Emulation.setDeviceMetricsOverride",
       {{"width", width_}, {"height", height_}, {"deviceScaleFactor", 1}, {"mobile", false}}, true);
  const nlohmann::json nav = call("Page.navigate", {{"url", url}}, true);
  if (nav.contains("errorText")) throw ChromiumError("cannot open " + url + ": " + nav["errorText"].dump());
}

nlohmann::json HeadlessChromium::evaluate(const std::string& expression) {
  const nlohmann::json r =
      call("Runtime.evaluate", {{"expression", expression}, {"awaitPromise", true}, {"returnByValue", true}}, true);
  if (r.contains("exceptionDetails")) {
    const auto& d = r["exceptionDetails"];
    std::string what = d.value("text", "exception");
    if (d.contains("exception")) what = d["exception"].value("description", what);
    throw ChromiumError("the page: " + what);
  }
  return r.contains("result") ? r["result"].value("value", nlohmann::json()) : nlohmann::json();
}

std::vector<unsigned char> HeadlessChromium::screenshot_png() {
  const nlohmann::json r = call("Page.captureScreenshot", {{"format", "png"}}, true);
  std::vector<unsigned char> png = base64_decode(r.value("data", ""));
  static const unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (png.size() < 8 || !std::equal(kSignature, kSignature + 8, png.begin()))
    throw ChromiumError("Page.captureScreenshot gave no PNG (" + std::to_string(png.size()) + " bytes)");
  return png;
}

}  // namespace chainsim
