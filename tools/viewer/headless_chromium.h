// Headless Chromium driven over the DevTools protocol on a pipe
// (--remote-debugging-pipe: Chromium reads JSON commands on its fd 3 and
// writes replies and events on its fd 4, each message ended by a NUL byte).
// `chainsim view --png` uses it to wait until the replay page says it is
// posed and drawn, and only then to take the screenshot: no guess of how long
// the page needs, so a loaded machine gets the same picture, only later.
#pragma once

#include <signal.h>
#include <sys/types.h>

#include <chrono>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace chainsim {

struct ChromiumError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class HeadlessChromium {
 public:
  // starts `program` headless with a fresh profile in profile_dir, its output
  // to log; the window (and so the screenshot) is width x height pixels.
  // Every call below gives up at `deadline` with a ChromiumError.
  HeadlessChromium(const std::string& program, const std::filesystem::path& profile_dir,
                   const std::filesystem::path& log, int width, int height,
                   std::chrono::steady_clock::time_point deadline);
  ~HeadlessChromium();  // ends Chromium and everything it started
  HeadlessChromium(const HeadlessChromium&) = delete;
  HeadlessChromium& operator=(const HeadlessChromium&) = delete;

  // opens url in the first page and attaches to it
  void open(const std::string& url);
  // evaluates a JavaScript expression in the page (awaiting it when it is a
  // promise) and returns its value; a thrown exception becomes a ChromiumError
  nlohmann::json evaluate(const std::string& expression);
  // the page's viewport as PNG bytes
  std::vector<unsigned char> screenshot_png();

  // set to the signal's number by a SIGINT/SIGTERM handler: the wait in
  // progress ends with a ChromiumError, so the caller can clean up
  static volatile sig_atomic_t interrupted;

 private:
  nlohmann::json call(const std::string& method, const nlohmann::json& params, bool in_page);
  void send(const nlohmann::json& msg);
  struct Timeout {};
  nlohmann::json receive();  // the next whole message; Timeout at the deadline
  std::string ended();       // why the pipe closed: the program and its exit status

  std::string program_;
  pid_t pid_ = -1;
  int to_ = -1, from_ = -1;  // our ends of Chromium's fd 3 and fd 4
  std::string inbox_;
  std::string session_;
  int next_id_ = 1;
  int width_, height_;
  std::chrono::steady_clock::time_point deadline_;
};

}  // namespace chainsim
