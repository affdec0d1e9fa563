#include "view_command.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>
#include <vector>

#include "lockstep_server.h"
#include "viewer_page.h"

extern char** environ;

namespace chainsim {

namespace fs = std::filesystem;

namespace {

constexpr int kExitFailed = kExitInternal;
constexpr int kChromiumTimeoutS = 90;

bool write_file(const fs::path& p, const std::string& text) {
  std::ofstream f(p, std::ios::binary | std::ios::trunc);
  f << text;
  return static_cast<bool>(f.flush());
}

std::string tail_of(const fs::path& p, size_t n) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  const std::string t = s.str();
  return t.size() > n ? "..." + t.substr(t.size() - n) : t;
}

// run argv with stdout and stderr to log; returns the exit status, or -1 on
// a timeout (the process group is killed) or when it cannot start
int run_logged(const std::vector<std::string>& argv, const fs::path& log, int timeout_s) {
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&fa, 1, 2);
  posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
  posix_spawnattr_t at;
  posix_spawnattr_init(&at);
  posix_spawnattr_setflags(&at, POSIX_SPAWN_SETPGROUP);
  posix_spawnattr_setpgroup(&at, 0);
  std::vector<char*> args;
  for (const auto& s : argv) args.push_back(const_cast<char*>(s.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, args[0], &fa, &at, args.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  posix_spawnattr_destroy(&at);
  if (rc != 0) return -1;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(timeout_s);
  int status = 0;
  for (;;) {
    const pid_t w = waitpid(pid, &status, WNOHANG);
    if (w == pid) break;
    if (std::chrono::steady_clock::now() > deadline) {
      kill(-pid, SIGKILL);
      waitpid(pid, &status, 0);
      return -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  kill(-pid, SIGKILL);  // helpers Chromium may have left in its group
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

int render_png(const ViewArgs& a, const std::string& page) {
  const std::string chromium = find_chromium();
  if (chromium.empty()) {
    std::fprintf(stderr,
                 "chainsim: view --png needs Chromium, which is not installed: install the Debian package "
                 "'chromium' (apt-get install chromium; tools/setup.sh does), or set CHAINSIM_CHROMIUM\n");
    return kExitBadInput;
  }
  int w = 0, h = 0;
  if (std::sscanf(a.size.c_str(), "%dx%d", &w, &h) != 2 || w < 16 || h < 16 || w > 8192 || h > 8192) {
    std::fprintf(stderr, "chainsim: --size %s: expected WIDTHxHEIGHT, e.g. 960x540\n", a.size.c_str());
    return kExitBadInput;
  }
  char tmpl[] = "/tmp/chainsim-view-XXXXXX";
  if (!mkdtemp(tmpl)) {
    std::perror("chainsim: mkdtemp");
    return kExitFailed;
  }
  const fs::path tmp = tmpl;
  const fs::path html = tmp / "page.html", shot = tmp / "shot.png", log = tmp / "chromium.log";
  if (!write_file(html, page)) {
    std::fprintf(stderr, "chainsim: cannot write %s\n", html.c_str());
    return kExitFailed;
  }
  char t[64];
  std::snprintf(t, sizeof t, "%.6g", a.png_time);
  const std::string url = "file://" + html.string() + "#t=" + t + "&hideui" + (a.hash.empty() ? "" : "&" + a.hash);
  const std::vector<std::string> argv = {
      chromium, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
      "--disable-background-networking", "--disable-component-update", "--disable-sync",
      "--disable-default-apps", "--hide-scrollbars", "--mute-audio",
      "--user-data-dir=" + (tmp / "profile").string(),
      // without these two the screenshot may be taken before the WebGL canvas is composited
      "--run-all-compositor-stages-before-draw", "--virtual-time-budget=5000",
      "--window-size=" + std::to_string(w) + "," + std::to_string(h),
      "--screenshot=" + shot.string(), url};
  const int rc = run_logged(argv, log, kChromiumTimeoutS);
  int result = kExitOk;
  std::error_code ec;
  if (rc != 0 || !fs::exists(shot) || fs::file_size(shot, ec) == 0) {
    std::fprintf(stderr, "chainsim: Chromium did not render %s (%s); its output:\n%s\n", url.c_str(),
                 rc == -1 ? "it did not start or timed out" : ("exit status " + std::to_string(rc)).c_str(),
                 tail_of(log, 2000).c_str());
    result = kExitFailed;
  } else {
    fs::copy_file(shot, a.out, fs::copy_options::overwrite_existing, ec);
    if (ec) {
      std::fprintf(stderr, "chainsim: cannot write %s: %s\n", a.out.c_str(), ec.message().c_str());
      result = kExitFailed;
    }
  }
  fs::remove_all(tmp, ec);
  return result;
}

}  // namespace

std::string find_chromium() {
  if (const char* c = std::getenv("CHAINSIM_CHROMIUM"); c && *c) return access(c, X_OK) == 0 ? c : "";
  for (const char* c : {"/usr/bin/chromium", "/usr/bin/chromium-browser"})
    if (access(c, X_OK) == 0) return c;
  return "";
}

int cmd_view(const ViewArgs& a) {
  std::string page;
  try {
    std::vector<std::string> warnings;
    const nlohmann::json boot = replay_boot(a.run_dir, &warnings);
    for (const std::string& w : warnings) std::fprintf(stderr, "chainsim: warning: %s\n", w.c_str());
    page = viewer_page(boot, "chainsim: " + boot["scene"].value("scene", std::string("run")));
  } catch (const ViewerError& e) {
    std::fprintf(stderr, "chainsim: %s\n", e.what());
    return kExitBadInput;
  }
  if (a.png_time >= 0) {
    if (a.out.empty()) {
      std::fprintf(stderr, "chainsim: view --png needs --out FILE.png\n");
      return kExitBadInput;
    }
    return render_png(a, page);
  }
  const std::string out = a.out.empty() ? (fs::path(a.run_dir) / "replay.html").string() : a.out;
  if (!write_file(out, page)) {
    std::fprintf(stderr, "chainsim: cannot write %s\n", out.c_str());
    return kExitFailed;
  }
  std::fprintf(stderr, "chainsim: wrote %s (%.1f MB); open it in a browser\n", out.c_str(), page.size() / 1e6);
  return kExitOk;
}

}  // namespace chainsim
